// Auto layer split with blur cuts: a continuous depth range (a ground plane)
// is cut where its blur changes, so a blurred object standing in front of a
// sharp part of the same continuous surface spreads over it as a Gaussian
// (the physical behaviour of a blurred foreground), which one layer cannot
// do (the sharp pixels insulate).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "defocus_test_helpers.h"
#include "gdof/image_set.h"
#include "gdof/layers.h"

using namespace gdof;
using namespace gdof::test;

namespace {

constexpr int kW = 96, kH = 64;
const Roi kWin{0, 0, kW, kH};
constexpr int kPole0 = 44, kPole1 = 52;  // the pole's columns
constexpr double kPoleDepth = 2.2;

// Ground: depth even in 1/depth from 2 (first pixel) to 20 (last), in scan
// order, so every depth between is present (no gap: a continuous surface).
double ground_depth(int x, int y) {
    return 1.0 / (0.5 + (0.05 - 0.5) * (double(y) * kW + x) / (double(kW) * kH - 1));
}
// A thin lens focused at 20: radius 8 px at depth 2, 0 at 20.
double radius_at(double depth) { return 8.0 * (1.0 / depth - 0.05) / 0.45; }
bool in_pole(int x) { return x >= kPole0 && x < kPole1; }
double depth_of(int x, int y) { return in_pole(x) ? kPoleDepth : ground_depth(x, y); }

// Opaque RGBA + Z: a red pole (all rows) in front of a green ground.
Image pole_scene() {
    Image img = Image::with_channels({"R", "G", "B", "A", "Z"}, kWin);
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            img.at(0, x, y) = in_pole(x) ? 1.0f : 0.0f;
            img.at(1, x, y) = in_pole(x) ? 0.0f : 1.0f;
            img.at(2, x, y) = 0.0f;
            img.at(3, x, y) = 1.0f;
            img.at(4, x, y) = float(depth_of(x, y));
        }
    return img;
}

DeepImage pole_scene_deep() {
    const Image flat = pole_scene();
    DeepImage d({{"R"}, {"G"}, {"B"}, {"A"}, {"Z"}}, kWin, kWin);
    EXPECT_TRUE(d.set_sample_counts(std::vector<std::uint32_t>(flat.npixels(), 1)));
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            const std::size_t k = d.first_sample(d.pixel_index(x, y));
            for (int c = 0; c < 5; ++c) d.samples(c)[k] = flat.at(c, x, y);
        }
    return d;
}

std::vector<float> radius_map() {
    std::vector<float> r(std::size_t(kW) * kH);
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) r[std::size_t(y) * kW + std::size_t(x)] = float(radius_at(depth_of(x, y)));
    return r;
}

// Fraction of a bar of width w, blurred by a Gaussian of sigma s, that lies
// outside the bar (1D, numerically).
double gaussian_fraction_outside(double w, double s) {
    const int n = 2000;
    double inside = 0.0;
    for (int i = 0; i < n; ++i) {
        const double x = (i + 0.5) * w / n;
        inside += 0.5 * (std::erf((w - x) / (s * std::sqrt(2.0))) + std::erf(x / (s * std::sqrt(2.0))));
    }
    return 1.0 - inside / n;
}

// Radius spread (max - min of radius_at over the layer's covered pixels).
double radius_spread(const Layer& l) {
    double lo = 1e300, hi = -1e300;
    const Image& img = l.image;
    const int a = img.channel_index("A"), z = img.channel_index("Z");
    const Roi w = img.data_window();
    for (int y = w.y0; y < w.y1; ++y)
        for (int x = w.x0; x < w.x1; ++x)
            if (img.at(a, x, y) > 0.0f) {
                const double r = radius_at(img.at(z, x, y));
                lo = std::min(lo, r), hi = std::max(hi, r);
            }
    return hi >= lo ? hi - lo : 0.0;
}

}  // namespace

TEST(layers_blur_cuts, ContinuousDepthIsCutWhereTheBlurChanges) {
    const Image img = pole_scene();
    const std::vector<float> r = radius_map();
    SliceOptions so;
    auto gaps_only = layers_from_depth_map(img, so);
    ASSERT_TRUE(gaps_only) << gaps_only.message();
    EXPECT_EQ(gaps_only->size(), 1u) << "no gap in a continuous ground: one layer without radii";

    so.radius = r;
    auto cut = layers_from_depth_map(img, so);
    ASSERT_TRUE(cut) << cut.message();
    // Automatic step: max(2 px, 8 px / 4) = 2 px; radii 0..8 -> about 4 layers.
    EXPECT_GE(cut->size(), 3u);
    EXPECT_LE(cut->size(), 6u);
    for (const Layer& l : *cut) {
        // Bin means within the step; a pixel may differ from its bin's mean
        // by the radius change over one bin (under 0.2 px here).
        EXPECT_LE(radius_spread(l), 2.0 + 0.2) << l.name;
    }

    // An explicit step: 1 px gives about twice as many layers, each within 1 px.
    so.split.blur_step = 1.0;
    auto fine = layers_from_depth_map(img, so);
    ASSERT_TRUE(fine) << fine.message();
    EXPECT_GT(fine->size(), cut->size());
    for (const Layer& l : *fine) EXPECT_LE(radius_spread(l), 1.0 + 0.2) << l.name;

    // max_layers wins over the step (the step is raised until they fit).
    so.split.blur_step = 0.05;
    so.split.max_layers = 3;
    auto capped = layers_from_depth_map(img, so);
    ASSERT_TRUE(capped) << capped.message();
    EXPECT_LE(capped->size(), 3u);
    EXPECT_GE(capped->size(), 2u);
}

TEST(layers_blur_cuts, ConstantBlurAddsNoCutToTheGaps) {
    // Two depth clusters (4 and 9) under one constant blur: exactly the gap's two layers.
    Image img = Image::with_channels({"R", "G", "B", "A", "Z"}, kWin);
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            for (int c = 0; c < 4; ++c) img.at(c, x, y) = 1.0f;
            img.at(4, x, y) = x < kW / 2 ? 4.0f + 0.01f * float(y) : 9.0f + 0.02f * float(y);
        }
    const std::vector<float> r(img.npixels(), 5.0f);
    SliceOptions so;
    so.radius = r;
    auto layers = layers_from_depth_map(img, so);
    ASSERT_TRUE(layers) << layers.message();
    EXPECT_EQ(layers->size(), 2u);
}

TEST(layers_blur_cuts, DeepAndDepthMapAgreeAndRadiiMustMatchTheSamples) {
    const DeepImage deep = pole_scene_deep();
    const std::vector<float> r = radius_map();  // one sample per pixel, in pixel order
    auto from_deep = layers_from_deep(deep, LayerSplit{}, r);
    ASSERT_TRUE(from_deep) << from_deep.message();
    SliceOptions so;
    so.radius = r;
    auto from_map = layers_from_depth_map(pole_scene(), so);
    ASSERT_TRUE(from_map) << from_map.message();
    ASSERT_EQ(from_deep->size(), from_map->size());
    for (std::size_t i = 0; i < from_deep->size(); ++i)
        EXPECT_DOUBLE_EQ((*from_deep)[i].slice_near, (*from_map)[i].slice_near) << i;

    const std::vector<float> short_r(r.begin(), r.end() - 1);
    auto bad = layers_from_deep(deep, LayerSplit{}, short_r);
    ASSERT_FALSE(bad);
    EXPECT_NE(bad.message().find(std::to_string(short_r.size()) + " blur radii"), std::string::npos) << bad.message();
    so.radius = short_r;
    auto bad_map = layers_from_depth_map(pole_scene(), so);
    ASSERT_FALSE(bad_map);
    EXPECT_NE(bad_map.message().find("blur radii"), std::string::npos) << bad_map.message();
}

// The pole (radius 7.2 px, sigma 3.6) in front of the far, nearly sharp rows
// of the same continuous ground: its red must spread beside it as a blurred
// bar does (the analytic fraction outside), for flat + Z and deep inputs.
// With gaps only (one layer) the sharp ground insulates it. Deep inputs are
// cut by blur by default, plates (flat + Z) too (LayerSplit::blur_cuts).
TEST(layers_blur_cuts, BlurredObjectSpreadsOverTheSharpPartOfAContinuousSurface) {
    const double rp = radius_at(kPoleDepth);
    const double expected = gaussian_fraction_outside(kPole1 - kPole0, rp / 2.0);
    const Camera cam = test_camera(kWin);
    const std::vector<float> rmap = radius_map();
    const BlurField field = map_field(kWin, [&](int x, int y) { return rmap[std::size_t(y) * kW + std::size_t(x)]; });

    // Red outside the pole's columns / all red, over the far rows (ground radius < 1 px).
    auto fraction_outside = [&](const Image& out) {
        double in = 0.0, outside = 0.0;
        for (int y = 56; y < kH; ++y)
            for (int x = 0; x < kW; ++x) (in_pole(x) ? in : outside) += value_at(out, 0, x, y);
        return outside / (in + outside);
    };
    for (bool deep : {false, true}) {
        ImageSet input;
        if (deep) input.parts.emplace_back(pole_scene_deep());
        else input.parts.emplace_back(pole_scene());
        DefocusOptions ds;
        DefocusStats stats;
        // Default auto cuts plates and deep inputs by blur alike. This
        // ground recedes 11% in depth per pixel row: the ground beside the
        // pole lies between the pole and the next row, and the mixed-pixel
        // step gives it the pole's depth (a known limit, docs/diffusion.md),
        // so the layering is tested without it.
        ds.cleanup.mixed_pixels = false;
        auto cut = defocus(input, field, cam, ds, &stats);
        ASSERT_TRUE(cut) << cut.message();
        EXPECT_GE(stats.layers, 3) << (deep ? "deep" : "flat");
        const double f_cut = fraction_outside(cut->flat(0));
        std::printf("%s: %d layers, fraction outside %.4f (analytic %.4f)\n", deep ? "deep" : "flat", stats.layers,
                    f_cut, expected);
        EXPECT_NEAR(f_cut, expected, 0.05 * expected) << (deep ? "deep" : "flat") << ": blurred bar's fraction outside";

        ds.split.blur_cuts = LayerSplit::BlurCuts::Off;  // gaps only: one layer
        auto one = defocus(input, field, cam, ds, &stats);
        ASSERT_TRUE(one) << one.message();
        EXPECT_EQ(stats.layers, 1);
        const double f_one = fraction_outside(one->flat(0));
        std::printf("%s, gaps only: 1 layer, fraction outside %.4f\n", deep ? "deep" : "flat", f_one);
        EXPECT_LT(f_one, 0.5 * expected) << (deep ? "deep" : "flat");
    }
}

TEST(layers_blur_cuts, ANoisySurfaceAtABlurCutSpreadsAsItsCleanDepthDoes) {
    // A red card almost facing the camera (depth 2.00 at its left edge, 2.06
    // at its right) over a black wall in focus (depth 6), a focal plane at 6:
    // the card is blurred, and the split cuts it where its blur changes. A
    // sensor's 0.5% noise puts its pixels on both sides of that cut at
    // random; smoothed (the default cleanup) it spreads over the wall as the
    // clean depth does.
    constexpr int x0 = 28, x1 = 68, y0 = 16, y1 = 48;
    auto in_card = [](int x, int y) { return x >= x0 && x < x1 && y >= y0 && y < y1; };
    auto true_z = [&](int x, int y) { return in_card(x, y) ? 2.0 + 0.06 * (x - x0) / (x1 - x0 - 1) : 6.0; };
    std::uint64_t s = 99;
    auto gaussian = [&] {
        auto u01 = [&] {
            s = s * 6364136223846793005ull + 1442695040888963407ull;
            return double(s >> 11) * (1.0 / 9007199254740992.0);
        };
        const double u = std::max(u01(), 1e-300), v = u01();
        return std::sqrt(-2.0 * std::log(u)) * std::cos(6.283185307179586 * v);
    };
    auto scene = [&](bool noisy) {
        Image img = Image::with_channels({"R", "G", "B", "A", "Z"}, kWin);
        for (int y = 0; y < kH; ++y)
            for (int x = 0; x < kW; ++x) {
                img.at(0, x, y) = in_card(x, y) ? 1.0f : 0.0f;
                img.at(3, x, y) = 1.0f;
                img.at(4, x, y) = float(true_z(x, y) * (noisy ? 1.0 + 0.005 * gaussian() : 1.0));
            }
        ImageSet set;
        set.parts.emplace_back(std::move(img));
        return set;
    };
    auto field = BlurField::parse(R"({"blurfield": {"kind": "focal_planes", "depths": [6], "slope": 2}})");
    ASSERT_TRUE(field) << field.message();
    const Camera cam = test_camera(kWin);
    // Red that left the card: over the wall above and below it.
    auto spread = [&](const Image& out) {
        double outside = 0.0, all = 0.0;
        for (int y = 0; y < kH; ++y)
            for (int x = x0; x < x1; ++x) {
                const double r = value_at(out, 0, x, y);
                all += r;
                if (!in_card(x, y)) outside += r;
            }
        return outside / all;
    };
    auto run = [&](const ImageSet& in, bool smooth, int* layers) {
        DefocusOptions ds;
        ds.split.blur_step = 0.05;  // a cut (or more) through the card
        ds.cleanup.smooth_noise = smooth;
        DefocusStats st;
        auto out = defocus(in, *field, cam, ds, &st);
        EXPECT_TRUE(out) << out.message();
        *layers = st.layers;
        return out ? spread(out->flat(0)) : 0.0;
    };
    int n_clean = 0, n_noisy = 0, n_raw = 0;
    const ImageSet noisy = scene(true);
    const double clean = run(scene(false), true, &n_clean);
    const double smoothed = run(noisy, true, &n_noisy);
    const double raw = run(noisy, false, &n_raw);
    std::printf("red outside the card: clean depth %.4f (%d layers), noisy smoothed %.4f (%d), noisy as measured %.4f (%d)\n",
                clean, n_clean, smoothed, n_noisy, raw, n_raw);
    ASSERT_GE(n_clean, 3) << "the card is cut";
    // The card's blur is 2 px per unit of depth from 6: 7.94 px on average;
    // vertically it spreads as a bar of 32 rows under a Gaussian of sigma r / 2.
    const double analytic = gaussian_fraction_outside(y1 - y0, 7.94 / 2.0);
    std::printf("analytic %.4f\n", analytic);
    EXPECT_NEAR(clean, analytic, 0.05 * analytic);
    EXPECT_NEAR(smoothed, clean, 0.05 * clean) << "as measured it is 10% off";
}
