// gdof --vibrate end to end: the thin-lens special case on a deep render
// against the ray tracer's thin lens (closer than --diffuse on the same deep
// input), a swirl field from a file, and the errors (bad JSON naming the
// key, bad sample counts, modifiers without --vibrate), never a partial output.
#include <cmath>

#include "cli_test_helpers.h"

using namespace gdof::test;

namespace {

bool built_without_embree(const CommandResult& r) { return contains(r.output, "without Embree"); }

// Relative L1 of R, G, B against the truth (same size).
double relative_l1(const Pixels& a, const Pixels& truth) {
    double e = 0, t = 0;
    for (int y = 0; y < truth.spec.height; ++y)
        for (int x = 0; x < truth.spec.width; ++x)
            for (int c = 0; c < 3; ++c) {
                e += std::abs(double(a.at(x, y, c)) - double(truth.at(x, y, c)));
                t += std::abs(double(truth.at(x, y, c)));
            }
    return e / t;
}

}  // namespace

TEST(cli_vibrate, thin_lens_on_a_deep_render_matches_the_ray_tracer_better_than_diffusion) {
    ScratchDir dir;
    const std::string obj = std::string(GDOF_SOURCE_DIR) + "/examples/render/generated.obj";
    write_text(dir.file("scene.json"), R"({
  "camera": {"position": [0.0, 1.3, 6.5], "look_at": [0.0, 0.8, 0.0], "up": [0, 1, 0], "focal_length_mm": 35,
             "sensor_width_mm": 36, "resolution": [160, 90], "f_number": 0.1, "focus_distance": 4.0},
  "meshes": [{"file": ")" + obj + R"("}],
  "lights": [{"type": "point", "position": [3.0, 5.0, 4.0], "intensity": [6, 6, 6]}],
  "environment": [0.05, 0.06, 0.08]
})");
    const std::string truth = dir.file("truth.exr"), deep = dir.file("deep.exr");
    auto r = run_gdof("--render " + quote(dir.file("scene.json")) + " --spp 256 --adaptive-threshold 0 --ch R,G,B,A -o " +
                      quote(truth));
    if (built_without_embree(r)) GDOF_SKIP_OR_FAIL(r.output);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    r = run_gdof("--render " + quote(dir.file("scene.json")) + " --pinhole --deep --spp 16 -o " + quote(deep));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const std::string vib = dir.file("vibrate.exr"), diff = dir.file("diffuse.exr");
    r = run_gdof(quote(deep) + " --psf-samples 256 --vibrate --stats -o " + quote(vib));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_TRUE(contains(r.output, "psf field")) << r.output;
    r = run_gdof(quote(deep) + " --diffuse -o " + quote(diff));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const Pixels t = read_image_pixels(truth), v = read_image_pixels(vib), d = read_image_pixels(diff);
    ASSERT_EQ(v.spec.width, t.spec.width);
    ASSERT_EQ(d.spec.width, t.spec.width);
    const double ev = relative_l1(v, t), ed = relative_l1(d, t);
    std::printf("relative L1 against the ray tracer's thin lens: --vibrate %.4f, --diffuse %.4f\n", ev, ed);
    EXPECT_LT(ev, ed);
    // The default field is the defocus kind: the example file gives the same bits.
    const std::string vib2 = dir.file("vibrate2.exr");
    r = run_gdof(quote(deep) + " --psf-field " + quote(std::string(GDOF_SOURCE_DIR) + "/examples/psf_fields/defocus.json") +
                 " --psf-samples 256 --vibrate -o " + quote(vib2));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_EQ(read_pixels(vib2), v.values);
    // And the swirl example differs.
    const std::string sw = dir.file("swirl.exr");
    r = run_gdof(quote(deep) + " --psf-field " + quote(std::string(GDOF_SOURCE_DIR) + "/examples/psf_fields/swirl.json") +
                 " --psf-samples 64 --vibrate -o " + quote(sw));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(read_pixels(sw), v.values);
}

TEST(cli_vibrate, bad_fields_and_flags_are_clear_errors) {
    ScratchDir dir;
    write_exr(dir.file("plate.exr"), 16, 16, {"R", "G", "B", "A", "Z"}, [](int, int, int c) { return c == 4 ? 3.0f : 0.5f; });
    const std::string in = quote(dir.file("plate.exr")) + " --focal-length-mm 50 --f-number 2 --focus-distance 1 ";
    write_text(dir.file("typo.json"), R"({"psf_field": {"kind": "swirl", "strenght": 2}})");
    write_text(dir.file("broken.json"), R"({"psf_field": {"kind": "swirl")");
    struct Case {
        std::string args, message;
        int exit;
    };
    const Case cases[] = {
        {"--psf-field " + quote(dir.file("typo.json")) + " --vibrate", "psf_field.strenght: unknown key", 1},
        {"--psf-field " + quote(dir.file("broken.json")) + " --vibrate", "malformed JSON at line", 1},
        {"--psf-field " + quote(dir.file("missing.json")) + " --vibrate", "missing.json", 1},
        {"--psf-samples many --vibrate", "--psf-samples", 2},
        {"--psf-samples 70000 --vibrate", "--psf-samples", 2},
        {"--psf-samples 8", "--psf-samples: no --vibrate follows it", 2},
        {"--aperture disc,cats_eye=1.5 --vibrate", "cats_eye must be in [0, 1]", 2},
    };
    for (const Case& c : cases) {
        const std::string out = dir.file("out.exr");
        auto r = run_gdof(in + c.args + " -o " + quote(out));
        EXPECT_EQ(r.exit_code, c.exit) << c.args << "\n" << r.output;
        EXPECT_TRUE(contains(r.output, c.message)) << c.args << "\n" << r.output;
        EXPECT_FALSE(std::filesystem::exists(out)) << c.args;
    }
}
