// --bokeh's visibility through the defocus pipeline (defocus_layers with
// DefocusFilter::Bokeh): the paper's Figure 6 (no holes in a blurred
// interior), partial occlusion (a blurred foreground disc gets a
// semi-transparent rim about 2R wide over a sharp background), a sharp
// foreground over a blurred background left exactly as it was, and the
// radius of the rim against the analytic coverage of a blurred disc edge.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "defocus_test_helpers.h"
#include "gdof/defocus.h"

using namespace gdof;
using namespace gdof::test;

namespace {

DefocusOptions bokeh(Aperture ap = {}) {
    DefocusOptions d;
    d.filter = DefocusFilter::Bokeh;
    d.aperture = std::move(ap);
    return d;
}

}  // namespace

TEST(bokeh, BlurredInteriorHasNoHoles_Figure6) {
    const Roi display{0, 0, 300, 240};
    const Roi rect{70, 50, 230, 190};
    Layer layer = make_layer(display, display, [](int x, int y) {
        return Rgba{texture(x, y, 0), texture(x, y, 1), texture(x, y, 2), 1.0f};
    });
    const BlurField field = map_field(display, [&](int x, int y) { return rect.contains(x, y) ? 1.0f : 0.0f; }, 60.0);
    DefocusStats stats;
    auto out = defocus_layers({layer}, field, test_camera(display), bokeh(), &stats);
    ASSERT_TRUE(out) << out.message();
    EXPECT_EQ(stats.layers_bokeh, 1);
    double amin = 1e9, amax = -1e9;
    for (int y = rect.y0; y < rect.y1; ++y)
        for (int x = rect.x0; x < rect.x1; ++x) {
            amin = std::min(amin, double(out->at(3, x, y)));
            amax = std::max(amax, double(out->at(3, x, y)));
        }
    EXPECT_GE(amin, 0.99);
    EXPECT_LE(amax, 1.0 + 1e-4);
    // The interior is blurred (the texture's contrast is gone)...
    double lo = 1e9, hi = -1e9;
    for (int y = 110; y < 130; ++y)
        for (int x = 140; x < 160; ++x) {
            lo = std::min(lo, double(out->at(0, x, y)));
            hi = std::max(hi, double(out->at(0, x, y)));
        }
    EXPECT_LT(hi - lo, 0.1);
    // ... and a sharp pixel never spreads into it: far from the rectangle
    // (beyond the blurred pixels' reach) the image is untouched (to the
    // rounding of the running sums).
    for (int y = 0; y < display.y1; y += 3)
        for (int x = 0; x < display.x1; x += 3)
            if (!rect.grown(68).contains(x, y)) {  // R + the coarse level's upsampling
                ASSERT_NEAR(out->at(0, x, y), layer.image.at(0, x, y), 1e-4) << x << "," << y;
            }
}

// A blurred foreground disc over a sharp background: its coverage is the
// analytic disc-blurred disc (a semi-transparent rim 2R wide), composited
// over the background; the background beyond the rim is untouched.
TEST(bokeh, BlurredForegroundGetsASemiTransparentRim) {
    const Roi display{0, 0, 240, 200};
    const double cx = 120, cy = 100, a = 40, R = 16;
    auto in_disc = [&](int x, int y) { return std::hypot(x + 0.5 - cx, y + 0.5 - cy) < a; };
    Layer fg = make_layer(display, display, [&](int x, int y) {
        return in_disc(x, y) ? Rgba{1, 0, 0, 1} : Rgba{0, 0, 0, 0};
    }, 2.0, "fg");
    Layer bg = make_layer(display, display, [](int x, int y) {
        return Rgba{0, texture(x, y, 1), 1, 1};
    }, 10.0, "bg");
    auto field = BlurField::parse(R"({"blurfield": {"kind": "region", "shape": "box", "mode": "blur", "blur": 16,
        "min": [-1000, -1000, 1], "max": [1000, 1000, 3]}})");
    ASSERT_TRUE(field) << field.message();
    const Camera cam = test_camera(display);
    auto fg_only = defocus_layers({fg}, *field, cam, bokeh());
    ASSERT_TRUE(fg_only) << fg_only.message();
    double worst = 0.0;
    int rim = 0;
    for (int y = 0; y < display.y1; ++y)
        for (int x = 0; x < display.x1; ++x) {
            const double d = std::hypot(x + 0.5 - cx, y + 0.5 - cy);
            const double want = blurred_disc_coverage(d, a, R);
            worst = std::max(worst, std::abs(value_at(*fg_only, 3, x, y) - want));
            if (want > 0.02 && want < 0.98) ++rim;
        }
    EXPECT_LT(worst, 0.03) << "coverage against the analytic disc-blurred disc";
    // The rim spans about 2R: between a - R and a + R.
    EXPECT_GT(rim, int(0.8 * 2 * std::numbers::pi * a * 2 * R));

    auto out = defocus_layers({fg, bg}, *field, cam, bokeh());
    ASSERT_TRUE(out) << out.message();
    for (int y = 0; y < display.y1; ++y)
        for (int x = 0; x < display.x1; ++x) {
            const double d = std::hypot(x + 0.5 - cx, y + 0.5 - cy);
            ASSERT_NEAR(out->at(3, x, y), 1.0, 1e-4);
            const double c = blurred_disc_coverage(d, a, R);
            // over: fg coverage c of red, the sharp background through 1 - c.
            EXPECT_NEAR(out->at(0, x, y), c, 0.03) << x << "," << y;
            EXPECT_NEAR(out->at(1, x, y), (1 - c) * texture(x, y, 1), 0.03) << x << "," << y;
            if (d > a + R + 1) {
                ASSERT_EQ(out->at(1, x, y), texture(x, y, 1)) << x << "," << y;
            }
        }
}

// A sharp foreground over a blurred background: the foreground is exactly
// what it was (the background's spread stays behind it).
TEST(bokeh, SharpForegroundOverBlurredBackgroundIsUnchanged) {
    const Roi display{0, 0, 220, 180};
    const Roi box{60, 50, 160, 130};
    Layer fg = make_layer(display, display, [&](int x, int y) {
        return box.contains(x, y) ? Rgba{texture(x, y, 0), texture(x, y, 1), texture(x, y, 2), 1} : Rgba{0, 0, 0, 0};
    }, 2.0, "fg");
    Layer bg = make_layer(display, display, [](int x, int y) {
        return ((x / 9 + y / 9) % 2) ? Rgba{20, 20, 20, 1} : Rgba{0, 0, 0, 1};  // bright HDR checks
    }, 10.0, "bg");
    auto field = BlurField::parse(R"({"blurfield": {"kind": "region", "shape": "box", "mode": "blur", "blur": 20,
        "min": [-1000, -1000, 5], "max": [1000, 1000, 100]}})");
    ASSERT_TRUE(field) << field.message();
    Aperture hex;
    hex.kind = Aperture::Kind::Polygon;
    hex.blades = 6;
    auto out = defocus_layers({fg, bg}, *field, test_camera(display), bokeh(hex));
    ASSERT_TRUE(out) << out.message();
    double worst = 0.0;
    for (int y = box.y0; y < box.y1; ++y)
        for (int x = box.x0; x < box.x1; ++x)
            for (int c = 0; c < 4; ++c) worst = std::max(worst, std::abs(double(out->at(c, x, y)) - fg.image.at(c, x, y)));
    EXPECT_LE(worst, 1e-3);
    // Beside it the background is blurred: the checks' contrast (20) is
    // down by an order of magnitude.
    double lo = 1e9, hi = -1e9;
    for (int y = 150; y < 170; ++y)
        for (int x = 90; x < 130; ++x) lo = std::min(lo, double(out->at(0, x, y))), hi = std::max(hi, double(out->at(0, x, y)));
    EXPECT_LT(hi - lo, 3.0);
    EXPECT_NEAR(0.5 * (hi + lo), 10.0, 1.5);
}
