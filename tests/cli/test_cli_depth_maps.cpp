// Live-action depth maps through --eval-blur: uint16 PNG counts with a scale
// (TUM RGB-D: metres = counts / 5000), a lens given by flags, checked against
// the thin-lens CoC of the decoded depth.
#include <cmath>

#include "cli_test_helpers.h"
#include "gdof/camera.h"

using namespace gdof::test;

namespace {

const char* kLensFlags = " --focal-length-mm 35 --sensor-width-mm 36 --f-number 2 --focus-distance 1.5";

gdof::ThinLens lens_for_width(int width) {
    gdof::ThinLens l;
    l.focal_length_mm = 35;
    l.sensor_width_mm = 36;
    l.f_number = 2;
    l.focus_distance = 1.5;
    l.image_width_px = width;
    return l;
}

void write_uint16_png(const std::string& path, int w, int h, const std::vector<std::uint16_t>& counts) {
    OIIO::ImageSpec spec(w, h, 1, OIIO::TypeDesc::UINT16);
    auto out = OIIO::ImageOutput::create(path);
    ASSERT_TRUE(out);
    ASSERT_TRUE(out->open(path, spec));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT16, counts.data()));
    ASSERT_TRUE(out->close());
}

}  // namespace

TEST(cli_depth_maps, ScaledUint16DepthGivesTheThinLensCoC) {
    ScratchDir dir;
    const int w = 64, h = 8;
    std::vector<std::uint16_t> counts(std::size_t(w) * h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) counts[std::size_t(y) * w + x] = std::uint16_t(x == 0 ? 0 : 1500 + 400 * x + y);
    const std::string png = dir.file("depth.png"), out = dir.file("blur.exr");
    write_uint16_png(png, w, h, counts);
    // OIIO reads 16-bit PNG normalised to 0..1: metres = v * 65535 / 5000.
    auto r = run_gdof(quote(png) + " --depth-channel Y --depth-encoding scaled --depth-scale 13.107" + kLensFlags +
                      " --eval-blur -o " + quote(out));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    OIIO::ImageSpec spec;
    auto px = read_pixels(out, &spec);
    const int b = spec.channelindex("blur");
    ASSERT_GE(b, 0);
    const gdof::ThinLens lens = lens_for_width(w);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const float v = px[(std::size_t(y) * w + x) * spec.nchannels + b];
            // Zero counts are "no measurement": a hole, no depth and no blur
            // (--diffuse fills holes; --depth-invalid sky makes them infinitely far).
            if (x == 0) {
                ASSERT_TRUE(std::isnan(v)) << v;
                continue;
            }
            const double depth = counts[std::size_t(y) * w + x] / 5000.0;
            const double expected = lens.coc_radius_px(depth);
            ASSERT_NEAR(v, expected, 1e-4 * (1 + expected)) << x << "," << y;
        }
}

TEST(cli_depth_maps, BadEncodingAndMissingNearFarAreNamed) {
    ScratchDir dir;
    const std::string png = dir.file("depth.png"), out = dir.file("blur.exr");
    write_uint16_png(png, 4, 4, std::vector<std::uint16_t>(16, 1000));
    auto r = run_gdof(quote(png) + " --depth-channel Y --depth-encoding logarithmic" + kLensFlags + " --eval-blur -o " +
                      quote(out));
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_TRUE(contains(r.output, "logarithmic")) << r.output;
    r = run_gdof(quote(png) + " --depth-channel Y --depth-encoding near_far_linear" + kLensFlags + " --eval-blur -o " +
                 quote(out));
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_TRUE(contains(r.output, "near")) << r.output;
    EXPECT_FALSE(fs::exists(out));
}

TEST(cli_depth_maps, RealTumDepthFrame) {
    GDOF_REQUIRE_SHARED(depth, "rgbd/tum/depth.png");
    ScratchDir dir;
    const std::string out = dir.file("blur.exr");
    auto r = run_gdof(quote(depth) + " --depth-channel Y --depth-encoding scaled --depth-scale 13.107" + kLensFlags +
                      " --eval-blur -o " + quote(out));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    OIIO::ImageSpec spec;
    auto blur = read_pixels(out, &spec);
    auto raw = read_pixels(depth);  // normalised 0..1
    ASSERT_EQ(raw.size(), std::size_t(spec.width) * spec.height);
    const int b = spec.channelindex("blur");
    const gdof::ThinLens lens = lens_for_width(spec.width);
    std::size_t valid = 0;
    for (std::size_t i = 0; i < raw.size(); i += 97) {
        const double counts = std::round(raw[i] * 65535.0);
        const float v = blur[i * std::size_t(spec.nchannels) + std::size_t(b)];
        if (counts == 0) {  // a hole: no depth, no blur
            ASSERT_TRUE(std::isnan(v)) << "pixel " << i;
            continue;
        }
        const double expected = lens.coc_radius_px(counts / 5000.0);
        ASSERT_TRUE(std::isfinite(v));
        ASSERT_NEAR(v, expected, 1e-3 * (1 + expected)) << "pixel " << i;
        valid += counts > 0;
    }
    EXPECT_GT(valid, 100u) << "the real frame should have measured depth";
}
