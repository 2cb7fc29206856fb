// Blur field JSON errors: each message names the key path (or line/column for
// malformed JSON). Also: every example in examples/blurfields parses.
#include <filesystem>
#include <fstream>
#include <sstream>

#include "gdof/blur_field.h"
#include "test_support.h"

using namespace gdof;

namespace {

std::string error_of(const std::string& text, const BlurField::Context& ctx = {}) {
    auto r = BlurField::parse(text, ctx);
    EXPECT_FALSE(r) << "parsed but should not:\n" << text;
    return r ? std::string() : r.message();
}

#define EXPECT_HAS(msg, part) EXPECT_NE((msg).find(part), std::string::npos) << "message: " << (msg)

const std::string kLens = R"("kind": "thin_lens", "focal_length_mm": 50, "f_number": 2, "focus_distance": 2)";

}  // namespace

TEST(blur_field_parse, MalformedJsonHasLineAndColumn) {
    const std::string m = error_of("{\n  \"blurfield\": {\n    \"kind\": \"thin_lens\",,\n  }\n}");
    EXPECT_HAS(m, "line 3");
    EXPECT_HAS(m, "column");
    EXPECT_HAS(error_of(""), "line 1");
}

TEST(blur_field_parse, UnknownKeysAreNamed) {
    std::string m = error_of(R"({"blurfield": {)" + kLens + R"(, "focal_length": 50}})");
    EXPECT_HAS(m, "blurfield.focal_length: unknown key");
    EXPECT_HAS(m, "focal_length_mm");  // lists the allowed keys
    m = error_of(R"({"blurfield": {)" + kLens + R"(}, "maxradius": 3})");
    EXPECT_HAS(m, "maxradius: unknown key");
    // Keys of another shape are unknown for this one.
    m = error_of(R"({"blurfield": {"kind": "region", "shape": "box", "center": [0,0,0], "size": [1,1,1],
                  "radius": 2, "blur": 1}})");
    EXPECT_HAS(m, "blurfield.radius: unknown key (allowed: kind, comment, shape, mode, blur, falloff, interpolation, min, max, "
                  "center, size, rotation_deg)");
    // The bare node without the wrapper is rejected, naming the key.
    m = error_of("{" + kLens + "}");
    EXPECT_HAS(m, "blurfield: missing required key");
    EXPECT_HAS(m, "bare");
    m = error_of("[1, 2]");
    EXPECT_HAS(m, "top level");
}

TEST(blur_field_parse, BadValuesNameTheKeyPath) {
    const std::string m = error_of(R"({"blurfield": {"kind": "min", "children": [
        {)" + kLens + R"(},
        {"kind": "region", "shape": "sphere", "center": [0, 0, -3], "radius": -2, "blur": 4}]}})");
    EXPECT_EQ(m, "blurfield.children[1].radius: must be >= 0, got -2");
    EXPECT_HAS(error_of(R"({"blurfield": {"kind": "thin_lens", "focal_length_mm": 50, "f_number": 0, "focus_distance": 2}})"),
               "blurfield.f_number: must be > 0, got 0");
    EXPECT_HAS(error_of(R"({"blurfield": {"kind": "thin_lens", "focal_length_mm": 50, "f_number": 2, "focus_distance": 0.03}})"),
               "blurfield.focus_distance: must be beyond the focal length");
    EXPECT_HAS(error_of(R"({"blurfield": {"kind": "focal_planes", "depths": [2, 2], "max_blur": 3}})"),
               "blurfield.depths: depth 2 is listed twice");
    EXPECT_HAS(error_of(R"({"blurfield": {"kind": "focal_planes", "depths": [2, -1], "max_blur": 3}})"),
               "blurfield.depths[1]: must be > 0, got -1");
    EXPECT_HAS(error_of(R"({"blurfield": {"kind": "focal_planes", "depths": [2], "max_blur": 3}})"), "blurfield.slope");
    EXPECT_HAS(error_of(R"({"blurfield": {"kind": "focal_planes", "depths": [2, 4], "max_blur": 3, "interpolation": "cubic"}})"),
               "blurfield.interpolation: must be one of linear, smooth, got \"cubic\"");
    EXPECT_HAS(error_of(R"({"blurfield": {"kind": "region", "shape": "plane", "point": [0,0,0], "normal": [0,0,0], "blur": 1}})"),
               "blurfield.normal: must not be the zero vector");
    EXPECT_HAS(error_of(R"({"blurfield": {"kind": "region", "shape": "box", "min": [0,0,0], "max": [1,1,1],
                          "center": [0,0,0], "blur": 1}})"),
               "either min/max or center/size");
    EXPECT_HAS(error_of(R"({"blurfield": {"kind": "scale", "factor": -1, "child": {)" + kLens + "}}}"),
               "blurfield.factor: must be >= 0, got -1");
    EXPECT_HAS(error_of(R"({"blurfield": {"kind": "clamp", "min": 3, "max": 1, "child": {)" + kLens + "}}}"),
               "blurfield.max: must be >= 3, got 1");
    EXPECT_HAS(error_of(R"({"blurfield": {)" + kLens + R"(}, "max_radius": -1})"), "max_radius: must be >= 0, got -1");
    EXPECT_HAS(error_of(R"({"blurfield": {"kind": "blurry"}})"), "blurfield.kind: unknown kind \"blurry\"");
    EXPECT_HAS(error_of(R"({"blurfield": {"kind": "scale", "factor": 2, "child": {"kind": "add", "children": [{"kind": "region",
        "shape": "cone", "blur": 1}]}}})"),
               "blurfield.child.children[0].shape: must be one of sphere, box, plane");
}

TEST(blur_field_parse, NonFiniteNumbersAreErrors) {
    // JSON has no NaN: strings are wrong types; overflowing literals are errors.
    std::string m = error_of(R"({"blurfield": {"kind": "thin_lens", "focal_length_mm": "nan", "f_number": 2, "focus_distance": 2}})");
    EXPECT_HAS(m, "blurfield.focal_length_mm: must be a number, got string \"nan\"");
    m = error_of(R"({"blurfield": {"kind": "thin_lens", "focal_length_mm": 50, "f_number": 2,
                     "focus_distance": 1e400}})");
    EXPECT_HAS(m, "malformed JSON at line 2, column 40: number overflow parsing '1e400'");
    m = error_of(R"({"blurfield": {"kind": "region", "shape": "sphere", "center": [0, "inf", 0], "radius": 1, "blur": 1}})");
    EXPECT_HAS(m, "blurfield.center[1]: must be a number");
    m = error_of(R"({"blurfield": {"kind": "region", "shape": "sphere", "center": [0, -1e999, 0], "radius": 1, "blur": 1}})");
    EXPECT_HAS(m, "overflow");
}

TEST(blur_field_parse, WrongTypesAndMissingKeys) {
    EXPECT_HAS(error_of(R"({"blurfield": {"kind": "thin_lens", "focal_length_mm": 50, "f_number": 2}})"),
               "blurfield.focus_distance: missing required key");
    EXPECT_HAS(error_of(R"({"blurfield": {"focal_length_mm": 50}})"), "blurfield.kind: missing required key");
    EXPECT_HAS(error_of(R"({"blurfield": {"kind": 3}})"), "blurfield.kind: must be a string, got number");
    EXPECT_HAS(error_of(R"({"blurfield": {"kind": "min", "children": {}}})"),
               "blurfield.children: must be a non-empty array");
    EXPECT_HAS(error_of(R"({"blurfield": {"kind": "min", "children": []}})"),
               "blurfield.children: must be a non-empty array");
    EXPECT_HAS(error_of(R"({"blurfield": {"kind": "min", "children": [3]}})"),
               "blurfield.children[0]: must be an object, got number");
    EXPECT_HAS(error_of(R"({"blurfield": {"kind": "region", "shape": "sphere", "center": [0, 0], "radius": 1, "blur": 1}})"),
               "blurfield.center: must be an array of 3 numbers");
    EXPECT_HAS(error_of(R"({"blurfield": {"kind": "region", "shape": "sphere", "center": [0, 0, 0], "radius": true, "blur": 1}})"),
               "blurfield.radius: must be a number, got boolean");
    EXPECT_HAS(error_of(R"({"blurfield": {"kind": "region", "shape": "sphere", "center": [0, 0, 0], "radius": 1}})"),
               "blurfield.blur: missing required key");
    EXPECT_HAS(error_of(R"({"max_radius": 3})"), "blurfield: missing required key");
    EXPECT_HAS(error_of(R"({"blurfield": {"kind": "scale", "factor": 2}})"), "blurfield.child: missing required key");
}

TEST(blur_field_parse, ImageMapResolution) {
    const std::string text = R"({"blurfield": {"kind": "image_map", "image": "masks/paint.exr", "channel": "A"}})";
    EXPECT_HAS(error_of(text), "blurfield.image: no image named \"masks/paint.exr\"");
    BlurField::Context ctx;
    ctx.base_dir = "/shots/sh010";
    std::string asked;
    auto img = std::make_shared<Image>(Image::with_channels({"R", "A"}, {0, 0, 4, 4}));
    ctx.load_image = [&](const std::string& path) -> Result<std::shared_ptr<const Image>> {
        asked = path;
        return std::shared_ptr<const Image>(img);
    };
    auto ok = BlurField::parse(text, ctx);
    ASSERT_TRUE(ok) << ok.message();
    EXPECT_EQ(asked, "/shots/sh010/masks/paint.exr");
    EXPECT_HAS(error_of(R"({"blurfield": {"kind": "image_map", "image": "a.exr", "channel": "Z"}})", ctx),
               "blurfield.channel: image \"a.exr\" has no channel \"Z\" (channels: R, A)");
    ctx.load_image = [](const std::string&) -> Result<std::shared_ptr<const Image>> {
        return Status::error("file not found");
    };
    EXPECT_HAS(error_of(text, ctx), "blurfield.image: cannot load \"/shots/sh010/masks/paint.exr\": file not found");
}

TEST(blur_field_parse, ExamplesParse) {
    const std::filesystem::path dir = std::filesystem::path(GDOF_SOURCE_DIR) / "examples" / "blurfields";
    ASSERT_TRUE(std::filesystem::exists(dir)) << dir;
    BlurField::Context ctx;
    ctx.load_image = [](const std::string&) -> Result<std::shared_ptr<const Image>> {
        auto img = std::make_shared<Image>(Image::with_channels({"R", "G", "B", "A"}, {0, 0, 8, 8}));
        return std::shared_ptr<const Image>(img);
    };
    int count = 0;
    for (const auto& e : std::filesystem::directory_iterator(dir)) {
        if (e.path().extension() != ".json") continue;
        std::ifstream in(e.path());
        std::stringstream ss;
        ss << in.rdbuf();
        auto r = BlurField::parse(ss.str(), ctx);
        EXPECT_TRUE(r) << e.path() << ": " << r.message();
        ++count;
    }
    EXPECT_GE(count, 4);
}
