// Method 4 through the defocus pipeline (DefocusFilter::Vibrate): the thin-
// lens special case against the analytic blurred disc, no cracks, energy
// kept without occlusion, no ghosts with few samples and convergence with
// many, partial occlusion from visibility, a swirl on its arc, a depth
// displacement that changes the occlusion order, and the same bits for any
// thread count.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

#include "defocus_test_helpers.h"
#include "gdof/defocus.h"
#include "gdof/psf_field.h"

using namespace gdof;
using namespace gdof::test;

namespace {

DefocusOptions vibrate(int samples, const std::string& field_json = {}) {
    DefocusOptions d;
    d.filter = DefocusFilter::Vibrate;
    d.vibrate.samples = samples;
    if (!field_json.empty()) {
        auto f = PsfField::parse(field_json);
        EXPECT_TRUE(f) << f.message();
        if (f) d.psf_field = f.value();
    }
    return d;
}


Result<Image> run(const std::vector<Layer>& layers, const BlurField& field, const Roi& display, const DefocusOptions& o,
                  DefocusStats* stats = nullptr, int threads = 0) {
    Exec e;
    e.nthreads = threads;
    return defocus_layers(layers, field, test_camera(display), o, stats, e);
}

}  // namespace

// The thin-lens special case: `defocus` with a disc spreads an opaque disc's
// coverage exactly as the analytic disc kernel does.
TEST(vibrate, DefocusDiscMatchesTheAnalyticDiscKernel) {
    const Roi display{0, 0, 120, 120};
    const double a = 25.0, R = 10.0, cx = 60.0, cy = 60.0;
    Layer disc = make_layer(display, display, [&](int x, int y) {
        const float in = std::hypot(x + 0.5 - cx, y + 0.5 - cy) < a ? 1.0f : 0.0f;
        return Rgba{in, in, in, in};
    });
    DefocusStats stats;
    auto out = run({disc}, constant_field(display, R), display, vibrate(256), &stats);
    ASSERT_TRUE(out) << out.message();
    EXPECT_EQ(stats.layers_vibrated, 1);
    EXPECT_NEAR(stats.vibrate.samples, 256, 3);
    double worst = 0.0;
    for (int y = 0; y < 120; ++y)
        for (int x = 0; x < 120; ++x) {
            const double d = std::hypot(x + 0.5 - cx, y + 0.5 - cy);
            worst = std::max(worst, std::abs(value_at(*out, 3, x, y) - blurred_disc_coverage(d, a, R)));
        }
    // The pixel grid's own anti-aliasing and the prefilter (sigma ~0.6 px)
    // soften the analytic edge slightly.
    EXPECT_LT(worst, 0.06);
}

// No cracks: an opaque plane under a non-uniform warp (blur ramp plus a
// strong swirl) stays opaque everywhere.
TEST(vibrate, OpaquePlaneDoesNotCrack) {
    const Roi display{0, 0, 160, 120};
    Layer plane = make_layer(display, display, [](int x, int y) {
        return Rgba{texture(x, y, 0), texture(x, y, 1), texture(x, y, 2), 1.0f};
    });
    const BlurField field = map_field(display, [](int x, int) { return float(x) / 160.0f; }, 20.0);
    auto out = run({plane}, field, display,
                   vibrate(16, R"({"psf_field": {"kind": "sum", "children": [{"kind": "defocus"},
                                  {"kind": "swirl", "strength": 3}]}})"));
    ASSERT_TRUE(out) << out.message();
    double amin = 1e9;
    int ax = -1, ay = -1;
    for (int y = 0; y < 120; ++y)
        for (int x = 0; x < 160; ++x)
            if (value_at(*out, 3, x, y) < amin) amin = value_at(*out, 3, x, y), ax = x, ay = y;
    EXPECT_GE(amin, 0.999) << "at " << ax << "," << ay;
    // An opaque rectangle under a constant blur: opaque wherever every
    // aperture sample keeps it covered, farther than R inside its outline,
    // plus the prefilter's reach (3 sigma; sigma = 0.7 x the spacing of 64
    // samples x R = 1.2 px).
    Layer rect = make_layer(display, display, [](int x, int y) {
        const float in = (x >= 40 && x < 120 && y >= 30 && y < 90) ? 1.0f : 0.0f;
        return Rgba{in * 0.3f, in * 0.6f, in, in};
    });
    auto r = run({rect}, constant_field(display, 8.0), display, vibrate(64));
    ASSERT_TRUE(r) << r.message();
    amin = 1e9;
    for (int y = 42; y < 78; ++y)
        for (int x = 52; x < 108; ++x) amin = std::min(amin, value_at(*r, 3, x, y));
    EXPECT_GE(amin, 0.999);
}

// Energy: without occlusion every sample is a moved copy, so the light is kept.
TEST(vibrate, EnergyIsKeptWithoutOcclusion) {
    const Roi display{0, 0, 140, 110};
    Layer l = make_layer(display, display, [](int x, int y) {
        if (x == 50 && y == 40) return Rgba{800.0f, 400.0f, 100.0f, 1.0f};  // an HDR point
        const bool patch = x >= 70 && x < 100 && y >= 50 && y < 75;
        const float a = patch ? 0.5f + 0.5f * texture(x, y, 3) : 0.0f;
        return Rgba{a * texture(x, y, 0), a * texture(x, y, 1), a * texture(x, y, 2), a};
    });
    double in[4];
    for (int c = 0; c < 4; ++c) in[c] = channel_sum(l.image, c);
    auto out = run({l}, constant_field(display, 12.0), display, vibrate(64));
    ASSERT_TRUE(out) << out.message();
    for (int c = 0; c < 4; ++c) EXPECT_NEAR(channel_sum(*out, c) / in[c], 1.0, 1e-3) << "channel " << c;
}

// No ghosts: one HDR point at R = 30 with 64 samples is one smooth disc, not
// 64 dots; and the result converges to the 4096-sample one.
TEST(vibrate, FewSamplesDoNotGhostAndConverge) {
    const Roi display{0, 0, 90, 90};
    Layer l = make_layer(display, display, [](int x, int y) {
        return x == 45 && y == 45 ? Rgba{1000.0f, 1000.0f, 1000.0f, 1.0f} : Rgba{0, 0, 0, 0};
    });
    const BlurField field = constant_field(display, 30.0);
    auto at = [&](int n) {
        auto out = run({l}, field, display, vibrate(n));
        EXPECT_TRUE(out) << out.message();
        return std::move(out).value();
    };
    const Image r64 = at(64);
    double lo = 1e30, hi = 0.0, sum = 0.0;
    int count = 0;
    for (int y = 0; y < 90; ++y)
        for (int x = 0; x < 90; ++x)
            if (std::hypot(x + 0.5 - 45.5, y + 0.5 - 45.5) < 0.8 * 30.0) {
                const double v = value_at(r64, 0, x, y);
                lo = std::min(lo, v);
                hi = std::max(hi, v);
                sum += v;
                ++count;
            }
    const double mean = sum / count;
    std::printf("64 samples, R = 30: inside 0.8 R intensity min %.4f max %.4f mean %.4f (expected %.4f): %.1f%%\n", lo,
                hi, mean, 1000.0 / (std::numbers::pi * 900.0), 100.0 * (hi - lo) / mean);
    EXPECT_LE((hi - lo) / mean, 0.30);
    EXPECT_NEAR(mean, 1000.0 / (std::numbers::pi * 900.0), 0.1 * mean);
    // Convergence: relative L1 against 4096 samples.
    const Image ref = at(4096);
    const double total = channel_sum(ref, 0);
    double prev = 1e30;
    for (int n : {16, 64, 256, 1024}) {
        const Image r = n == 64 ? r64 : at(n);
        double e = 0.0;
        for (std::size_t i = 0; i < r.npixels(); ++i) e += std::abs(double(r.plane(0)[i]) - double(ref.plane(0)[i]));
        e /= total;
        std::printf("samples %5d: relative L1 against 4096 samples %.4f\n", n, e);
        EXPECT_LT(e, prev * 0.75);
        prev = e;
    }
    // The error is the prefilter's (sigma ~ 1/sqrt(samples)): halved per 4x samples.
    EXPECT_LT(prev, 0.08);
}

// Partial occlusion from visibility: a blurred foreground over a sharp
// background gets a semi-transparent rim whose coverage is the analytic
// blurred disc edge; a sharp foreground stays exactly itself over a moving
// (blurred) background.
TEST(vibrate, BlurredForegroundHasASemiTransparentRimAndSharpForegroundOccludes) {
    const Roi display{0, 0, 120, 120};
    const double a = 20.0, R = 9.0;
    Layer fg = make_layer(display, display, [&](int x, int y) {
        const float in = std::hypot(x + 0.5 - 60, y + 0.5 - 60) < a ? 1.0f : 0.0f;
        return Rgba{in, 0, 0, in};
    }, 2.0, "fg");
    Layer bg = make_layer(display, display, [](int, int) { return Rgba{0, 0, 1, 1}; }, 10.0, "bg");
    // Blurred where the foreground is (depth 2), sharp behind.
    auto field = BlurField::parse(R"({"blurfield": {"kind": "focal_planes", "depths": [10], "max_blur": 9, "slope": 1000,
                                       "interpolation": "linear"}})");
    ASSERT_TRUE(field) << field.message();
    DefocusStats stats;
    auto out = run({fg, bg}, *field, display, vibrate(256), &stats);
    ASSERT_TRUE(out) << out.message();
    ASSERT_NEAR(stats.max_radius_px, R, 0.5);
    int rim = 0;
    double worst = 0.0;
    for (int y = 0; y < 120; ++y)
        for (int x = 0; x < 120; ++x) {
            const double d = std::hypot(x + 0.5 - 60, y + 0.5 - 60);
            const double red = value_at(*out, 0, x, y), blue = value_at(*out, 2, x, y);
            EXPECT_NEAR(value_at(*out, 3, x, y), 1.0, 1e-3);
            EXPECT_NEAR(red + blue, 1.0, 1e-3);  // the background shows exactly where the foreground does not
            worst = std::max(worst, std::abs(red - blurred_disc_coverage(d, a, stats.max_radius_px)));
            if (red > 0.1 && red < 0.9) ++rim;
        }
    EXPECT_LT(worst, 0.06);
    EXPECT_GT(rim, int(2.0 * std::numbers::pi * a * 0.8 * R));  // a band ~2R wide all round
    // Swapped focus: the foreground sharp, the background blurred.
    Layer tex = make_layer(display, display, [](int x, int y) {
        return Rgba{texture(x, y, 0), texture(x, y, 1), texture(x, y, 2), 1.0f};
    }, 10.0, "bg");
    auto near_focus = BlurField::parse(R"({"blurfield": {"kind": "focal_planes", "depths": [2], "max_blur": 9, "slope": 1000,
                                            "interpolation": "linear"}})");
    ASSERT_TRUE(near_focus) << near_focus.message();
    auto sharp = run({fg, tex}, *near_focus, display, vibrate(64));
    ASSERT_TRUE(sharp) << sharp.message();
    for (int y = 0; y < 120; ++y)
        for (int x = 0; x < 120; ++x)
            if (std::hypot(x + 0.5 - 60, y + 0.5 - 60) < a) {
                ASSERT_NEAR(value_at(*sharp, 0, x, y), 1.0, 1e-5) << x << "," << y;
                ASSERT_NEAR(value_at(*sharp, 2, x, y), 0.0, 1e-5) << x << "," << y;
            }
}

// A point's swirl lands on the arc of its circle about the frame centre,
// spread over the predicted angle (u_t of a uniform disc: standard deviation
// half the arc's half-length).
TEST(vibrate, SwirlPointLandsOnThePredictedArc) {
    const Roi display{0, 0, 200, 200};
    const int px = 140, py = 100;  // 40 px right of the centre (100, 100)
    Layer l = make_layer(display, display, [&](int x, int y) {
        return x == px && y == py ? Rgba{100.0f, 100.0f, 100.0f, 1.0f} : Rgba{0, 0, 0, 0};
    });
    const double B = 10.0, strength = 5.0, rho = std::hypot(px + 0.5 - 100.0, py + 0.5 - 100.0);
    const double half_diag = 0.5 * std::hypot(200.0, 200.0);
    const double theta = strength * B * (rho / half_diag) / rho;  // the arc's half-angle
    auto out = run({l}, constant_field(display, B), display,
                   vibrate(256, R"({"psf_field": {"kind": "swirl", "strength": 5}})"));
    ASSERT_TRUE(out) << out.message();
    double total = 0, on_arc = 0, m2 = 0;
    for (int y = 0; y < 200; ++y)
        for (int x = 0; x < 200; ++x) {
            const double v = value_at(*out, 0, x, y);
            if (v == 0.0) continue;
            total += v;
            const double dx = x + 0.5 - 100.0, dy = y + 0.5 - 100.0;
            const double ang = std::atan2(dy, dx) - std::atan2(py + 0.5 - 100.0, px + 0.5 - 100.0);
            // Within 3.5 px of the arc: the prefilter's 3 sigma (sigma = 0.7 x
            // the samples' spacing along the arc, 1.1 px here) and the pixel.
            if (std::abs(std::hypot(dx, dy) - rho) <= 3.5 && std::abs(ang) <= theta + 3.5 / rho) on_arc += v;
            m2 += v * ang * ang;
        }
    EXPECT_NEAR(total, 100.0, 0.1);
    EXPECT_GT(on_arc / total, 0.97);
    const double sd = std::sqrt(m2 / total);
    std::printf("swirl: arc half-angle %.4f rad, angular sd %.4f (predicted %.4f)\n", theta, sd, theta / 2.0);
    EXPECT_NEAR(sd, theta / 2.0, 0.15 * theta / 2.0 + 0.5 / rho);
}

// A `depth` displacement changes the occlusion order where it applies: a far
// green layer pulled in front of a near red square inside a box region, and
// left behind it elsewhere.
TEST(vibrate, DepthDisplacementChangesTheOcclusionOrder) {
    const Roi display{0, 0, 100, 60};
    Layer red = make_layer(display, display, [](int x, int y) {
        const bool in = (x >= 10 && x < 40 && y >= 15 && y < 45) || (x >= 60 && x < 90 && y >= 15 && y < 45);
        return in ? Rgba{1, 0, 0, 1} : Rgba{0, 0, 0, 0};
    }, 5.0, "red");
    Layer green = make_layer(display, display, [](int, int) { return Rgba{0, 1, 0, 1}; }, 10.0, "green");
    // The weight: 1 on the left half of the frame (an image_map) times a box
    // around depth 10 (a region): the green layer's left half moves 8 units
    // nearer (to depth 2), the red squares stay.
    auto half = std::make_shared<Image>(Image::with_channels({"Y"}, display));
    for (int y = 0; y < 60; ++y)
        for (int x = 0; x < 50; ++x) half->at(0, x, y) = 1.0f;
    BlurField::Context ctx;
    ctx.images["left"] = half;
    auto field = PsfField::parse(R"({"psf_field": {"kind": "blend",
        "weight": {"kind": "mul", "children": [{"kind": "image_map", "image": "left"},
                   {"kind": "region", "shape": "box", "min": [-1000, -1000, 9], "max": [1000, 1000, 11], "mode": "blur", "blur": 1}]},
        "children": [{"kind": "depth"}, {"kind": "depth", "offset": -8}]}})", ctx);
    ASSERT_TRUE(field) << field.message();
    DefocusOptions o = vibrate(4);
    o.psf_field = *field;
    auto out = run({red, green}, constant_field(display, 0.0), display, o);
    ASSERT_TRUE(out) << out.message();
    for (int y = 20; y < 40; ++y) {
        for (int x = 15; x < 35; ++x) {  // left square: green now in front
            ASSERT_NEAR(value_at(*out, 1, x, y), 1.0, 1e-4) << x << "," << y;
            ASSERT_NEAR(value_at(*out, 0, x, y), 0.0, 1e-4) << x << "," << y;
        }
        for (int x = 65; x < 85; ++x) {  // right square: red still in front
            ASSERT_NEAR(value_at(*out, 0, x, y), 1.0, 1e-4) << x << "," << y;
            ASSERT_NEAR(value_at(*out, 1, x, y), 0.0, 1e-4) << x << "," << y;
        }
    }
}

TEST(vibrate, SameBitsForAnyThreadCount) {
    const Roi display{0, 0, 96, 64};
    Layer fg = make_layer(display, display, [](int x, int y) {
        const float in = std::hypot(x - 40.0, y - 30.0) < 15 ? 1.0f : 0.0f;
        return Rgba{in * texture(x, y, 0), in * 0.5f, in * texture(x, y, 2), in};
    }, 3.0);
    Layer bg = make_layer(display, display, [](int x, int y) {
        return Rgba{texture(x, y, 0), texture(x, y, 1), texture(x, y, 2), 1.0f};
    }, 9.0);
    const BlurField field = map_field(display, [](int x, int y) { return float(x + y) / 160.0f; }, 12.0);
    const std::string json = R"({"psf_field": {"kind": "sum", "children": [{"kind": "defocus"}, {"kind": "swirl"},
                                  {"kind": "depth", "distance": 2}]}})";
    auto one = run({fg, bg}, field, display, vibrate(9, json), nullptr, 1);
    auto two = run({fg, bg}, field, display, vibrate(9, json), nullptr, 2);
    ASSERT_TRUE(one) << one.message();
    ASSERT_TRUE(two) << two.message();
    EXPECT_TRUE(bit_identical(*one, *two));
}

TEST(vibrate, BadSettingsAreErrorsNamingTheCulprit) {
    const Roi display{0, 0, 16, 16};
    Layer l = make_layer(display, display, [](int, int) { return Rgba{1, 1, 1, 1}; });
    DefocusOptions o = vibrate(0);
    o.vibrate.samples = -1;
    auto r = run({l}, constant_field(display, 2.0), display, o);
    ASSERT_FALSE(r);
    EXPECT_NE(r.message().find("samples"), std::string::npos);
    o = vibrate(8);
    o.aperture.cats_eye = 1.5;  // 0..1 (a cat's eye in range works: test_vibrate_cats_eye)
    r = run({l}, constant_field(display, 2.0), display, o);
    ASSERT_FALSE(r);
    EXPECT_NE(r.message().find("cats_eye"), std::string::npos);
}
