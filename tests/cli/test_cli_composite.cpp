// gdof --composite end to end: surfaces, near/far maps, blur field + depth
// image, AOVs, --stats, and the errors for bad stacks.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "cli_test_helpers.h"
#include "gdof/camera.h"

namespace gdof::test {
namespace {

constexpr int W = 96, H = 48;

float ref_value(int i, int x, int y, int c) {
    if (c == 3) return 1.0f;
    return float(i) + 0.01f * float(x) + 0.001f * float(y) + 0.1f * float(c);
}

// Three references of a 50 mm lens on 36 mm at f/4, focused at 1, 2, 4 m;
// near/far from the thin lens (coc 1 px).
std::string make_stack(const ScratchDir& dir, const std::string& skip = "") {
    fs::create_directories(dir.path() / "stack");
    for (int i = 0; i < 3; ++i) {
        const std::string name = "ref." + std::to_string(i + 1) + ".exr";
        if (name == skip) continue;
        write_exr(dir.file("stack/" + name), W, H, {"R", "G", "B", "A"},
                  [i](int x, int y, int c) { return ref_value(i, x, y, c); },
                  [](OIIO::ImageSpec& spec) {
                      spec.attribute("focalLength", 50.0f);
                      spec.full_x = 0;
                  });
    }
    write_text(dir.file("stack/manifest.json"), R"({
      "gdof_stack": 1, "coc_px": 1.0, "focal_length_mm": 50, "sensor_width_mm": 36,
      "width": 96, "height": 48,
      "references": [
        {"file": "ref.1.exr", "focus_distance": 1, "f_number": 4},
        {"file": "ref.2.exr", "focus_distance": 2, "f_number": 4},
        {"file": "ref.3.exr", "focus_distance": 4, "f_number": 4}]})");
    return dir.file("stack/manifest.json");
}

ThinLens::DofLimits limits(double focus) {
    ThinLens l;
    l.focal_length_mm = 50;
    l.f_number = 4;
    l.focus_distance = focus;
    l.sensor_width_mm = 36;
    l.image_width_px = W;
    return l.dof_limits(1.0);
}

std::string num(double v) {
    if (std::isinf(v)) return "\"inf\"";
    char b[64];
    std::snprintf(b, sizeof b, "%.17g", v);
    return b;
}

void expect_region_is_ref(const std::vector<float>& px, int nch, int x0, int x1, int ref) {
    for (int y = 0; y < H; ++y)
        for (int x = x0; x < x1; ++x)
            for (int c = 0; c < 4; ++c)
                ASSERT_EQ(px[(std::size_t(y) * W + std::size_t(x)) * std::size_t(nch) + std::size_t(c)],
                          ref_value(ref, x, y, c))
                    << "pixel " << x << "," << y << " channel " << c << " should be reference " << ref;
}

TEST(cli_composite, surfaces_equal_to_a_reference_give_that_reference) {
    ScratchDir dir;
    const std::string m = make_stack(dir);
    const auto l = limits(2.0);
    write_text(dir.file("s.json"), "{\"near\": " + num(l.near) + ", \"far\": " + num(l.far) + "}");
    auto r = run_gdof("--stats --composite " + quote(m) + " --surfaces " + quote(dir.file("s.json")) + " --aovs -o " +
                      quote(dir.file("out.exr")));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_TRUE(contains(r.output, "references used 1 of 3")) << r.output;
    EXPECT_TRUE(contains(r.output, "files opened 1")) << r.output;
    EXPECT_TRUE(contains(r.output, "Mpixel/s")) << r.output;
    OIIO::ImageSpec spec;
    const auto px = read_pixels(dir.file("out.exr"), &spec);
    ASSERT_EQ(spec.width, W);
    ASSERT_EQ(spec.nchannels, 6);
    EXPECT_EQ(spec.channelnames[4], "stack.deviation");  // EXR sorts channel names within a layer
    expect_region_is_ref(px, 6, 0, W, 1);
    const int ci = spec.channelindex("stack.index");
    ASSERT_GE(ci, 0);
    EXPECT_EQ(px[std::size_t(ci)], 1.0f);
    EXPECT_EQ(spec.get_float_attribute("focalLength"), 50.0f) << "metadata of the reference";
}

TEST(cli_composite, near_far_maps_piecewise) {
    ScratchDir dir;
    const std::string m = make_stack(dir);
    const auto a = limits(1.0), b = limits(4.0);
    write_exr(dir.file("near.exr"), W, H, {"near"}, [&](int x, int, int) { return float(x < W / 2 ? a.near : b.near); });
    write_exr(dir.file("far.exr"), W, H, {"far"}, [&](int x, int, int) { return float(x < W / 2 ? a.far : b.far); });
    auto r = run_gdof("--composite " + quote(m) + " --near-map " + quote(dir.file("near.exr")) + " --far-map " +
                      quote(dir.file("far.exr")) + " -o " + quote(dir.file("out.exr")));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const auto px = read_pixels(dir.file("out.exr"));
    expect_region_is_ref(px, 4, 0, W / 2, 0);
    expect_region_is_ref(px, 4, W / 2, W, 2);
}

TEST(cli_composite, blur_field_and_depth_image) {
    ScratchDir dir;
    const std::string m = make_stack(dir);
    // Depth image: a thin lens focused at 4 m as the field; every pixel's interval is reference 3's.
    write_exr(dir.file("depth.exr"), W, H, {"Z"}, [](int x, int, int) { return x < W / 2 ? 4.0f : 9.0f; },
              [](OIIO::ImageSpec& spec) { spec.attribute("focalLength", 50.0f); spec.attribute("sensorWidth", 36.0f); });
    write_text(dir.file("f.json"), R"({"blurfield": {"kind": "thin_lens", "focal_length_mm": 50, "f_number": 4,
        "focus_distance": 4, "sensor_width_mm": 36}})");
    auto r = run_gdof(quote(dir.file("depth.exr")) + " --focal-length-mm 50 --sensor-width-mm 36 --blurfield " +
                      quote(dir.file("f.json")) + " --composite " + quote(m) + " -o " + quote(dir.file("out.exr")));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const auto px = read_pixels(dir.file("out.exr"));
    expect_region_is_ref(px, 4, 0, W, 2);
}

TEST(cli_composite, missing_reference_is_named_up_front) {
    ScratchDir dir;
    const std::string m = make_stack(dir, "ref.3.exr");
    const auto l = limits(1.0);
    write_text(dir.file("s.json"), "{\"near\": " + num(l.near) + ", \"far\": " + num(l.far) + "}");
    auto r = run_gdof("--composite " + quote(m) + " --surfaces " + quote(dir.file("s.json")) + " -o " +
                      quote(dir.file("out.exr")));
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_TRUE(contains(r.output, "ref.3.exr")) << r.output;
    EXPECT_TRUE(contains(r.output, "not found")) << r.output;
    EXPECT_FALSE(fs::exists(dir.file("out.exr")));
}

TEST(cli_composite, bad_inputs) {
    ScratchDir dir;
    const std::string m = make_stack(dir);
    // Duplicate (focus, aperture).
    write_text(dir.file("dup.json"), R"({"focal_length_mm": 50, "sensor_width_mm": 36, "width": 96, "height": 48,
        "references": [{"file": "stack/ref.1.exr", "focus_distance": 1, "f_number": 4},
                       {"file": "stack/ref.2.exr", "focus_distance": 1, "f_number": 4}]})");
    write_text(dir.file("s.json"), R"({"near": 1, "far": 2})");
    auto r = run_gdof("--composite " + quote(dir.file("dup.json")) + " --surfaces " + quote(dir.file("s.json")) +
                      " -o " + quote(dir.file("out.exr")));
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_TRUE(contains(r.output, "duplicate")) << r.output;
    EXPECT_TRUE(contains(r.output, "stack/ref.1.exr")) << r.output;
    EXPECT_TRUE(contains(r.output, "stack/ref.2.exr")) << r.output;
    // Mismatched resolution of a selected reference.
    write_exr(dir.file("stack/ref.2.exr"), 80, 48, {"R", "G", "B", "A"}, [](int, int, int) { return 0.5f; });
    const auto l = limits(2.0);
    write_text(dir.file("s2.json"), "{\"near\": " + num(l.near) + ", \"far\": " + num(l.far) + "}");
    r = run_gdof("--composite " + quote(m) + " --surfaces " + quote(dir.file("s2.json")) + " -o " +
                 quote(dir.file("out.exr")));
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_TRUE(contains(r.output, "ref.2.exr")) << r.output;
    EXPECT_TRUE(contains(r.output, "80x48")) << r.output;
    EXPECT_TRUE(contains(r.output, "96x48")) << r.output;
    // Usage errors, on a sound stack again (every reference's size is checked
    // before the focus source is looked at).
    const std::string m_ok = make_stack(dir);
    r = run_gdof("--composite " + quote(m_ok) + " --soft 0 -o x.exr");
    EXPECT_EQ(r.exit_code, 2) << r.output;
    r = run_gdof("--surfaces " + quote(dir.file("s.json")) + " in.exr -o x.exr");
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_TRUE(contains(r.output, "only used with --composite")) << r.output;
    r = run_gdof("--composite " + quote(m_ok) + " -o " + quote(dir.file("out.exr")));
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_TRUE(contains(r.output, "--surfaces")) << r.output;
}

TEST(cli_composite, soft_mode_and_help) {
    ScratchDir dir;
    const std::string m = make_stack(dir);
    const auto a = limits(1.0), b = limits(2.0);
    write_text(dir.file("s.json"), "{\"near\": " + num(0.5 * (a.near + b.near)) + ", \"far\": " +
                                       num(0.5 * (a.far + b.far) + 0.01) + "}");
    auto r = run_gdof("--composite " + quote(m) + " --surfaces " + quote(dir.file("s.json")) + " --soft 2 -o " +
                      quote(dir.file("soft.exr")));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const auto px = read_pixels(dir.file("soft.exr"));
    // A blend of references 0 and 1 (values i + ...): strictly between them.
    EXPECT_GT(px[0], ref_value(0, 0, 0, 0));
    EXPECT_LT(px[0], ref_value(1, 0, 0, 0));
    auto h = run_gdof("--help");
    EXPECT_TRUE(contains(h.output, "--composite")) << h.output;
    EXPECT_TRUE(contains(h.output, "--surfaces")) << h.output;
}

}  // namespace
}  // namespace gdof::test
