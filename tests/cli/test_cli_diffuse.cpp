// gdof CLI: --diffuse (method 3) end to end on the generated example scene
// (flat RGBA + Z + P + camera, and its deep version), its modifiers
// (--solver, --layers, --adi-steps), --stats, frame ranges and errors.
#include <cmath>
#include <cstdio>

#include <OpenImageIO/imagebufalgo.h>

#include "cli/cli_test_helpers.h"
#include "gdof/camera.h"
#include "gdof/io/image_io.h"

using namespace gdof::test;

namespace {

// Sharp at depth 2.9 and 12.6 (the red and the far sphere), up to 6 px between and in front.
const char* kField = R"({"blurfield": {"kind": "focal_planes", "depths": [2.9, 12.6], "max_blur": 6, "slope": 4,
                         "interpolation": "smooth"}})";

struct Scene {
    ScratchDir dir;
    std::string flat, deep, field;
    Scene() {
        flat = dir.file("scene.exr");
        deep = dir.file("deep.exr");
        field = dir.file("field.json");
        auto r = run_command(std::string("'") + GDOF_EXAMPLE_SCENE_PATH + "' --size 160x90 --subsamples 2 -o " +
                             quote(flat) + " --deep " + quote(deep));
        EXPECT_EQ(r.exit_code, 0) << r.output;
        write_text(field, kField);
    }
    std::string diffuse(const std::string& input, const std::string& out, const std::string& extra = "") const {
        return quote(input) + " --blurfield " + quote(field) + " " + extra + " --diffuse -o " + quote(out);
    }
};

int channel(const OIIO::ImageSpec& s, const std::string& name) {
    for (int c = 0; c < s.nchannels; ++c)
        if (s.channelnames[std::size_t(c)] == name) return c;
    return -1;
}

double mean_abs_diff(const std::vector<float>& a, const std::vector<float>& b, int stride, int nc) {
    double s = 0;
    std::size_t n = 0;
    for (std::size_t i = 0; i + std::size_t(stride) <= a.size() && i < b.size(); i += std::size_t(stride))
        for (int c = 0; c < nc; ++c, ++n) s += std::abs(a[i + std::size_t(c)] - b[i + std::size_t(c)]);
    return n ? s / double(n) : 1e9;
}

}  // namespace

TEST(cli_diffuse, FlatInputBecomesDefocusedRgbaWithItsOtherChannels) {
    Scene sc;
    const std::string out = sc.dir.file("out.exr");
    auto r = run_gdof(sc.diffuse(sc.flat, out));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    OIIO::ImageSpec in_spec, spec;
    auto in = read_pixels(sc.flat, &in_spec);
    auto px = read_pixels(out, &spec);
    ASSERT_FALSE(px.empty());
    // R, G, B, A first (half, as the input), then the input's other channels.
    ASSERT_GE(spec.nchannels, 4);
    EXPECT_EQ(spec.channelnames[0], "R");
    EXPECT_EQ(spec.channelnames[3], "A");
    EXPECT_EQ(spec.channelformat(0), OIIO::TypeDesc::HALF);
    EXPECT_EQ(spec.nchannels, in_spec.nchannels);
    EXPECT_GE(channel(spec, "Z"), 0);
    EXPECT_GE(channel(spec, "P.x"), 0);
    EXPECT_GE(channel(spec, "id"), 0);
    EXPECT_EQ(spec.full_width, 160);
    EXPECT_EQ(spec.full_height, 90);
    EXPECT_TRUE(spec.find_attribute("worldToCamera")) << "metadata kept";
    // A full-frame input: the result is the frame (blur does not leak out).
    EXPECT_EQ(spec.x, 0);
    EXPECT_EQ(spec.y, 0);
    EXPECT_EQ(spec.width, 160);
    EXPECT_EQ(spec.height, 90);
    // Opaque scene: opaque result everywhere, edges and corners included (the
    // frame edge insulates); blurred: it differs from the input.
    double max_diff = 0;
    for (int y = 0; y < 90; ++y)
        for (int x = 0; x < 160; ++x) {
            const std::size_t o = (std::size_t(y - spec.y) * std::size_t(spec.width) + std::size_t(x - spec.x)) *
                                  std::size_t(spec.nchannels);
            const std::size_t i = (std::size_t(y) * 160 + std::size_t(x)) * std::size_t(in_spec.nchannels);
            ASSERT_NEAR(px[o + 3], 1.0f, 2e-3) << x << "," << y;
            max_diff = std::max(max_diff, double(std::abs(px[o] - in[i])));
            // Z is carried over unchanged.
            ASSERT_EQ(px[o + std::size_t(channel(spec, "Z"))], in[i + std::size_t(channel(in_spec, "Z"))]);
        }
    EXPECT_GT(max_diff, 0.05);
}

TEST(cli_diffuse, DeepInputAndAThinLensFromTheFileWithoutBlurfield) {
    Scene sc;
    // Zero blur: the deep image flattened (reference: OIIO's own flatten).
    const std::string zero = sc.dir.file("zero.json"), sharp = sc.dir.file("sharp.exr");
    write_text(zero, R"({"blurfield": {"kind": "focal_planes", "depths": [2.9], "max_blur": 0, "slope": 1}})");
    auto r = run_gdof(quote(sc.deep) + " --blurfield " + quote(zero) + " --diffuse -o " + quote(sharp));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    OIIO::ImageBuf deep(sc.deep);
    OIIO::ImageBuf flat = OIIO::ImageBufAlgo::flatten(deep);
    ASSERT_FALSE(flat.has_error()) << flat.geterror();
    OIIO::ImageSpec sspec;
    auto sp = read_pixels(sharp, &sspec);
    ASSERT_EQ(sspec.nchannels, 4);
    double worst = 0;
    for (int y = 0; y < 90; ++y)
        for (int x = 0; x < 160; ++x)
            for (int c = 0; c < 4; ++c) {
                const std::size_t o = (std::size_t(y - sspec.y) * std::size_t(sspec.width) + std::size_t(x - sspec.x)) * 4;
                worst = std::max(worst, double(std::abs(sp[o + std::size_t(c)] - flat.getchannel(x, y, 0, c))));
            }
    EXPECT_LT(worst, 2e-3);

    // Blurred: R, G, B, A, different from the sharp result, and close to what
    // the flat version of the same scene gives.
    const std::string out = sc.dir.file("out_deep.exr"), flat_out = sc.dir.file("out_flat.exr");
    r = run_gdof(sc.diffuse(sc.deep, out));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    OIIO::ImageSpec spec;
    auto px = read_pixels(out, &spec);
    ASSERT_EQ(spec.nchannels, 4);
    EXPECT_EQ(spec.channelnames[3], "A");
    EXPECT_EQ(spec.full_width, 160);
    EXPECT_GT(mean_abs_diff(px, sp, 4, 4), 0.005);
    for (std::size_t i = 3; i < px.size(); i += 4) ASSERT_LE(px[i], 1.001f);
    r = run_gdof(sc.diffuse(sc.flat, flat_out));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    OIIO::ImageSpec fspec;
    auto fpx = read_pixels(flat_out, &fspec);
    ASSERT_EQ(spec.width, fspec.width);
    std::vector<float> rgba, deep_rgba;
    for (int y = 10; y < 80; ++y)
        for (int x = 10; x < 150; ++x) {
            const std::size_t p = std::size_t(y - spec.y) * std::size_t(spec.width) + std::size_t(x - spec.x);
            for (int c = 0; c < 4; ++c) {
                rgba.push_back(fpx[p * std::size_t(fspec.nchannels) + std::size_t(c)]);
                deep_rgba.push_back(px[p * 4 + std::size_t(c)]);
            }
        }
    // They differ where the deep file's coverage is partial (antialiased
    // edges are coverage samples, not a flat pixel's average) and in how the
    // two inputs are cut into layers; both extend layers behind nearer ones.
    // Measured mean 0.0138 (0.049 before deep layers were extended).
    const double d = mean_abs_diff(deep_rgba, rgba, 4, 4);
    std::printf("[ measured ] deep vs flat input, mean |difference| of defocused RGBA inside the frame: %.4f\n", d);
    EXPECT_LT(d, 0.03);

    // No --blurfield: the camera's own lens (the file has focal length,
    // f-number, focus distance), exactly as that thin lens given as a field.
    r = run_gdof(quote(sc.flat) + " --diffuse -o " + quote(sc.dir.file("lens.exr")));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    auto scene_image = gdof::io::read_flat(sc.flat);
    ASSERT_TRUE(scene_image) << scene_image.message();
    auto camera = gdof::Camera::from_image(*scene_image);
    ASSERT_TRUE(camera) << camera.message();
    auto lens = camera->thin_lens();
    ASSERT_TRUE(lens) << lens.message();
    char json[512];
    std::snprintf(json, sizeof json,
                  R"({"blurfield": {"kind": "thin_lens", "focal_length_mm": %.17g, "f_number": %.17g, )"
                  R"("focus_distance": %.17g, "sensor_width_mm": %.17g, "scene_unit_mm": %.17g}})",
                  lens->focal_length_mm, lens->f_number, lens->focus_distance, lens->sensor_width_mm,
                  lens->scene_unit_mm);
    write_text(sc.dir.file("lens.json"), json);
    r = run_gdof(quote(sc.flat) + " --blurfield " + quote(sc.dir.file("lens.json")) + " --diffuse -o " +
                 quote(sc.dir.file("lens_field.exr")));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    OIIO::ImageSpec in_spec, lens_spec;
    const auto input = read_pixels(sc.flat, &in_spec);
    const auto from_camera = read_pixels(sc.dir.file("lens.exr"), &lens_spec);
    ASSERT_EQ(lens_spec.nchannels, in_spec.nchannels);
    EXPECT_EQ(from_camera, read_pixels(sc.dir.file("lens_field.exr")));
    EXPECT_GT(mean_abs_diff(from_camera, input, in_spec.nchannels, 4), 2e-4)
        << "f/2.8 at 4.5: blurred (measured 6.5e-4)";
}

TEST(cli_diffuse, SolverLayersAdiStepsAndStats) {
    Scene sc;
    const std::string a = sc.dir.file("adi.exr"), e = sc.dir.file("explicit.exr");
    // The default solver is auto: at 6 px every layer runs explicit (cheaper below ~15 px).
    auto r = run_gdof("--stats " + sc.diffuse(sc.flat, sc.dir.file("auto.exr"), "--layers 3"));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_TRUE(contains(r.output, "(solver auto)")) << r.output;
    EXPECT_TRUE(contains(r.output, "solver            3 explicit, 0 adi")) << r.output;
    r = run_gdof("--stats " + sc.diffuse(sc.flat, a, "--layers 3 --solver adi --adi-steps 32"));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    // The defocus report: layers (empty / sharp), solvers, pixels, time per stage.
    EXPECT_TRUE(contains(r.output, "--diffuse")) << r.output;
    EXPECT_TRUE(contains(r.output, "solver adi")) << r.output;
    EXPECT_TRUE(contains(r.output, "solver            0 explicit, 3 adi")) << r.output;
    EXPECT_TRUE(contains(r.output, "layers            3 (")) << r.output;
    EXPECT_TRUE(contains(r.output, "empty")) << r.output;
    EXPECT_TRUE(contains(r.output, "sharp")) << r.output;
    EXPECT_TRUE(contains(r.output, "pixels diffused")) << r.output;
    EXPECT_TRUE(contains(r.output, "pixels skipped")) << r.output;
    EXPECT_TRUE(contains(r.output, "max blur radius   6.00 px")) << r.output;
    EXPECT_TRUE(contains(r.output, "t diffuse")) << r.output;
    EXPECT_TRUE(contains(r.output, "gdof: stats")) << r.output;
    r = run_gdof(sc.diffuse(sc.flat, e, "--layers 3 --solver explicit"));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    OIIO::ImageSpec sa, se;
    auto pa = read_pixels(a, &sa), pe = read_pixels(e, &se);
    ASSERT_EQ(pa.size(), pe.size());
    EXPECT_LT(mean_abs_diff(pa, pe, sa.nchannels, 4), 0.01);
    EXPECT_GT(mean_abs_diff(pa, pe, sa.nchannels, 4), 0.0);  // really another solver
}

// --pyramid: on by default for blurs above 6 px (the --stats line says so),
// off gives the full-resolution reference; the two agree closely.
TEST(cli_diffuse, PyramidOnByDefaultOffIsTheReference) {
    Scene sc;
    const std::string big = sc.dir.file("big.json"), on = sc.dir.file("on.exr"), off = sc.dir.file("off.exr");
    write_text(big, R"({"blurfield": {"kind": "focal_planes", "depths": [2.9], "max_blur": 24, "slope": 12}})");
    auto r = run_gdof("--stats " + quote(sc.flat) + " --blurfield " + quote(big) + " --layers 2 --diffuse -o " + quote(on));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_TRUE(contains(r.output, "on the pyramid")) << r.output;
    r = run_gdof("--stats " + quote(sc.flat) + " --blurfield " + quote(big) + " --layers 2 --pyramid off --diffuse -o " +
                 quote(off));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_FALSE(contains(r.output, "on the pyramid")) << r.output;
    OIIO::ImageSpec so, sf;
    auto po = read_pixels(on, &so), pf = read_pixels(off, &sf);
    ASSERT_EQ(po.size(), pf.size());
    EXPECT_GT(mean_abs_diff(po, pf, so.nchannels, 4), 0.0);
    EXPECT_LT(mean_abs_diff(po, pf, so.nchannels, 4), 0.01);
    r = run_gdof(quote(sc.flat) + " --pyramid maybe --diffuse -o " + quote(sc.dir.file("x.exr")));
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_TRUE(contains(r.output, "--pyramid: expected 'on' or 'off', got 'maybe'")) << r.output;
    EXPECT_FALSE(fs::exists(sc.dir.file("x.exr")));
}

TEST(cli_diffuse, FrameRanges) {
    Scene sc;
    fs::copy_file(sc.flat, sc.dir.file("in.0001.exr"));
    fs::copy_file(sc.flat, sc.dir.file("in.0002.exr"));
    auto r = run_gdof("--frames 1-2 " + quote(sc.dir.file("in.#.exr")) + " --blurfield " + quote(sc.field) +
                      " --diffuse -o " + quote(sc.dir.file("out.#.exr")));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    ASSERT_TRUE(fs::exists(sc.dir.file("out.0001.exr")));
    ASSERT_TRUE(fs::exists(sc.dir.file("out.0002.exr")));
    EXPECT_EQ(read_pixels(sc.dir.file("out.0001.exr")), read_pixels(sc.dir.file("out.0002.exr")));
}

TEST(cli_diffuse, ErrorsNameTheCulpritAndLeaveNoOutput) {
    Scene sc;
    const std::string out = sc.dir.file("out.exr");
    // No depth: RGBA only (a camera from the flags).
    const std::string rgba = sc.dir.file("rgba.exr");
    write_exr(rgba, 32, 16, {"R", "G", "B", "A"}, [](int, int, int) { return 0.5f; });
    auto r = run_gdof(quote(rgba) + " --focal-length-mm 35 --blurfield " + quote(sc.field) + " --diffuse -o " + quote(out));
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_TRUE(contains(r.output, "--diffuse")) << r.output;
    EXPECT_TRUE(contains(r.output, "no depth channel 'Z'")) << r.output;
    EXPECT_FALSE(fs::exists(out));
    // No camera at all.
    r = run_gdof(quote(rgba) + " --blurfield " + quote(sc.field) + " --diffuse -o " + quote(out));
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_TRUE(contains(r.output, "--focal-length-mm")) << r.output;
    EXPECT_FALSE(fs::exists(out));
    // Bad --solver / --layers / --adi-steps values: usage errors naming flag and value.
    r = run_gdof(sc.diffuse(sc.flat, out, "--solver fast"));
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_TRUE(contains(r.output, "--solver")) << r.output;
    EXPECT_TRUE(contains(r.output, "'fast'")) << r.output;
    r = run_gdof(sc.diffuse(sc.flat, out, "--layers banana"));
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_TRUE(contains(r.output, "--layers")) << r.output;
    EXPECT_TRUE(contains(r.output, "banana")) << r.output;
    r = run_gdof(sc.diffuse(sc.flat, out, "--layers 0"));
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_TRUE(contains(r.output, "--layers")) << r.output;
    r = run_gdof(sc.diffuse(sc.flat, out, "--adi-steps -3"));
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_TRUE(contains(r.output, "--adi-steps")) << r.output;
    // A modifier after the last --diffuse would be silently ignored: an error.
    r = run_gdof(quote(sc.flat) + " --diffuse --solver explicit -o " + quote(out));
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_TRUE(contains(r.output, "--solver: no --diffuse follows it")) << r.output;
    // --diffuse with nothing on the stack.
    r = run_gdof("--diffuse -o " + quote(out));
    EXPECT_EQ(r.exit_code, 2) << r.output;
    // An absurd blur names the value.
    const std::string huge = sc.dir.file("huge.json");
    write_text(huge, R"({"blurfield": {"kind": "focal_planes", "depths": [2.9], "slope": 100000}})");
    r = run_gdof(quote(sc.flat) + " --blurfield " + quote(huge) + " --diffuse -o " + quote(out));
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_TRUE(contains(r.output, "max_radius")) << r.output;
    EXPECT_FALSE(fs::exists(out));
    EXPECT_EQ(list_dir(sc.dir.path().string()).size(), 5u) << "only the inputs remain";
}

TEST(cli_diffuse, HelpListsTheCommands) {
    auto r = run_gdof("--help");
    ASSERT_EQ(r.exit_code, 0);
    for (const char* f : {"--diffuse", "--solver", "--layers", "--adi-steps"}) EXPECT_TRUE(contains(r.output, f)) << f;
}
