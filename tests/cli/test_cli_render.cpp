// gdof --render end to end: outputs, options, errors.
#include "cli_test_helpers.h"
#include "../unit/scene_test_helpers.h"

using namespace gdof::test;

namespace {

bool built_without_embree(const CommandResult& r) { return contains(r.output, "without Embree"); }

}  // namespace

TEST(cli_render, renders_multilayer_exr_with_aovs) {
    ScratchDir dir;
    write_quad_obj(dir);
    write_text(dir.file("scene.json"), plane_scene_json(R"(, "f_number": 2, "focus_distance": 4)", 40, 30));
    const std::string out = dir.file("out.exr");
    auto r = run_gdof("--stats --render " + quote(dir.file("scene.json")) + " --spp 8 --min-spp 2 -o " + quote(out));
    if (built_without_embree(r)) GDOF_SKIP_OR_FAIL(r.output);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_TRUE(contains(r.output, "Mrays/s")) << r.output;
    EXPECT_TRUE(contains(r.output, "segments")) << r.output;
    OIIO::ImageSpec spec;
    auto px = read_pixels(out, &spec);
    EXPECT_EQ(spec.width, 40);
    EXPECT_EQ(spec.height, 30);
    for (const char* ch : {"R", "G", "B", "A", "albedo.R", "Z", "P.x", "P.y", "P.z", "N.x", "id"}) {
        bool found = false;
        for (const auto& n : spec.channelnames) found |= n == ch;
        EXPECT_TRUE(found) << ch;
    }
    EXPECT_TRUE(spec.find_attribute("worldToCamera") != nullptr);
}

TEST(cli_render, pinhole_and_blurfield_forms) {
    ScratchDir dir;
    write_quad_obj(dir);
    write_text(dir.file("scene.json"), plane_scene_json("", 24, 16));
    write_text(dir.file("field.json"),
               R"({"blurfield": {"kind": "thin_lens", "focal_length_mm": 35, "f_number": 2, "focus_distance": 3, "sensor_width_mm": 36}})");
    auto r = run_gdof("--render " + quote(dir.file("scene.json")) + " --pinhole --spp 2 -o " + quote(dir.file("pin.exr")));
    if (built_without_embree(r)) GDOF_SKIP_OR_FAIL(r.output);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    r = run_gdof("--render " + quote(dir.file("scene.json")) + " --blurfield " + quote(dir.file("field.json")) +
                 " --spp 4 -o " + quote(dir.file("field.exr")));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_TRUE(fs::exists(dir.file("field.exr")));
}

TEST(cli_render, missing_mesh_is_named) {
    ScratchDir dir;
    write_text(dir.file("scene.json"),
               R"({"camera": {"position": [0,0,5], "look_at": [0,0,0]}, "meshes": [{"file": "nowhere.obj"}]})");
    auto r = run_gdof("--render " + quote(dir.file("scene.json")) + " -o " + quote(dir.file("out.exr")));
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_TRUE(contains(r.output, "nowhere.obj")) << r.output;
    EXPECT_TRUE(contains(r.output, "meshes[0].file")) << r.output;
    EXPECT_FALSE(fs::exists(dir.file("out.exr")));
}

TEST(cli_render, bad_key_is_named) {
    ScratchDir dir;
    write_quad_obj(dir);
    write_text(dir.file("scene.json"),
               R"({"camera": {"position": [0,0,5], "look_at": [0,0,0], "zoom": 2}, "meshes": [{"file": "quad.obj"}]})");
    auto r = run_gdof("--render " + quote(dir.file("scene.json")) + " -o " + quote(dir.file("out.exr")));
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_TRUE(contains(r.output, "camera.zoom: unknown key")) << r.output;
}

TEST(cli_render, bad_spp_is_a_usage_error) {
    ScratchDir dir;
    write_quad_obj(dir);
    write_text(dir.file("scene.json"), plane_scene_json());
    auto r = run_gdof("--render " + quote(dir.file("scene.json")) + " --spp 0 -o " + quote(dir.file("out.exr")));
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_TRUE(contains(r.output, "--spp")) << r.output;
}

TEST(cli_render, generated_example_scene) {
    const std::string scene = std::string(GDOF_SOURCE_DIR) + "/examples/render/generated.json";
    ScratchDir dir;
    auto r = run_gdof("--render " + quote(scene) + " --pinhole --spp 1 -o " + quote(dir.file("gen.exr")));
    if (built_without_embree(r)) GDOF_SKIP_OR_FAIL(r.output);
    ASSERT_EQ(r.exit_code, 0) << r.output;
}
