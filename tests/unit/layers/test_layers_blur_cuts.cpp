// Auto layer split with blur cuts. A blurred object standing in front of a
// sharp part of a continuous surface (a ground plane) must spread over it as
// a Gaussian (the physical behaviour of a blurred foreground), which one
// layer cannot do (the sharp pixels insulate). Deep samples are cut wherever
// a slice's blur span would exceed the step; a plate (flat + depth) only at
// the silhouettes that need it, each bound where it hides the least light.
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

DeepImage pole_scene_deep() { return deep_of(pole_scene()); }

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

TEST(layers_blur_cuts, DeepSamplesAreCutWhereTheBlurChanges) {
    const DeepImage deep = pole_scene_deep();
    const std::vector<float> r = radius_map();  // one sample per pixel, in pixel order
    auto gaps_only = layers_from_deep(deep, LayerSplit{});
    ASSERT_TRUE(gaps_only) << gaps_only.message();
    EXPECT_EQ(gaps_only->size(), 1u) << "no gap in a continuous ground: one layer without radii";

    auto cut = layers_from_deep(deep, LayerSplit{}, r);
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
    LayerSplit fine_split;
    fine_split.blur_step = 1.0;
    auto fine = layers_from_deep(deep, fine_split, r);
    ASSERT_TRUE(fine) << fine.message();
    EXPECT_GT(fine->size(), cut->size());
    for (const Layer& l : *fine) EXPECT_LE(radius_spread(l), 1.0 + 0.2) << l.name;

    // max_layers wins over the step (the step is raised until they fit).
    LayerSplit capped_split;
    capped_split.blur_step = 0.05;
    capped_split.max_layers = 3;
    auto capped = layers_from_deep(deep, capped_split, r);
    ASSERT_TRUE(capped) << capped.message();
    EXPECT_LE(capped->size(), 3u);
    EXPECT_GE(capped->size(), 2u);
}

namespace {

// The plate layer whose slice holds depth z (-1: none).
int layer_of(const std::vector<Layer>& layers, double z) {
    for (std::size_t i = 0; i < layers.size(); ++i)
        if (z >= layers[i].slice_near && z <= layers[i].slice_far) return int(i);
    return -1;
}

}  // namespace

TEST(layers_blur_cuts, APlateIsCutOnlyAtTheSilhouettesThatNeedIt) {
    const std::vector<float> r = radius_map();
    SliceOptions so;
    so.radius = r;

    // The ground alone: continuous, its blur 0..8 px varies within one layer.
    Image ground = pole_scene();
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) ground.at(4, x, y) = float(ground_depth(x, y));
    std::vector<float> rg(r.size());
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) rg[std::size_t(y) * kW + std::size_t(x)] = float(radius_at(ground_depth(x, y)));
    SliceOptions sg;
    sg.radius = rg;
    auto alone = layers_from_depth_map(ground, sg);
    ASSERT_TRUE(alone) << alone.message();
    EXPECT_EQ(alone->size(), 1u) << "no silhouette, no cut";

    // With the pole (7.2 px) in front: the pole and every farther ground pixel
    // beside it whose radius is more than the 2 px step smaller lie in
    // different slices, the pole's nearer.
    const Image img = pole_scene();
    auto cut = layers_from_depth_map(img, so);
    ASSERT_TRUE(cut) << cut.message();
    EXPECT_GE(cut->size(), 2u);
    const int pole_layer = layer_of(*cut, kPoleDepth);
    int needs = 0;
    for (int y = 0; y < kH; ++y)
        for (int x : {kPole0 - 1, kPole1}) {
            const double z = ground_depth(x, y);
            if (z <= kPoleDepth * 1.05 || radius_at(kPoleDepth) - radius_at(z) <= 2.0) continue;
            ++needs;
            EXPECT_GT(layer_of(*cut, z), pole_layer) << "ground at depth " << z << " beside the pole";
        }
    EXPECT_GT(needs, 50);

    // A step above the pole's largest difference from the ground: no need, one layer.
    so.split.blur_step = 7.5;
    auto none = layers_from_depth_map(img, so);
    ASSERT_TRUE(none) << none.message();
    EXPECT_EQ(none->size(), 1u);
}

TEST(layers_blur_cuts, ADeepImageIsCutAtTheSilhouettesOfItsFrontSurface) {
    // What defocus does for diffusion: the bounds of the plate of its front
    // samples, not one per blur span.
    const std::vector<float> r = radius_map();
    Image ground = pole_scene();
    std::vector<float> rg(r.size());
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            ground.at(4, x, y) = float(ground_depth(x, y));
            rg[std::size_t(y) * kW + std::size_t(x)] = float(radius_at(ground_depth(x, y)));
        }
    auto by_span = layers_from_deep(deep_of(ground), LayerSplit{}, rg);
    ASSERT_TRUE(by_span) << by_span.message();
    EXPECT_GE(by_span->size(), 3u) << "span cuts: the ground's 0..8 px in strips";
    auto alone = layers_from_deep(deep_of(ground), LayerSplit{}, rg, {}, true);
    ASSERT_TRUE(alone) << alone.message();
    EXPECT_EQ(alone->size(), 1u) << "no silhouette, no cut";

    // The pole: every farther ground pixel beside it that needs a bound lies
    // behind one, as in the plate (the same bounds: one sample a pixel).
    const DeepImage deep = pole_scene_deep();
    auto cut = layers_from_deep(deep, LayerSplit{}, r, {}, true);
    ASSERT_TRUE(cut) << cut.message();
    SliceOptions so;
    so.radius = r;
    auto plate = layers_from_depth_map(pole_scene(), so);
    ASSERT_TRUE(plate) << plate.message();
    ASSERT_EQ(cut->size(), plate->size());
    for (std::size_t i = 0; i + 1 < cut->size(); ++i) EXPECT_EQ((*cut)[i].slice_far, (*plate)[i].slice_far) << i;
    // Ground pixels beside the pole that need a bound, not behind one.
    auto unseparated = [](const std::vector<Layer>& layers) {
        const int pole_layer = layer_of(layers, kPoleDepth);
        int needs = 0, wrong = 0;
        for (int y = 0; y < kH; ++y)
            for (int x : {kPole0 - 1, kPole1}) {
                const double z = ground_depth(x, y);
                if (z <= kPoleDepth * 1.05 || radius_at(kPoleDepth) - radius_at(z) <= 2.0) continue;
                ++needs;
                if (layer_of(layers, z) <= pole_layer) ++wrong;
            }
        EXPECT_GT(needs, 50);
        return wrong;
    };
    EXPECT_EQ(unseparated(*cut), 0);

    // A pixel's surface is the sample where its coverage reaches one half: a
    // faint veil (alpha 0.2) just in front of the pole over every pixel,
    // blurred like it, adds no silhouette and takes none away (were it the
    // surface, every pixel would be at its depth: no silhouette, one layer).
    DeepImage veiled({{"R"}, {"G"}, {"B"}, {"A"}, {"Z"}}, kWin, kWin);
    ASSERT_TRUE(veiled.set_sample_counts(std::vector<std::uint32_t>(std::size_t(kW) * kH, 2)));
    std::vector<float> rv(2 * r.size());
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            const std::size_t k = veiled.first_sample(veiled.pixel_index(x, y));
            const float veil[5] = {0.1f, 0.1f, 0.1f, 0.2f, 2.1f};
            for (int c = 0; c < 5; ++c) {
                veiled.samples(c)[k] = veil[c];
                veiled.samples(c)[k + 1] = deep.samples(c)[deep.first_sample(deep.pixel_index(x, y))];
            }
            rv[k] = float(radius_at(2.1));
            rv[k + 1] = r[std::size_t(y) * kW + std::size_t(x)];
        }
    auto under_veil = layers_from_deep(veiled, LayerSplit{}, rv, {}, true);
    ASSERT_TRUE(under_veil) << under_veil.message();
    EXPECT_GT(under_veil->size(), 1u);
    EXPECT_EQ(unseparated(*under_veil), 0);
}

TEST(layers_blur_cuts, APlatesBoundDoesNotHideAHighlightBehindIt) {
    // The pole needs a bound between its depth (2.2) and the ground beside it
    // where that ground is at least 2 px sharper (beyond depth 2.92). Without
    // a highlight the bound goes to 2.83, where it hides the least of the
    // uniform ground. A lamp on the ground at depths 2.78-2.86 would then lie
    // just behind it, under the nearer ground of the rows above (within a
    // blur radius) that hides its glow: with the lamp, the bound moves behind
    // it (still in range), and the lamp shares the pole's layer.
    const std::vector<float> r = radius_map();
    SliceOptions so;
    so.radius = r;
    Image img = pole_scene();
    auto plain = layers_from_depth_map(img, so);
    ASSERT_TRUE(plain) << plain.message();
    int lamp = 0;
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            const double z = ground_depth(x, y);
            if (in_pole(x) || z < 2.78 || z > 2.86) continue;
            for (int c = 0; c < 3; ++c) img.at(c, x, y) = 40.0f;
            ++lamp;
        }
    ASSERT_GT(lamp, 20);
    auto with_lamp = layers_from_depth_map(img, so);
    ASSERT_TRUE(with_lamp) << with_lamp.message();
    const int pole_layer = layer_of(*with_lamp, kPoleDepth);
    EXPECT_EQ(layer_of(*with_lamp, 2.78), pole_layer);
    EXPECT_EQ(layer_of(*with_lamp, 2.86), pole_layer);
    EXPECT_GT(with_lamp->size(), 1u) << "the pole still has its bound";
    EXPECT_NE(layer_of(*plain, 2.86), layer_of(*plain, kPoleDepth)) << "without the lamp the bound is in front of it";

    // The same bounds for any thread count (the light is summed in fixed bands).
    for (int n : {1, 3}) {
        Exec exec;
        exec.nthreads = n;
        auto again = layers_from_depth_map(img, so, exec);
        ASSERT_TRUE(again) << again.message();
        ASSERT_EQ(again->size(), with_lamp->size()) << n << " threads";
        for (std::size_t i = 0; i < again->size(); ++i) EXPECT_EQ((*again)[i].slice_far, (*with_lamp)[i].slice_far) << n;
    }
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

TEST(layers_blur_cuts, RadiiMustMatchTheSamples) {
    const DeepImage deep = pole_scene_deep();
    const std::vector<float> r = radius_map();
    const std::vector<float> short_r(r.begin(), r.end() - 1);
    auto bad = layers_from_deep(deep, LayerSplit{}, short_r);
    ASSERT_FALSE(bad);
    EXPECT_NE(bad.message().find(std::to_string(short_r.size()) + " blur radii"), std::string::npos) << bad.message();
    SliceOptions so;
    so.radius = short_r;
    auto bad_map = layers_from_depth_map(pole_scene(), so);
    ASSERT_FALSE(bad_map);
    EXPECT_NE(bad_map.message().find("blur radii"), std::string::npos) << bad_map.message();
}

// The pole (radius 7.2 px, sigma 3.6) in front of the far, nearly sharp rows
// of the same continuous ground: its red must spread beside it as a blurred
// bar does (the analytic fraction outside), for flat + Z and deep inputs.
// With gaps only (one layer) the sharp ground insulates it. Deep inputs and
// plates (flat + Z) are cut by blur by default (LayerSplit::blur_cuts), for
// diffusion both at the pole's silhouette.
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
        // At the pole's silhouette: the pole and the ground behind it.
        EXPECT_EQ(stats.layers, 2) << (deep ? "deep" : "flat");
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
    // A red card receding from depth 2.0 (left edge) to 2.24 (right) over a
    // black wall in focus (depth 6), a focal plane at 6: the card is blurred
    // (8 to 7.5 px). Apart from it, a black square at depth 2.08 stands in
    // front of one at 2.2, and the nearer is 0.24 px more blurred: with a
    // tiny blur step that silhouette needs a bound between 2.08 and 2.2,
    // which cuts the card (the card itself, continuous, needs none). A
    // sensor's 0.5% noise puts the card's pixels near that bound on both of
    // its sides at random; smoothed (the default cleanup) it spreads over the
    // wall as the clean depth does.
    constexpr int x0 = 28, x1 = 68, y0 = 16, y1 = 48;
    auto in_card = [](int x, int y) { return x >= x0 && x < x1 && y >= y0 && y < y1; };
    auto card_z = [](int x) { return 2.0 + 0.24 * (x - x0) / (x1 - x0 - 1); };
    auto true_z = [&](int x, int y) {
        if (in_card(x, y)) return card_z(x);
        if (y >= 52 && y < 60 && x >= 4 && x < 12) return 2.08;
        if (y >= 52 && y < 60 && x >= 12 && x < 20) return 2.2;
        return 6.0;
    };
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
    // The card's blur is 2 px per unit of depth from 6; vertically each
    // column spreads as a bar of 32 rows under a Gaussian of sigma r / 2.
    double analytic = 0.0;
    for (int x = x0; x < x1; ++x) analytic += gaussian_fraction_outside(y1 - y0, 2.0 * (6.0 - card_z(x)) / 2.0) / (x1 - x0);
    std::printf("analytic %.4f\n", analytic);
    EXPECT_NEAR(clean, analytic, 0.05 * analytic);
    EXPECT_NEAR(smoothed, clean, 0.01 * clean) << "as measured it is 2.5% off";
}

// A blur that is not a function of depth (a sphere of focus, a blur map):
// two poles at one depth, the right one blurred by 7.2 px, the left one and
// the whole ground sharp. Cut by blur span, the poles' depth bin holds
// mostly sharp pixels, so it is not cut from the ground and the blurred pole
// is insulated by the sharp ground beside it (its outline stays sharp: the
// Cornell box's edge over the wall under a sphere of focus). Cut at the
// silhouettes of the deep image's front surface (defocus, diffusion), the
// blurred pole spreads as the analytic blurred bar does.
TEST(layers_blur_cuts, ADeepImageWhoseBlurIsNotAFunctionOfDepthIsCutAtItsSilhouettes) {
    constexpr int kSharp0 = 8, kSharp1 = 32;  // the sharp pole's columns, 12 px left of the blurred one
    const double rp = radius_at(kPoleDepth);
    const double expected = gaussian_fraction_outside(kPole1 - kPole0, rp / 2.0);
    Image img = pole_scene();
    for (int y = 0; y < kH; ++y)
        for (int x = kSharp0; x < kSharp1; ++x) {
            img.at(0, x, y) = 0.0f, img.at(1, x, y) = 0.0f, img.at(2, x, y) = 1.0f;
            img.at(4, x, y) = float(kPoleDepth);
        }
    const DeepImage deep = deep_of(img);
    auto radius = [&](int x, int) { return in_pole(x) ? float(rp) : 0.0f; };
    const Camera cam = test_camera(kWin);
    const BlurField field = map_field(kWin, radius);

    std::vector<float> r(img.npixels());
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) r[std::size_t(y) * kW + std::size_t(x)] = radius(x, y);
    auto by_span = layers_from_deep(deep, LayerSplit{}, r);
    ASSERT_TRUE(by_span) << by_span.message();
    EXPECT_EQ(by_span->size(), 1u) << "the blur span of every depth bin is under the step";

    // Red beside the blurred pole (not over the sharp one), over the rows
    // where the ground is behind it (from depth 2.58: row 16 on).
    auto fraction_outside = [&](const Image& out) {
        double in = 0.0, outside = 0.0;
        for (int y = 16; y < kH; ++y)
            for (int x = kSharp1; x < kW; ++x) (in_pole(x) ? in : outside) += value_at(out, 0, x, y);
        return outside / (in + outside);
    };
    ImageSet input;
    input.parts.emplace_back(deep);
    DefocusStats stats;
    auto out = defocus(input, field, cam, DefocusOptions{}, &stats);
    ASSERT_TRUE(out) << out.message();
    const double f = fraction_outside(out->flat(0));
    std::printf("deep, blur map: %d layers, fraction outside %.4f (analytic %.4f)\n", stats.layers, f, expected);
    EXPECT_GE(stats.layers, 2);
    EXPECT_NEAR(f, expected, 0.05 * expected);
    // The sharp pole stays sharp: no red on it, and its blue within its columns.
    double blue_in = 0.0, blue_out = 0.0;
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kPole0; ++x) (x >= kSharp0 && x < kSharp1 ? blue_in : blue_out) += value_at(out->flat(0), 2, x, y);
    EXPECT_LT(blue_out, 0.01 * blue_in);
}

