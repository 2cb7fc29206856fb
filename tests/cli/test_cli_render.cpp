// gdof --render end to end: outputs, options, errors.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <set>

#include "cli_test_helpers.h"
#include "gdof/io/image_io.h"
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

// A card at depth 3 in front of a plane at depth 6, both facing the camera,
// lit from the camera (so the card's shadow hides behind it): the blur field
// is sharp at depth 6 and 6 px at the card. Against the pinhole render, the
// plane away from the card is unchanged and the card's edges are blurred.
TEST(cli_render, blurfield_blurs_only_where_the_field_says) {
    ScratchDir dir;
    write_text(dir.file("card.obj"), "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nf 1 2 3 4\n");
    write_text(dir.file("scene.json"), R"({
  "camera": {"position": [0, 0, 5], "look_at": [0, 0, 0], "focal_length_mm": 35, "sensor_width_mm": 36,
             "resolution": [64, 48]},
  "materials": {"back": {"kd": 0.3}, "card": {"kd": 0.9}},
  "meshes": [{"file": "card.obj", "scale": [10, 10, 1], "translate": [0, 0, -1], "material": "back"},
             {"file": "card.obj", "scale": [0.6, 0.6, 1], "translate": [0, 0, 2], "material": "card"}],
  "lights": [{"type": "point", "position": [0, 0, 5], "intensity": 40}]
})");
    write_text(dir.file("field.json"),
               R"({"blurfield": {"kind": "focal_planes", "depths": [6], "max_blur": 6, "slope": 2}})");
    const std::string scene = quote(dir.file("scene.json"));
    auto r = run_gdof("--render " + scene + " --pinhole --spp 16 -o " + quote(dir.file("pin.exr")));
    if (built_without_embree(r)) GDOF_SKIP_OR_FAIL(r.output);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    r = run_gdof("--render " + scene + " --blurfield " + quote(dir.file("field.json")) + " --spp 64 -o " +
                 quote(dir.file("blur.exr")));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const Pixels pin = read_image_pixels(dir.file("pin.exr")), blur = read_image_pixels(dir.file("blur.exr"));
    ASSERT_EQ(pin.spec.width, 64);
    ASSERT_EQ(blur.spec.width, 64);
    ASSERT_EQ(blur.spec.height, 48);
    // The card spans x, y in 32 +- 12.4 and 24 +- 12.4 px (62.2 px per unit at depth 1).
    const float back = pin.at(2, 24, 0), card = pin.at(32, 24, 0);  // R
    ASSERT_GT(card, 3 * back) << "the card is lit 4x brighter and is 3x whiter";
    int far_pixels = 0;
    double far_worst = 0, edge_sum = 0;
    int edge_pixels = 0;
    for (int y = 0; y < 48; ++y)
        for (int x = 0; x < 64; ++x) {
            const double dx = std::max(std::abs(x + 0.5 - 32.0) - 12.44, 0.0);
            const double dy = std::max(std::abs(y + 0.5 - 24.0) - 12.44, 0.0);
            const double outside = std::hypot(dx, dy);
            const double d = std::abs(blur.at(x, y, 0) - pin.at(x, y, 0));
            if (outside > 8) {  // the 6 px cones of these pixels miss the card
                far_worst = std::max(far_worst, d / pin.at(x, y, 0));
                ++far_pixels;
            }
            // Within 2 px of the card's left or right edge, away from its corners.
            if (std::abs(std::abs(x + 0.5 - 32.0) - 12.44) < 2 && std::abs(y + 0.5 - 24.0) < 8) {
                edge_sum += d;
                ++edge_pixels;
            }
        }
    std::printf("[ measured ] blurred vs pinhole: in-focus plane worst %.2e relative; card edges mean %.3f of the "
                "card/plane contrast\n", far_worst, edge_sum / edge_pixels / (card - back));
    ASSERT_GT(far_pixels, 300);
    EXPECT_LT(far_worst, 1e-4) << "the in-focus plane equals the pinhole render (measured 2e-7)";
    ASSERT_GT(edge_pixels, 40);
    EXPECT_GT(edge_sum / edge_pixels, 0.15 * (card - back)) << "the card's edges are blurred";
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

// The bundled scene: its size, finite beauty, full alpha (the environment
// is not black), several objects, and a finite depth on every object pixel.
TEST(cli_render, generated_example_scene) {
    const std::string scene = std::string(GDOF_SOURCE_DIR) + "/examples/render/generated.json";
    ScratchDir dir;
    auto r = run_gdof("--render " + quote(scene) + " --pinhole --spp 1 -o " + quote(dir.file("gen.exr")));
    if (built_without_embree(r)) GDOF_SKIP_OR_FAIL(r.output);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    OIIO::ImageSpec spec;
    const auto px = read_pixels(dir.file("gen.exr"), &spec);
    ASSERT_EQ(spec.width, 640);
    ASSERT_EQ(spec.height, 360);
    const int a = spec.channelindex("A"), z = spec.channelindex("Z"), id = spec.channelindex("id");
    ASSERT_GE(a, 0);
    ASSERT_GE(z, 0);
    ASSERT_GE(id, 0);
    auto in = gdof::io::read_flat(dir.file("gen.exr"));
    ASSERT_TRUE(in) << in.message();
    const int idc = in->channel_index("id");
    std::set<std::uint32_t> ids;
    for (std::size_t p = 0; p < std::size_t(640 * 360); ++p) {
        const float* v = &px[p * std::size_t(spec.nchannels)];
        for (int c = 0; c < 3; ++c) ASSERT_TRUE(std::isfinite(v[c]) && v[c] >= 0) << "pixel " << p;
        ASSERT_EQ(v[a], 1.0f) << "pixel " << p;
        const std::uint32_t object = in->uplane(idc)[p];
        ids.insert(object);
        if (object != 0) {
            ASSERT_TRUE(std::isfinite(v[z]) && v[z] > 0) << "pixel " << p;
        }
    }
    EXPECT_GE(ids.size(), 5u) << "ground, wall, boxes, spheres, poles";
}
