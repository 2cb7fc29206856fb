// A slice bound across a continuous surface (defocus_seams.cpp): a shaded
// wall receding from depth 2.0 to 2.24 under one blur, cut by a bound that
// a pair of squares below it needs (the nearer blurred, the farther sharp).
// Blurred alike, the wall's two parts must add up to the wall blurred whole:
// the reference is the same plate as one layer (gaps only), which has no
// bound, compared on the rows well away from the squares. The same for the
// plate's deep render (one sample a pixel), and with a backdrop far behind
// the wall (so the wall's far part is not the farthest layer, which backs
// the whole frame).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "defocus_test_helpers.h"
#include "gdof/image_set.h"
#include "gdof/layers.h"

using namespace gdof;
using namespace gdof::test;

namespace {

constexpr int kW = 96, kH = 96;
const Roi kWin{0, 0, kW, kH};
constexpr float kWallRadius = 5.0f;

bool in_near_square(int x, int y) { return y >= 84 && y < 92 && x >= 4 && x < 12; }
bool in_far_square(int x, int y) { return y >= 84 && y < 92 && x >= 12 && x < 20; }

double wall_z(int x) { return 2.0 + 0.24 * x / (kW - 1); }

// With `backdrop`, rows 0..2 are a green backdrop at depth 6 instead.
Image seam_scene(bool backdrop = false) {
    Image img = Image::with_channels({"R", "G", "B", "A", "Z"}, kWin);
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            const double t = double(x) / (kW - 1);
            const bool near_sq = in_near_square(x, y), far_sq = in_far_square(x, y);
            img.at(0, x, y) = near_sq ? 0.9f : far_sq ? 0.2f : float(0.1 + 0.8 * t);  // shading across the wall
            img.at(1, x, y) = near_sq || far_sq ? 0.4f : 0.3f;
            img.at(2, x, y) = near_sq || far_sq ? 0.1f : float(0.5 * (1.0 - t));
            img.at(3, x, y) = 1.0f;
            img.at(4, x, y) = float(near_sq ? 2.08 : far_sq ? 2.2 : wall_z(x));
            if (backdrop && y < 3) {
                img.at(0, x, y) = img.at(2, x, y) = 0.05f;
                img.at(1, x, y) = 0.9f;
                img.at(4, x, y) = 6.0f;
            }
        }
    return img;
}

float radius_of(int x, int y) { return in_far_square(x, y) ? 1.0f : kWallRadius; }

// A lamp at 17 on a ceiling at 0.002 receding from depth 2.0 on its first
// row to 2.6 on its last.
ImageSet lamp_on_ceiling(const Roi& win, const Roi& lamp) {
    Image img = Image::with_channels({"R", "G", "B", "A", "Z"}, win);
    for (int y = win.y0; y < win.y1; ++y)
        for (int x = win.x0; x < win.x1; ++x) {
            const float v = lamp.contains(x, y) ? 17.0f : 0.002f;
            for (int c = 0; c < 3; ++c) img.at(c, x, y) = v;
            img.at(3, x, y) = 1.0f;
            img.at(4, x, y) = float(2.0 + 0.6 * (y - win.y0) / (win.height() - 1));
        }
    ImageSet input;
    input.parts.emplace_back(std::move(img));
    return input;
}

// The plate cut by a bound (two slices of equal extent in 1 / depth: at
// depth 2.26 on the ceiling above) and as one layer (gaps only).
void cut_and_whole(const ImageSet& input, const BlurField& field, const Roi& win, Image& cut, Image& whole) {
    const Camera cam = test_camera(win);
    DefocusOptions ds;
    ds.split.mode = LayerSplit::Mode::Count;
    ds.split.count = 2;
    DefocusStats cut_stats, one_stats;
    auto c = defocus(input, field, cam, ds, &cut_stats);
    ASSERT_TRUE(c) << c.message();
    ASSERT_EQ(cut_stats.layers, 2);
    ds.split.mode = LayerSplit::Mode::Auto;
    ds.split.blur_cuts = LayerSplit::BlurCuts::Off;
    auto one = defocus(input, field, cam, ds, &one_stats);
    ASSERT_TRUE(one) << one.message();
    ASSERT_EQ(one_stats.layers, 1);
    cut = c->flat(0);
    whole = one->flat(0);
}

// A seam pixel of the scene's layer l at (x, y): inside the seam box,
// extension (covered), and over the wall (not a square), whose depth there
// is within 5% of the extension's.
void expect_seam_over_the_wall(const Layer& l, int x, int y) {
    EXPECT_TRUE(l.seam_box.contains(x, y)) << l.name << " " << x << "," << y;
    EXPECT_GT(l.image.at(3, x, y), 0.0f) << "a seam pixel is extension: " << x << "," << y;
    EXPECT_FALSE(in_near_square(x, y) || in_far_square(x, y)) << l.name << " " << x << "," << y;
    const double z = l.image.at(4, x, y);
    EXPECT_LE(std::max(z, wall_z(x)), std::min(z, wall_z(x)) * 1.05) << x << "," << y;
}

}  // namespace

// Diffusion (cut where the squares need it) and the bokeh filter (a disc;
// two slices of equal extent in 1 / depth), each against itself as one layer
// (with the backdrop: as the wall and the backdrop, which a gap parts).
TEST(plate_seams, AWallCutByABoundBlursAsTheWholeWall) {
    const Camera cam = test_camera(kWin);
    const BlurField field = map_field(kWin, radius_of);
    for (bool backdrop : {false, true})
        for (bool deep : {false, true})
            for (DefocusFilter filter : {DefocusFilter::Diffusion, DefocusFilter::Bokeh}) {
                ImageSet input;
                if (deep) input.parts.emplace_back(deep_of(seam_scene(backdrop)));
                else input.parts.emplace_back(seam_scene(backdrop));
                const std::string name = std::string(deep ? "deep" : "plate") + (backdrop ? " with a backdrop, " : ", ") +
                                         (filter == DefocusFilter::Bokeh ? "bokeh" : "diffusion");
                DefocusOptions ds;
                ds.filter = filter;
                if (filter == DefocusFilter::Bokeh) {
                    // Slices of equal extent in 1 / depth, one bound across
                    // the wall (at depth 2.18 with the backdrop, and six more
                    // beyond it, empty).
                    ds.split.mode = LayerSplit::Mode::Count;
                    ds.split.count = backdrop ? 8 : 2;
                }
                DefocusStats cut_stats, one_stats;
                auto cut = defocus(input, field, cam, ds, &cut_stats);
                ASSERT_TRUE(cut) << cut.message();
                ASSERT_GE(cut_stats.layers, backdrop ? 3 : 2) << name << ": the squares need a bound, which crosses the wall";
                ds.split.mode = LayerSplit::Mode::Auto;
                ds.split.blur_cuts = LayerSplit::BlurCuts::Off;  // gaps only: the wall is one layer
                auto one = defocus(input, field, cam, ds, &one_stats);
                ASSERT_TRUE(one) << one.message();
                ASSERT_EQ(one_stats.layers, backdrop ? 2 : 1) << name;
                // Rows 24..55: 28 px and more from the squares, whose sharp
                // radius the far layer's radii carry some way behind the near
                // one (push-pull), a difference of another kind, and 21 px
                // from the backdrop.
                double worst = 0.0;
                int wx = -1, wy = -1;
                for (int y = 24; y < 56; ++y)
                    for (int x = 0; x < kW; ++x)
                        for (int c = 0; c < 3; ++c) {
                            const double a = value_at(cut->flat(0), c, x, y), b = value_at(one->flat(0), c, x, y);
                            const double rel = std::abs(a - b) / std::max(b, 0.05);
                            if (rel > worst) worst = rel, wx = x, wy = y;
                        }
                std::printf("%s: %d layers; largest difference from one layer over the wall: %.4f (relative, at %d,%d)\n",
                            name.c_str(), cut_stats.layers, worst, wx, wy);
                // Continued from the rim instead (the extension's fill), the
                // far part differs by 0.72% beside the bound with diffusion
                // and 0.81% with the bokeh filter; taken from its own pixels,
                // 0.07% and 0.04% (the plate). The far part extended behind
                // the near one by the largest radius R only (the kernel
                // reaches 1.5 R): a band 2.8% darker (deep, diffusion), 4.1%
                // (deep, bokeh), and 5.1% for the plate with the backdrop.
                // Continued past R behind the near part: at most 0.25% but
                // for the deep render with the backdrop and the bokeh
                // filter, 0.56%, the tail of a band under the wall's top
                // edge, against the backdrop (7% 4 px below it), which is
                // there without the bound.
                EXPECT_LT(worst, 0.006) << name;
            }
}

TEST(plate_seams, OnlyExtensionBehindTheSameSurfaceIsASeam) {
    const Image img = seam_scene();
    std::vector<float> radius(img.npixels());
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) radius[std::size_t(y) * kW + std::size_t(x)] = radius_of(x, y);
    SliceOptions so;
    so.radius = radius;
    so.extend_px = 8.0;
    so.surface_reach_px = 13.0;  // and the ring past it, behind the wall only
    auto layers = layers_from_depth_map(img, so);
    ASSERT_TRUE(layers) << layers.message();
    ASSERT_GE(layers->size(), 2u);
    std::size_t seams = 0, behind_square = 0;
    for (const Layer& l : *layers) {
        const Roi w = l.image.data_window();
        if (!l.seam.empty()) {
            ASSERT_EQ(l.seam.size(), w.npixels()) << l.name;
        }
        for (int y = w.y0; y < w.y1; ++y)
            for (int x = w.x0; x < w.x1; ++x) {
                const std::size_t o = std::size_t(y - w.y0) * std::size_t(w.width()) + std::size_t(x - w.x0);
                const bool seam = !l.seam.empty() && l.seam[o];
                // The far layers' extension behind the nearer square (2.08
                // over the far square's 2.2): another surface, never a seam.
                if (in_near_square(x, y) && l.depth_near > 2.085 && l.image.at(3, x, y) > 0.0f) {
                    ++behind_square;
                    EXPECT_FALSE(seam) << l.name << " " << x << "," << y;
                }
                if (!seam) continue;
                ++seams;
                expect_seam_over_the_wall(l, x, y);
            }
    }
    std::printf("%zu seam pixels, %zu extension pixels behind the nearer square\n", seams, behind_square);
    EXPECT_GT(seams, 0u) << "the bound crosses the wall";
    EXPECT_GT(behind_square, 0u) << "the far layer extends behind the nearer square";
}

// The same scene's deep render (one sample a pixel), sliced by its front
// surface as defocus does for diffusion: its layers' seams are the
// extension behind the nearer part of the wall, as the plate's, never
// behind the nearer square (another surface); with the ring past the
// extension's reach (ExtendOptions::surface_reach_px) too.
TEST(plate_seams, ADeepImagesSeamsAreItsExtensionBehindTheSameSurface) {
    const DeepImage deep = deep_of(seam_scene());
    std::vector<float> radius(deep.total_samples());
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) radius[deep.first_sample(deep.pixel_index(x, y))] = radius_of(x, y);
    ExtendOptions ext;
    ext.extend_px = 8.0;
    ext.occluder_alpha = 0.999f;
    ext.continue_coverage = true;
    for (bool by_front_surface : {false, true})
    for (double ring : {0.0, 13.0}) {
        ext.surface_reach_px = ring;
        // Without the front surface, two slices of equal extent in 1 / depth
        // (a bound across the wall too, with extension behind it).
        LayerSplit split;
        if (!by_front_surface) split.mode = LayerSplit::Mode::Count, split.count = 2;
        auto source = deep_layer_source(deep, split, radius, &ext, {}, by_front_surface);
        ASSERT_TRUE(source) << source.message();
        std::size_t seams = 0;
        for (int i = 0; i < (*source)->size(); ++i) {
            Layer storage;
            auto made = (*source)->make(i, storage, {});
            ASSERT_TRUE(made) << made.message();
            const Layer& l = **made;
            const Roi w = l.image.data_window();
            for (int y = w.y0; y < w.y1; ++y)
                for (int x = w.x0; x < w.x1; ++x) {
                    const std::size_t o = std::size_t(y - w.y0) * std::size_t(w.width()) + std::size_t(x - w.x0);
                    if (l.seam.empty() || !l.seam[o]) continue;
                    ++seams;
                    expect_seam_over_the_wall(l, x, y);
                }
        }
        std::printf("deep, %s, %s: %d layers, %zu seam pixels\n", by_front_surface ? "by its front surface" : "two slices",
                    ring > 0.0 ? "with the ring behind its own surface" : "no ring", (*source)->size(), seams);
        if (by_front_surface) {
            EXPECT_GT(seams, 0u) << "the squares' bound crosses the wall";
        } else if (ring > 0.0) {
            EXPECT_GT(seams, 0u) << "the ring's front surface marks the seams of slices of equal extent too";
        } else {
            EXPECT_EQ(seams, 0u) << "seams are marked for the front surface's slices, or with the ring";
        }
    }
}

// A light on a receding ceiling, cut by a slice bound (ExtendOptions::
// HighlightKnee::RimMedian): the far part of the ceiling is extended behind
// the near part by a fill from its rim, and the rim holds the far half of
// the lamp. Averaged linearly, the lamp (17 over a ceiling at 0.002) rules
// the fill well beside it, and wherever the near part's blurred edge lets
// the extension show, the ceiling beside the lamp glows: "wings" along the
// bound (the benchmark's Cornell lamp cut at 3.96 m). The reference is the
// same plate as one layer, where nothing is extended.
TEST(plate_seams, ALightCutByABoundDoesNotGlowSideways) {
    constexpr int W = 192, H = 96;
    const Roi win{0, 0, W, H};
    const ImageSet input = lamp_on_ceiling(win, Roi{80, 28, 112, 60});  // the bound at row 41, across the lamp
    const BlurField field = map_field(win, [](int, int) { return 8.0f; });
    Image cut, one;
    cut_and_whole(input, field, win, cut, one);
    if (HasFatalFailure()) return;
    // Beside the lamp, 24 px and more from it (three radii: one layer puts
    // 1e-5 of the lamp there), on the lamp's rows and a radius around them.
    double worst = 0.0;
    int wx = -1, wy = -1;
    for (int y = 20; y < 68; ++y)
        for (int x = 0; x < W; ++x) {
            if (x > 80 - 24 && x < 112 + 24) continue;
            const double excess = value_at(cut, 0, x, y) - value_at(one, 0, x, y);
            if (excess > worst) worst = excess, wx = x, wy = y;
        }
    std::printf("largest excess beside the lamp: %.5f (%.3f%% of the lamp) at %d,%d\n", worst, 100.0 * worst / 17.0,
                wx, wy);
    // A linear fill: 0.0063 (three times the ceiling); a knee at 1 (deep
    // inputs' rule): 0.0014; at 8 times the rim's median: 0.00005.
    EXPECT_LT(worst, 0.1 * 0.002) << "a tenth of the ceiling";
}

// The surface onward (Layer::onward): a lamp at the largest blur on a
// receding ceiling whose rows beyond it blur less and less, cut by a bound
// below the lamp. One layer insulates the lamp's glow with those rows' small
// radii; the near part alone, blurred with its own radii extrapolated past
// its edge, threw its Gaussian tail 10 px further over them (the benchmark's
// Cornell lamp with two focal planes: 0.06, 0.03, 0.01 over a ceiling at
// 0.001 where one layer has 0.02, 0.004, 0.0003). The near part now spreads
// there with the far part's own radii: as the whole ceiling. The same for the
// plate's deep render (one sample a pixel), sliced by its front surface.
TEST(plate_seams, ALightAboveABoundSpreadsOverTheFarPartAsTheWholeCeiling) {
    constexpr int W = 128, H = 96;
    const Roi win{0, 0, W, H};
    const ImageSet plate = lamp_on_ceiling(win, Roi{48, 18, 80, 34});  // the bound between rows 41 and 42
    ImageSet deep;  // its deep render (one sample a pixel), sliced by its front surface as the plate
    deep.parts.emplace_back(deep_of(plate.flat(0)));
    // 8 px down to row 40, then less and less: 1 px from row 56.
    const BlurField field = map_field(win, [](int, int y) {
        return y <= 40 ? 8.0f : float(std::max(1.0, 8.0 - 7.0 * (y - 40) / 16.0));
    });
    for (const ImageSet* input : std::initializer_list<const ImageSet*>{&plate, &deep}) {
    const char* name = input == &deep ? "deep" : "plate";
    Image cut, one;
    cut_and_whole(*input, field, win, cut, one);
    if (HasFatalFailure()) return;
    // The far part below the lamp, from 4 px past the bound: the light on
    // it, cut against one layer, and the largest excess on a pixel.
    double light_cut = 0.0, light_one = 0.0, worst = 0.0;
    int wx = -1, wy = -1;
    for (int y = 46; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const double a = value_at(cut, 0, x, y), b = value_at(one, 0, x, y);
            light_cut += a - 0.002;
            light_one += b - 0.002;
            if (a - b > worst) worst = a - b, wx = x, wy = y;
        }
    std::printf("%s: light on the far part below the lamp: %.4f cut, %.4f one layer; largest excess %.5f at %d,%d\n",
                name, light_cut, light_one, worst, wx, wy);
    // With the near part's radii extrapolated: 2.4 times one layer's light
    // there (0.291 against 0.122), 0.0035 more on a pixel (1.8 times the
    // ceiling); now the same to 4 decimals.
    EXPECT_NEAR(light_cut, light_one, 0.02 * light_one) << name;
    EXPECT_LT(worst, 0.1 * 0.002) << name << ": a tenth of the ceiling";
    }
}
