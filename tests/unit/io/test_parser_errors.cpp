// Every JSON parser of the library reports an unknown key the same way
// ("<source>: <path>: unknown key (allowed: ...)", InvalidArgument, the key
// as subject), and malformed JSON with its line and column: they all read
// through json_read.
#include <gtest/gtest.h>

#include <fstream>
#include <regex>

#include "gdof/blur_field.h"
#include "gdof/focal_stack.h"
#include "gdof/focus_surfaces.h"
#include "gdof/io/lightfield_io.h"
#include "gdof/io/stack_sources.h"
#include "gdof/render_stack.h"
#include "gdof/scene.h"
#include "test_support.h"

using namespace gdof;

namespace {

struct Case {
    std::string parser;
    Status status;
    std::string prefix;  // "<source>: <path>" before ": unknown key"
    std::string key;
    std::string allowed_sample;  // one of the allowed keys the message lists
};

void expect_unknown_key(const Case& c) {
    SCOPED_TRACE(c.parser);
    ASSERT_FALSE(c.status.is_ok());
    const std::string& m = c.status.message();
    // Exactly "<prefix>: unknown key (allowed: k1, k2, ...)".
    static const std::regex format(R"(^(.*): unknown key \(allowed: ([a-z_0-9]+(, [a-z_0-9]+)*)\)$)");
    std::smatch match;
    ASSERT_TRUE(std::regex_match(m, match, format)) << m;
    EXPECT_EQ(match[1].str(), c.prefix) << m;
    EXPECT_NE((", " + match[2].str() + ",").find(", " + c.allowed_sample + ","), std::string::npos) << m;
    EXPECT_EQ(c.status.code(), StatusCode::InvalidArgument) << m;
    EXPECT_EQ(c.status.subject(), c.key) << m;
}

const std::string kLens = R"("kind": "thin_lens", "focal_length_mm": 50, "f_number": 2, "focus_distance": 2)";

}  // namespace

TEST(parser_errors, EveryParserNamesAnUnknownKeyTheSameWay) {
    test::ScratchDir dir;
    const std::string manifest = dir.file("stack.json");
    std::ofstream(manifest) << R"({"references": [{"file": "a.exr", "near": 1, "far": 2, "fstop": 2}]})";

    const std::vector<Case> cases = {
        {"blur field", BlurField::parse(R"({"blurfield": {)" + kLens + R"(, "focal_length": 50}})").status(),
         "blurfield.focal_length", "focal_length", "focal_length_mm"},
        {"blur field (top)", BlurField::parse(R"({"blurfield": {)" + kLens + R"(}, "maxradius": 3})").status(),
         "maxradius", "maxradius", "max_radius"},
        {"stack manifest", parse_stack_manifest(R"({"refs": []})", "").status(), "stack manifest: refs", "refs",
         "references"},
        {"stack manifest (reference)",
         parse_stack_manifest(R"({"references": [{"file": "a.exr", "fnumber": 2}]})", "").status(),
         "stack manifest: references[0].fnumber", "fnumber", "f_number"},
        {"focus surfaces", parse_focus_surfaces(R"({"near": 1, "far": 2, "farr": 3})").status(), "surfaces: farr",
         "farr", "far"},
        {"focus surfaces (grid)", parse_focus_surfaces(R"({"near": {"points": [[1]]}, "far": 2})").status(),
         "surfaces: near.points", "points", "grid"},
        {"scene", parse_scene(R"({"camera": {"position": [0, 0, 5], "look_at": [0, 0, 0], "zoom": 2}})", "",
                              "scene 'a.json'")
                      .status(),
         "scene 'a.json': camera.zoom", "zoom", "focal_length_mm"},
        {"render stack", parse_render_stack_options(R"({"apertures": [1, 2]})", "'r.json'").status(),
         "'r.json': apertures", "apertures", "f_numbers"},
        {"render stack (reference)",
         parse_render_stack_options(R"({"references": [{"focus_distance": 2, "f_number": 2, "fstop": 1}]})", "'r.json'")
             .status(),
         "'r.json': references[0].fstop", "fstop", "f_number"},
        {"light field", io::parse_lightfield_config(R"({"disparity_at_infinty": 1})", "lf.json").status(),
         "lf.json: disparity_at_infinty", "disparity_at_infinty", "disparity_at_infinity"},
        {"light field (crop)",
         io::parse_lightfield_config(R"({"crop": {"x": 0, "y": 0, "w": 1, "height": 1}})", "lf.json").status(),
         "lf.json: crop.w", "w", "width"},
        {"light-field stack", io::parse_extract_stack_options(R"({"fstops": [1]})", "stack.json").status(),
         "stack.json: fstops", "fstops", "apertures"},
        {"stack from disk", io::load_stack(manifest).status(), "'" + manifest + "': stack manifest: references[0].fstop",
         "fstop", "far"},
    };
    for (const Case& c : cases) expect_unknown_key(c);
}

TEST(parser_errors, EveryParserGivesLineAndColumnForMalformedJson) {
    const std::string bad = "{\n  \"a\": 1,,\n}";  // the second comma: line 2, column 10
    const std::string at = "malformed JSON at line 2, column 10: ";
    const std::vector<std::pair<std::string, Status>> cases = {
        {"blur field", BlurField::parse(bad).status()},
        {"stack manifest", parse_stack_manifest(bad, "").status()},
        {"focus surfaces", parse_focus_surfaces(bad).status()},
        {"scene", parse_scene(bad, "", "scene 'a.json'").status()},
        {"render stack", parse_render_stack_options(bad, "'r.json'").status()},
        {"light field", io::parse_lightfield_config(bad, "lf.json").status()},
        {"light-field stack", io::parse_extract_stack_options(bad, "stack.json").status()},
    };
    for (const auto& [name, st] : cases) {
        SCOPED_TRACE(name);
        ASSERT_FALSE(st.is_ok());
        EXPECT_NE(st.message().find(at), std::string::npos) << st.message();
        EXPECT_EQ(st.code(), StatusCode::InvalidArgument);
    }
}
