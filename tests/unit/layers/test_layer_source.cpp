// Layers made one at a time (LayerSource) against the list builders: a deep
// source with an extension prepares where each pixel is hidden from the
// samples themselves, the list path from the layers' images; both must give
// every layer bit for bit.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "gdof/layers.h"

using namespace gdof;

namespace {

// Up to three samples per pixel at depths near 2, 5 and 11 (some pixels
// without any), opaque or semi-transparent, in any stored order.
DeepImage random_deep(unsigned seed) {
    const Roi win{-3, 2, 61, 42}, display{0, 0, 64, 48};
    DeepImage d({{"R", PixelType::Float}, {"G", PixelType::Float}, {"B", PixelType::Float}, {"A", PixelType::Float},
                 {"Z", PixelType::Float}},
                win, display);
    std::mt19937 rng(seed);
    std::vector<std::uint32_t> counts(d.npixels());
    for (auto& c : counts) c = rng() % 4;
    EXPECT_TRUE(d.set_sample_counts(counts));
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    const float depth[3] = {2.0f, 5.0f, 11.0f};
    for (std::size_t k = 0; k < d.total_samples(); ++k) {
        const float a = rng() % 3 == 0 ? 0.3f + 0.6f * u(rng) : 1.0f;
        for (int c = 0; c < 3; ++c) d.samples(c)[k] = a * u(rng);
        d.samples(3)[k] = a;
        d.samples(4)[k] = depth[rng() % 3] * (1.0f + 0.02f * u(rng));
    }
    return d;
}

void expect_same_layer(const Layer& a, const Layer& b) {
    EXPECT_EQ(a.name, b.name);
    ASSERT_EQ(a.image.data_window(), b.image.data_window()) << a.name;
    ASSERT_EQ(a.image.nchannels(), b.image.nchannels());
    for (int c = 0; c < a.image.nchannels(); ++c)
        for (std::size_t i = 0; i < a.image.npixels(); ++i) {
            const float x = a.image.plane(c)[i], y = b.image.plane(c)[i];
            ASSERT_TRUE(x == y || (std::isnan(x) && std::isnan(y))) << a.name << " channel " << c << " pixel " << i;
        }
}

}  // namespace

TEST(layer_source, DeepSourceWithExtensionEqualsBuilderThenExtension) {
    for (unsigned seed : {1u, 2u, 3u})
        for (float occluder : {0.999f, 0.0f}) {
            const DeepImage d = random_deep(seed);
            LayerSplit split;
            split.mode = LayerSplit::Mode::Count;
            split.count = 3;
            ExtendOptions ext;
            ext.extend_px = 6.0;
            ext.occluder_alpha = occluder;
            ext.continue_coverage = occluder > 0.0f;
            auto list = layers_from_deep(d, split);
            ASSERT_TRUE(list) << list.message();
            ASSERT_TRUE(extend_layers_behind(*list, d.data_window(), ext));
            auto src = deep_layer_source(d, split, {}, &ext);
            ASSERT_TRUE(src) << src.message();
            ASSERT_EQ((*src)->size(), int(list->size()));
            Roi frame;
            for (int i = 0; i < (*src)->size(); ++i) {
                Layer storage;
                auto made = (*src)->make(i, storage);
                ASSERT_TRUE(made) << made.message();
                expect_same_layer(**made, (*list)[std::size_t(i)]);
                frame = unite(frame, (*made)->image.data_window());
            }
            // frame(), known before any layer is made, is their union.
            EXPECT_EQ((*src)->frame(), frame);
            EXPECT_EQ((*src)->display_window(), d.display_window());
        }
}

TEST(layer_source, ListedLayersAreServedAsTheyAre) {
    const DeepImage d = random_deep(4);
    auto list = layers_from_deep(d, LayerSplit{});
    ASSERT_TRUE(list);
    auto src = source_of(*list);
    ASSERT_EQ(src->size(), int(list->size()));
    Layer storage;
    auto made = src->make(0, storage);
    ASSERT_TRUE(made);
    EXPECT_EQ(*made, &(*list)[0]);  // borrowed, not copied
    EXPECT_FALSE(src->make(src->size(), storage));
}
