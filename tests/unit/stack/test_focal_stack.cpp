// Focus/aperture stack manifests: parsing, near/far from the thin lens,
// explicit limits, errors naming the key path, duplicates, round trip.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "gdof/camera.h"
#include "gdof/focal_stack.h"
#include "test_support.h"

namespace gdof {
namespace {

const char* kManifest = R"({
  "gdof_stack": 1,
  "coc_px": 1.5,
  "scene_unit_mm": 1000,
  "focal_length_mm": 50, "sensor_width_mm": 36,
  "width": 1920, "height": 1080,
  "references": [
    {"file": "ref.0001.exr", "focus_distance": 2.0, "f_number": 2.8},
    {"file": "sub/ref.0002.exr", "focus_distance": 4.0, "f_number": 8, "near": 3.1, "far": 5.9},
    {"file": "/abs/ref.0003.exr", "focus_distance": 20.0, "f_number": 16, "focal_length_mm": 35},
    {"file": "ref.0004.exr", "focus_distance": 3.0, "f_number": 4, "far": "inf"}
  ]
})";

TEST(focal_stack, near_far_from_the_thin_lens) {
    auto r = parse_stack_manifest(kManifest, "/stacks/shot");
    ASSERT_TRUE(r) << r.message();
    const FocalStack& s = r.value();
    ASSERT_EQ(s.references.size(), 4u);
    EXPECT_EQ(s.width, 1920);
    EXPECT_EQ(s.height, 1080);
    EXPECT_DOUBLE_EQ(s.coc_px, 1.5);

    ThinLens lens;
    lens.focal_length_mm = 50;
    lens.f_number = 2.8;
    lens.focus_distance = 2.0;
    lens.sensor_width_mm = 36;
    lens.image_width_px = 1920;
    const auto lim = lens.dof_limits(1.5);
    EXPECT_DOUBLE_EQ(s.references[0].near, lim.near);
    EXPECT_DOUBLE_EQ(s.references[0].far, lim.far);
    EXPECT_LT(s.references[0].near, 2.0);
    EXPECT_GT(s.references[0].far, 2.0);

    // Explicit limits are kept.
    EXPECT_DOUBLE_EQ(s.references[1].near, 3.1);
    EXPECT_DOUBLE_EQ(s.references[1].far, 5.9);

    // Per-reference focal length overrides the default.
    lens.focal_length_mm = 35;
    lens.f_number = 16;
    lens.focus_distance = 20;
    const auto lim3 = lens.dof_limits(1.5);
    EXPECT_DOUBLE_EQ(s.references[2].near, lim3.near);
    EXPECT_TRUE(std::isinf(s.references[2].far)) << "20 m at f/16 on 35 mm is beyond the hyperfocal distance";

    // One explicit limit, the other from the lens.
    EXPECT_TRUE(std::isinf(s.references[3].far));
    lens.focal_length_mm = 50;
    lens.f_number = 4;
    lens.focus_distance = 3;
    EXPECT_DOUBLE_EQ(s.references[3].near, lens.dof_limits(1.5).near);
}

TEST(focal_stack, paths_resolve_against_the_manifest_folder) {
    auto r = parse_stack_manifest(kManifest, "/stacks/shot");
    ASSERT_TRUE(r) << r.message();
    EXPECT_EQ(r->references[0].file, "ref.0001.exr");
    EXPECT_EQ(r->references[0].path, "/stacks/shot/ref.0001.exr");
    EXPECT_EQ(r->references[1].path, "/stacks/shot/sub/ref.0002.exr");
    EXPECT_EQ(r->references[2].path, "/abs/ref.0003.exr");
}

TEST(focal_stack, round_trip) {
    auto a = parse_stack_manifest(kManifest, "/x");
    ASSERT_TRUE(a) << a.message();
    const std::string text = format_stack_manifest(a.value());
    EXPECT_NE(text.find("\"inf\""), std::string::npos) << text;
    auto b = parse_stack_manifest(text, "/x");
    ASSERT_TRUE(b) << b.message() << "\n" << text;
    ASSERT_EQ(a->references.size(), b->references.size());
    for (std::size_t i = 0; i < a->references.size(); ++i) {
        EXPECT_EQ(a->references[i].file, b->references[i].file);
        EXPECT_EQ(a->references[i].near, b->references[i].near) << i;
        EXPECT_EQ(a->references[i].far, b->references[i].far) << i;
        EXPECT_EQ(a->references[i].f_number, b->references[i].f_number) << i;
    }
    EXPECT_EQ(a->width, b->width);
    EXPECT_EQ(a->coc_px, b->coc_px);
}

TEST(focal_stack, light_field_references_with_explicit_limits) {
    auto r = parse_stack_manifest(R"({"references": [
        {"file": "a.exr", "near": 1, "far": 2, "focus_disparity": 0.5, "aperture_radius_views": 3},
        {"file": "b.exr", "near": 2, "far": 4, "focus_disparity": 0.25, "aperture_radius_views": 3}]})",
                                  "");
    ASSERT_TRUE(r) << r.message();
    EXPECT_DOUBLE_EQ(r->references[1].focus_disparity, 0.25);
    EXPECT_TRUE(std::isnan(r->references[1].f_number));
    // Same disparity and aperture twice: duplicate.
    auto d = parse_stack_manifest(R"({"references": [
        {"file": "a.exr", "near": 1, "far": 2, "focus_disparity": 0.5, "aperture_radius_views": 3},
        {"file": "b.exr", "near": 1, "far": 2, "focus_disparity": 0.5, "aperture_radius_views": 3}]})",
                                  "");
    ASSERT_FALSE(d);
    EXPECT_NE(d.message().find("duplicate"), std::string::npos) << d.message();
}

void expect_error(const std::string& json, const std::string& needle) {
    auto r = parse_stack_manifest(json, "/d");
    ASSERT_FALSE(r) << "expected an error containing '" << needle << "' for " << json;
    EXPECT_NE(r.message().find(needle), std::string::npos) << r.message();
}

TEST(focal_stack, duplicates_name_both_entries) {
    auto r = parse_stack_manifest(R"({"focal_length_mm": 50, "sensor_width_mm": 36, "width": 100, "references": [
        {"file": "a.exr", "focus_distance": 2, "f_number": 2.8},
        {"file": "b.exr", "focus_distance": 3, "f_number": 2.8},
        {"file": "c.exr", "focus_distance": 2.0, "f_number": 2.8}]})",
                                  "/d");
    ASSERT_FALSE(r);
    const std::string& m = r.message();
    EXPECT_NE(m.find("references[2]"), std::string::npos) << m;
    EXPECT_NE(m.find("references[0]"), std::string::npos) << m;
    EXPECT_NE(m.find("'a.exr'"), std::string::npos) << m;
    EXPECT_NE(m.find("'c.exr'"), std::string::npos) << m;
    EXPECT_NE(m.find("duplicate"), std::string::npos) << m;
}

TEST(focal_stack, errors_name_the_key_path) {
    const std::string lens = R"("focal_length_mm": 50, "sensor_width_mm": 36, "width": 100, )";
    expect_error("{" + lens + R"("references": [{"file": "a.exr", "focus_distance": 2, "f_number": -2}]})",
                 "references[0].f_number: must be > 0");
    expect_error("{" + lens + R"("references": [{"file": "a.exr", "focus_distance": 2, "f_number": 2},
                                                 {"focus_distance": 3, "f_number": 2}]})",
                 "references[1].file: missing");
    expect_error("{" + lens + R"("references": [{"file": "a.exr", "focus_distance": 2, "fnumber": 2}]})",
                 "references[0].fnumber: unknown key");
    expect_error("{" + lens + R"("refs": []})", "refs: unknown key");
    expect_error("{" + lens + R"("references": []})", "references: must list at least one");
    expect_error("{" + lens + R"("references": [{"file": "a.exr", "focus_distance": 2, "f_number": 2, "near": 5, "far": 3}]})",
                 "near (5) is beyond far (3)");
    expect_error(R"({"focal_length_mm": 50, "sensor_width_mm": 36,
                     "references": [{"file": "a.exr", "focus_distance": 2, "f_number": 2}]})",
                 "width: missing");
    expect_error(R"({"width": 10, "references": [{"file": "a.exr", "focus_distance": 2, "f_number": 2}]})",
                 "references[0].focal_length_mm: missing");
    expect_error(R"({"width": 10, "references": [{"file": "a.exr", "near": 2}]})",
                 "references[0].focus_distance: missing");
    expect_error(R"({"gdof_stack": 2, "references": []})", "gdof_stack: unsupported manifest version");
    expect_error(R"({"references": [{"file": "a.exr", "near": 1, "far": "infinite"}]})",
                 "references[0].far: must be a number or \"inf\"");
    expect_error("[1, 2]", "top level: must be an object");
    expect_error("{\"references\": [", "stack manifest: malformed JSON at line 1, column 16");
}

}  // namespace
}  // namespace gdof
