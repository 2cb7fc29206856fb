// gdof --aperture with --render and --bokeh end to end: the ray tracer's
// hexagonal bokeh (a far emitter's blur points its corners where
// polygon:6 puts them), the scene key camera.aperture equal to the flag,
// --bokeh on a plate + depth equal to the library's defocus() with the same
// aperture, and the errors.
#include <cmath>
#include <numbers>

#include "cli_test_helpers.h"
#include "gdof/defocus.h"
#include "gdof/io/image_io.h"

using namespace gdof::test;

namespace {

bool built_without_embree(const CommandResult& r) { return contains(r.output, "without Embree"); }

// An emitter (3.5 px wide) at depth 20 on black, the camera focused at 0.5:
// its blur is the aperture's shape, about 16 px in radius.
void write_emitter_scene(const ScratchDir& dir, const std::string& name, const std::string& aperture_key) {
    write_text(dir.file("dot.obj"), "v -0.4 -0.4 0\nv 0.4 -0.4 0\nv 0.4 0.4 0\nv -0.4 0.4 0\nf 1 2 3 4\n");
    write_text(dir.file(name), R"({
  "camera": {"position": [0, 0, 20], "look_at": [0, 0, 0], "focal_length_mm": 50, "sensor_width_mm": 36,
             "resolution": [64, 64], "f_number": 0.3, "focus_distance": 0.5)" + aperture_key + R"(},
  "materials": {"glow": {"kd": 0, "ke": 50}},
  "meshes": [{"file": "dot.obj", "material": "glow"}]
})");
}

}  // namespace

TEST(cli_bokeh, render_aperture_polygon_gives_hexagonal_bokeh) {
    ScratchDir dir;
    write_emitter_scene(dir, "scene.json", "");
    const std::string out = dir.file("hex.exr");
    auto r = run_gdof("--render " + quote(dir.file("scene.json")) +
                      " --aperture polygon:6 --spp 1024 --adaptive-threshold 0 --ch R,G,B,A -o " + quote(out));
    if (built_without_embree(r)) GDOF_SKIP_OR_FAIL(r.output);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    OIIO::ImageSpec spec;
    const auto px = read_pixels(out, &spec);
    ASSERT_EQ(spec.width, 64);
    auto at = [&](double x, double y) {
        const int xi = int(x), yi = int(y);
        if (xi < 0 || yi < 0 || xi >= 64 || yi >= 64) return 0.0f;
        return px[(std::size_t(yi) * 64 + std::size_t(xi)) * std::size_t(spec.nchannels)];
    };
    // Its extent per direction from the centre, where it falls below half of the plateau.
    float level = 0.0f;
    for (int y = 30; y < 35; ++y)
        for (int x = 30; x < 35; ++x) level += 0.5f * at(x, y) / 25.0f;
    ASSERT_GT(level, 0.0f);
    auto extent = [&](double deg) {
        const double a = deg * std::numbers::pi / 180.0;
        double best = 0;
        for (double t = 0; t < 31; t += 0.25)
            if (at(32 + t * std::cos(a), 32 - t * std::sin(a)) >= level) best = t;
        return best;
    };
    // polygon:6 has a vertex on +u (image right): corners at 0, 60, ...
    // degrees reach farther than the edge middles at 30, 90, ... (cos 30).
    for (int k = 0; k < 6; ++k) {
        const double corner = extent(60.0 * k), edge = extent(60.0 * k + 30.0);
        EXPECT_GT(corner, 8.0) << k;
        EXPECT_NEAR(edge / corner, std::cos(std::numbers::pi / 6), 0.08) << "corner " << 60 * k;
    }

    // The scene's camera.aperture says the same: the same image.
    write_emitter_scene(dir, "scene_hex.json", R"(, "aperture": {"shape": "polygon", "blades": 6})");
    const std::string out2 = dir.file("hex2.exr");
    r = run_gdof("--render " + quote(dir.file("scene_hex.json")) + " --spp 1024 --adaptive-threshold 0 --ch R,G,B,A -o " +
                 quote(out2));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_EQ(read_pixels(out2), px);
    // A disc is not that.
    const std::string disc = dir.file("disc.exr");
    r = run_gdof("--render " + quote(dir.file("scene.json")) + " --spp 1024 --adaptive-threshold 0 --ch R,G,B,A -o " +
                 quote(disc));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(read_pixels(disc), px);
}

// --bokeh on a plate + depth map: what defocus() gives with the filter and
// the aperture of --aperture.
TEST(cli_bokeh, bokeh_equals_the_library_with_the_same_aperture) {
    ScratchDir dir;
    const int w = 80, h = 60;
    auto value = [](int x, int y, int c) -> float {
        if (c == 3) return 1.0f;
        if (c == 4) return x > 30 && x < 50 && y > 20 && y < 40 ? 1.5f : 8.0f;  // Z
        return ((x * 7 + y * 3) % 23 == 0) ? 30.0f : 0.1f + 0.05f * float(c);
    };
    write_exr(dir.file("plate.exr"), w, h, {"R", "G", "B", "A", "Z"}, value);
    const std::string lens = " --focal-length-mm 50 --sensor-width-mm 36 --f-number 1.4 --focus-distance 8";
    const std::string out = dir.file("out.exr");
    auto r = run_gdof(quote(dir.file("plate.exr")) + lens + " --aperture polygon:5:10,roundness=0.3 --bokeh -o " + quote(out));
    ASSERT_EQ(r.exit_code, 0) << r.output;

    auto in = gdof::io::read_image(dir.file("plate.exr"));
    ASSERT_TRUE(in) << in.message();
    gdof::CameraDesc d;
    d.display_window = {0, 0, w, h};
    d.focal_length_mm = 50;
    d.sensor_width_mm = 36;
    d.f_number = 1.4;
    d.focus_distance = 8;
    auto cam = gdof::Camera::create(d);
    ASSERT_TRUE(cam);
    auto field = gdof::BlurField::from_thin_lens(*cam->thin_lens());
    ASSERT_TRUE(field);
    gdof::DefocusOptions o;
    o.filter = gdof::DefocusFilter::Bokeh;
    o.aperture = *gdof::parse_aperture("polygon:5:10,roundness=0.3");
    auto lib = gdof::defocus(*in, *field, *cam, o);
    ASSERT_TRUE(lib) << lib.message();
    OIIO::ImageSpec spec;
    const auto px = read_pixels(out, &spec);
    const gdof::Image& img = lib->flat(0);
    double worst = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < 4; ++c)
                worst = std::max(worst, double(std::abs(px[(std::size_t(y) * w + std::size_t(x)) * std::size_t(spec.nchannels) + std::size_t(c)] -
                                                        img.at(c, x, y))));
    EXPECT_LE(worst, 1e-6);
    // And it is not --diffuse.
    const std::string diff = dir.file("diff.exr");
    r = run_gdof(quote(dir.file("plate.exr")) + lens + " --diffuse -o " + quote(diff));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(read_pixels(diff), px);
}

TEST(cli_bokeh, bad_apertures_are_clear_errors) {
    ScratchDir dir;
    write_exr(dir.file("plate.exr"), 16, 16, {"R", "G", "B", "A", "Z"}, [](int, int, int c) { return c == 4 ? 3.0f : 0.5f; });
    const std::string in = quote(dir.file("plate.exr")) + " --focal-length-mm 50 --f-number 2 --focus-distance 1 ";
    struct Case {
        std::string args, message;
        int exit;
    };
    const Case cases[] = {
        {"--aperture polygon:2 --bokeh", "blades must be 3 to 64", 2},
        {"--aperture star --bokeh", "unknown shape 'star'", 2},
        {"--aperture disc,petals=3 --bokeh", "unknown key 'petals'", 2},
        {"--aperture disc,squeeze=0 --bokeh", "squeeze must be in [0.1, 10]", 2},
        {"--aperture polygon:six --bokeh", "blades 'six' is not a whole number", 2},
        {"--aperture image:" + quote(dir.file("missing.png")) + " --bokeh", "missing.png", 1},
    };
    for (const Case& c : cases) {
        const std::string out = dir.file("out.exr");
        auto r = run_gdof(in + c.args + " -o " + quote(out));
        EXPECT_EQ(r.exit_code, c.exit) << c.args << "\n" << r.output;
        EXPECT_TRUE(contains(r.output, c.message)) << c.args << "\n" << r.output;
        EXPECT_TRUE(contains(r.output, "--aperture")) << c.args << "\n" << r.output;
        EXPECT_FALSE(std::filesystem::exists(out)) << c.args;
    }
    // --layers applies to --bokeh too; alone it is a usage error naming both.
    auto l = run_gdof(in + "--layers 2 --bokeh -o " + quote(dir.file("l.exr")));
    EXPECT_EQ(l.exit_code, 0) << l.output;
    l = run_gdof(in + "--layers 2 -o " + quote(dir.file("l2.exr")));
    EXPECT_EQ(l.exit_code, 2) << l.output;
    EXPECT_TRUE(contains(l.output, "--layers: no --diffuse or --bokeh follows it")) << l.output;
    // An all-black image kernel.
    write_exr(dir.file("black.exr"), 8, 8, {"R", "G", "B"}, [](int, int, int) { return 0.0f; });
    auto r = run_gdof(in + "--aperture image:" + quote(dir.file("black.exr")) + " --bokeh -o " + quote(dir.file("o.exr")));
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_TRUE(contains(r.output, "all zero")) << r.output;
    // The ray tracer has no cat's eye.
    write_text(dir.file("q.obj"), "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nf 1 2 3 4\n");
    write_text(dir.file("s.json"), R"({"camera": {"position": [0, 0, 5], "look_at": [0, 0, 0], "resolution": [8, 8],
        "f_number": 2, "focus_distance": 5}, "meshes": [{"file": "q.obj"}]})");
    r = run_gdof("--render " + quote(dir.file("s.json")) + " --aperture disc,cats_eye=0.5 -o " + quote(dir.file("r.exr")));
    if (!built_without_embree(r)) {
        EXPECT_EQ(r.exit_code, 1) << r.output;
        EXPECT_TRUE(contains(r.output, "cats_eye")) << r.output;
        EXPECT_FALSE(std::filesystem::exists(dir.file("r.exr")));
    }
    // A bad scene key names its path.
    write_text(dir.file("s2.json"), R"({"camera": {"position": [0, 0, 5], "look_at": [0, 0, 0], "resolution": [8, 8],
        "aperture": {"shape": "polygon", "blades": 1}}, "meshes": [{"file": "q.obj"}]})");
    r = run_gdof("--render " + quote(dir.file("s2.json")) + " -o " + quote(dir.file("r2.exr")));
    EXPECT_NE(r.exit_code, 0) << r.output;
    EXPECT_TRUE(contains(r.output, "camera.aperture.blades")) << r.output;
}
