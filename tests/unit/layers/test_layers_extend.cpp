// Layers extended behind the nearer layers that hide them (deep renders keep
// only visible samples, so the background behind an opaque foreground is
// missing until it is extended).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "gdof/layers.h"

using namespace gdof;

namespace {

// A deep image: a background wall at depth 10 (colour 0.2, 0.4, 0.6) with no
// samples behind an opaque foreground square at depth 2 (x, y in [20, 30)),
// and a semi-transparent foreground disc (alpha 0.5) over empty space at the
// right (no background there at all).
DeepImage scene() {
    const Roi win{0, 0, 64, 48};
    DeepImage d({{"R", PixelType::Float}, {"G", PixelType::Float}, {"B", PixelType::Float}, {"A", PixelType::Float},
                 {"Z", PixelType::Float}},
                win, win);
    std::vector<std::uint32_t> counts(d.npixels(), 0);
    auto square = [](int x, int y) { return x >= 20 && x < 30 && y >= 20 && y < 30; };
    auto disc = [](int x, int y) { return std::hypot(x - 54.5, y - 10.5) < 5.0; };
    auto wall = [](int x, int) { return x < 44; };
    for (int y = 0; y < 48; ++y)
        for (int x = 0; x < 64; ++x) counts[d.pixel_index(x, y)] = (square(x, y) || disc(x, y) || wall(x, y)) ? 1 : 0;
    EXPECT_TRUE(d.set_sample_counts(counts));
    for (int y = 0; y < 48; ++y)
        for (int x = 0; x < 64; ++x) {
            if (!counts[d.pixel_index(x, y)]) continue;
            const std::size_t k = d.first_sample(d.pixel_index(x, y));
            float rgba[4] = {0.2f, 0.4f, 0.6f, 1.0f}, z = 10.0f;
            if (square(x, y)) rgba[0] = 0.9f, rgba[1] = 0.1f, rgba[2] = 0.1f, z = 2.0f;
            if (disc(x, y)) rgba[0] = 0.4f, rgba[1] = 0.4f, rgba[2] = 0.0f, rgba[3] = 0.5f, z = 2.0f;
            for (int c = 0; c < 4; ++c) d.samples(c)[k] = rgba[c];
            d.samples(4)[k] = z;
        }
    return d;
}

// An opaque deep image with one sample per pixel: grey `value(x, y)` at
// `depth(x, y)`.
template <class Value, class Depth>
DeepImage opaque_one_sample(const Roi& win, Value value, Depth depth) {
    DeepImage d({{"R", PixelType::Float}, {"G", PixelType::Float}, {"B", PixelType::Float}, {"A", PixelType::Float},
                 {"Z", PixelType::Float}},
                win, win);
    EXPECT_TRUE(d.set_sample_counts(std::vector<std::uint32_t>(d.npixels(), 1)));
    for (int y = win.y0; y < win.y1; ++y)
        for (int x = win.x0; x < win.x1; ++x) {
            const std::size_t k = d.first_sample(d.pixel_index(x, y));
            for (int c = 0; c < 3; ++c) d.samples(c)[k] = value(x, y);
            d.samples(3)[k] = 1.0f;
            d.samples(4)[k] = depth(x, y);
        }
    return d;
}

// The image's two layers (default split), the farther extended by
// `extend_px` behind the nearer where that hides it fully (deep renders).
std::vector<Layer> extended_pair(const DeepImage& d, double extend_px) {
    auto layers = layers_from_deep(d, LayerSplit{});
    EXPECT_TRUE(layers) << layers.message();
    if (!layers || layers->size() != 2u) {
        ADD_FAILURE() << "expected two layers";
        return {};
    }
    ExtendOptions ext;
    ext.extend_px = extend_px;
    ext.occluder_alpha = 0.999f;
    EXPECT_TRUE(extend_layers_behind(*layers, d.data_window(), ext));
    return std::move(layers).value();
}

}  // namespace

TEST(layers_extend, BackgroundContinuesBehindAnOpaqueForegroundOnly) {
    const DeepImage d = scene();
    LayerSplit split;
    split.mode = LayerSplit::Mode::Auto;
    auto layers = layers_from_deep(d, split);
    ASSERT_TRUE(layers) << layers.message();
    ASSERT_EQ(layers->size(), 2u);
    const Image& bg_before = (*layers)[1].image;
    EXPECT_FALSE(bg_before.data_window().contains(25, 25) && bg_before.at(3, 25, 25) > 0.0f);

    ExtendOptions ext;
    ext.extend_px = 8.0;
    ext.occluder_alpha = 0.999f;
    ASSERT_TRUE(extend_layers_behind(*layers, d.data_window(), ext));
    const Image& fg = (*layers)[0].image;
    const Image& bg = (*layers)[1].image;
    // Behind the square: opaque wall colour and the wall's depth.
    for (int y = 20; y < 30; ++y)
        for (int x = 20; x < 30; ++x) {
            ASSERT_TRUE(bg.data_window().contains(x, y));
            EXPECT_EQ(bg.at(3, x, y), 1.0f);
            EXPECT_NEAR(bg.at(0, x, y), 0.2f, 1e-5);
            EXPECT_NEAR(bg.at(2, x, y), 0.6f, 1e-5);
            EXPECT_NEAR(bg.at(4, x, y), 10.0f, 1e-4);
        }
    // Behind the half-transparent disc there is nothing to reveal: no background invented.
    ASSERT_FALSE(bg.data_window().contains(54, 10) && bg.at(3, 54, 10) > 0.0f);
    // The nearest layer is never extended.
    EXPECT_EQ(fg.at(3, 25, 25), 1.0f);
    EXPECT_EQ(fg.at(0, 25, 25), 0.9f);
}

TEST(layers_extend, ExtensionStopsAtTheGivenDistance) {
    // A wide opaque foreground hides the wall's right part; the wall extends
    // only extend_px behind it.
    const Roi win{0, 0, 40, 8};
    const DeepImage d = opaque_one_sample(
        win, [](int x, int) { return x >= 10 ? 1.0f : 0.5f; }, [](int x, int) { return x >= 10 ? 1.0f : 9.0f; });
    std::vector<Layer> layers = extended_pair(d, 4.0);
    ASSERT_EQ(layers.size(), 2u);
    const Image& bg = layers[1].image;
    EXPECT_EQ(bg.data_window().x1, 14);  // pixels 10..13 are within 4 px of x = 9
    EXPECT_EQ(bg.at(3, 13, 4), 1.0f);
    EXPECT_NEAR(bg.at(0, 13, 4), 0.5f, 1e-6);
    ExtendOptions negative;
    negative.extend_px = -1.0;
    EXPECT_FALSE(extend_layers_behind(layers, win, negative));
}

// The extension continues what the layer shows at its edge, not what lies
// deeper inside it: a dark ceiling (0.001, depth 10) with a lamp (20) whose
// top is 6 px below a nearer band (depth 2) that hides the ceiling's upper
// part. Behind the band the ceiling's continuation stays dark, beside the
// lamp and above it. Before (every own pixel feeding the fill, bilinear pull
// taps) it was 0.01 to 3.2 there: a ghost of the lamp over the whole ceiling,
// revealed wherever the band's blurred edge is semi-transparent (the
// benchmark's Cornell box with a sphere of focus).
TEST(layers_extend, ABrightSpotInsideALayerDoesNotLeakIntoItsExtension) {
    const Roi win{0, 0, 128, 64};
    const DeepImage d = opaque_one_sample(
        win,
        [](int x, int y) {
            const bool band = y < 32, lamp = y >= 38 && y < 54 && x >= 90 && x < 110;
            return band ? 0.5f : lamp ? 20.0f : 0.001f;
        },
        [](int, int y) { return y < 32 ? 2.0f : 10.0f; });
    std::vector<Layer> layers = extended_pair(d, 20.0);
    ASSERT_EQ(layers.size(), 2u);
    const Image& ceiling = layers[1].image;
    for (int y = 12; y < 32; ++y)
        for (int x = 10; x < 118; x += 4) {
            ASSERT_TRUE(ceiling.data_window().contains(x, y));
            EXPECT_EQ(ceiling.at(3, x, y), 1.0f);
            EXPECT_LT(ceiling.at(0, x, y), 0.01f) << "x " << x << ", y " << y;
        }
}

namespace {

// A dark ceiling (0.001, depth 10) under a nearer band (0.5, depth 2,
// y < 32), with a wide lamp (30) 8 px below the band whose lower edge meets
// a farther wall (0.3, depth 20): three layers, the lamp at the ceiling's
// rim where it meets the wall. Its layers, unextended, and the options that
// extend them (32 px, as deep inputs: behind full occlusion).
const Roi kLampFrame{0, 0, 128, 64};
std::vector<Layer> lamp_above_a_farther_wall() {
    auto lamp = [](int x, int y) { return y >= 40 && y < 50 && x >= 34 && x < 94; };
    auto wall = [](int x, int y) { return y >= 50 && x >= 24 && x < 104; };
    const DeepImage d = opaque_one_sample(
        kLampFrame, [&](int x, int y) { return y < 32 ? 0.5f : lamp(x, y) ? 30.0f : wall(x, y) ? 0.3f : 0.001f; },
        [&](int x, int y) { return y < 32 ? 2.0f : wall(x, y) ? 20.0f : 10.0f; });
    auto layers = layers_from_deep(d, LayerSplit{});
    EXPECT_TRUE(layers) << layers.message();
    if (!layers || layers->size() != 3u) {
        ADD_FAILURE() << "expected three layers";
        return {};
    }
    return std::move(layers).value();
}
ExtendOptions reach_32px() {
    ExtendOptions ext;
    ext.extend_px = 32.0;
    ext.occluder_alpha = 0.999f;
    return ext;
}

}  // namespace

// With fill_from_hidden_edge (plates) only the edge that faces the hidden
// pixels feeds their fill: in lamp_above_a_farther_wall the lamp's lower
// edge is the ceiling layer's rim, and borders nothing the extension fills; before, it fed the fill all the same, and the
// ceiling's continuation behind the band took the lamp's light (up to 17
// here; on the benchmark's Cornell box 0.5 to 7 behind the near ceiling
// strip, a ceiling of 0.05: a bright line along the strip's blurred edge in
// one frame of a focus pull).
TEST(layers_extend, AnEdgeThatFacesNothingHiddenDoesNotFeedTheExtension) {
    std::vector<Layer> layers = lamp_above_a_farther_wall();
    ASSERT_EQ(layers.size(), 3u);
    ExtendOptions ext = reach_32px();
    ext.fill_from_hidden_edge = true;  // as plates extend
    std::vector<Layer> every_edge = layers;
    ASSERT_TRUE(extend_layers_behind(layers, kLampFrame, ext));
    const Image& ceiling = layers[1].image;
    for (int y = 0; y < 32; ++y)
        for (int x = 10; x < 118; x += 4) {
            ASSERT_TRUE(ceiling.data_window().contains(x, y));
            EXPECT_EQ(ceiling.at(3, x, y), 1.0f);
            EXPECT_LT(ceiling.at(0, x, y), 0.01f) << "x " << x << ", y " << y;
        }
    // Without the option (deep inputs) every edge feeds the fill: the lamp's light reaches behind the band.
    ext.fill_from_hidden_edge = false;
    ASSERT_TRUE(extend_layers_behind(every_edge, kLampFrame, ext));
    float brightest = 0.0f;
    for (int x = 10; x < 118; x += 4) brightest = std::max(brightest, every_edge[1].image.at(0, x, 20));
    EXPECT_GT(brightest, 0.1f);
}

// fill_highlight_knee One (deep inputs): colours above 1 are averaged as
// 1 + log(v). The map is increasing and concave, so by Jensen's inequality
// a continuation can only be darker than the linear fill's (which averages
// the same rim values with the same weights), never brighter, and it stays
// within the rim's range; a uniform colour above 1 comes back as itself.
// lamp_above_a_farther_wall, every edge feeding the fill (deep inputs): the
// lamp (30) at the rim beside a dark ceiling glows into the ceiling's
// continuation behind the band (the "lamp wings" of the benchmark's deep
// Cornell box).
TEST(layers_extend, CompressedHighlightsFillNoBrighterThanTheLinearFill) {
    const std::vector<Layer> layers = lamp_above_a_farther_wall();
    ASSERT_EQ(layers.size(), 3u);
    ExtendOptions ext = reach_32px();
    std::vector<Layer> linear = layers, compressed = layers;
    ASSERT_TRUE(extend_layers_behind(linear, kLampFrame, ext));
    ext.fill_highlight_knee = ExtendOptions::HighlightKnee::One;
    ASSERT_TRUE(extend_layers_behind(compressed, kLampFrame, ext));
    const Image &lin = linear[1].image, &com = compressed[1].image;
    ASSERT_TRUE(lin.data_window() == com.data_window());
    float brightest_linear = 0.0f, brightest = 0.0f;
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 128; ++x) {
            if (!lin.data_window().contains(x, y) || !(lin.at(3, x, y) > 0.0f)) continue;
            ASSERT_EQ(com.at(3, x, y), lin.at(3, x, y));
            for (int c = 0; c < 3; ++c) {
                EXPECT_LE(com.at(c, x, y), lin.at(c, x, y) * (1.0f + 1e-5f)) << x << "," << y;
                EXPECT_GE(com.at(c, x, y), 0.001f * (1.0f - 1e-5f)) << x << "," << y;
            }
            EXPECT_EQ(com.at(4, x, y), lin.at(4, x, y));  // depth is not a colour
            brightest_linear = std::max(brightest_linear, lin.at(0, x, y));
            brightest = std::max(brightest, com.at(0, x, y));
        }
    EXPECT_GT(brightest_linear, 1.0f);
    EXPECT_LT(brightest, 0.5f * brightest_linear);
    // Own pixels are not touched.
    for (int x = 34; x < 94; x += 7) EXPECT_EQ(com.at(0, x, 45), 30.0f);

    // A uniform wall at 20 behind the band: its continuation is 20 (the
    // round trip through the log is exact up to rounding).
    const DeepImage bright = opaque_one_sample(
        kLampFrame, [](int, int y) { return y < 32 ? 0.5f : 20.0f; }, [](int, int y) { return y < 32 ? 2.0f : 10.0f; });
    auto two = layers_from_deep(bright, LayerSplit{});
    ASSERT_TRUE(two) << two.message();
    ASSERT_EQ(two->size(), 2u);
    ASSERT_TRUE(extend_layers_behind(*two, bright.data_window(), ext));
    const Image& behind = (*two)[1].image;
    for (int y = 0; y < 32; y += 3)
        for (int x = 0; x < 128; x += 5) {
            ASSERT_TRUE(behind.data_window().contains(x, y));
            EXPECT_NEAR(behind.at(0, x, y), 20.0f, 20.0f * 1e-5f) << x << "," << y;
        }
}
