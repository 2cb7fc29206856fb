// The layer functions that run in parallel use the caller's Exec: its
// thread count (results do not depend on it) and its cancellation.
#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include "gdof/layers.h"

using namespace gdof;

namespace {

// 1 to 3 samples per pixel at depths 1..6, semi-transparent.
DeepImage small_deep() {
    const Roi win{-2, 1, 30, 19};
    DeepImage d({{"R"}, {"G"}, {"B"}, {"A"}, {"Z"}}, win, Roi{0, 0, 32, 20});
    std::vector<std::uint32_t> counts(win.npixels());
    for (std::size_t i = 0; i < counts.size(); ++i) counts[i] = std::uint32_t(1 + i % 3);
    EXPECT_TRUE(d.set_sample_counts(counts));
    for (std::size_t k = 0; k < d.total_samples(); ++k) {
        for (int c = 0; c < 3; ++c) d.samples(c)[k] = 0.1f * float((k * 7 + std::size_t(c)) % 9);
        d.samples(3)[k] = 0.25f + 0.25f * float(k % 3);
        d.samples(4)[k] = 1.0f + float((k * 5) % 6);
    }
    return d;
}

Exec threads(int n) {
    Exec e;
    e.nthreads = n;
    return e;
}

Exec cancelled_exec() {
    Exec e;
    e.cancelled = [] { return true; };
    return e;
}

bool same_bits(const Image& a, const Image& b) {
    if (a.data_window() != b.data_window() || a.nchannels() != b.nchannels()) return false;
    for (int c = 0; c < a.nchannels(); ++c)
        if (a.npixels() && std::memcmp(a.plane(c), b.plane(c), a.npixels() * sizeof(float)) != 0) return false;
    return true;
}

}  // namespace

TEST(layers_exec, FlattenAndCompositeDoNotDependOnTheThreadCount) {
    const DeepImage d = small_deep();
    auto one = flatten_deep(d, threads(1)), many = flatten_deep(d, threads(4));
    ASSERT_TRUE(one && many);
    EXPECT_TRUE(same_bits(*one, *many));

    auto layers = layers_from_deep(d, LayerSplit{});
    ASSERT_TRUE(layers) << layers.message();
    std::vector<const Image*> ptrs;
    for (const Layer& l : *layers) ptrs.push_back(&l.image);
    const Roi window = d.data_window().grown(2);
    auto c1 = composite_layers(ptrs, window, threads(1)), c4 = composite_layers(ptrs, window, threads(4));
    ASSERT_TRUE(c1 && c4);
    EXPECT_TRUE(same_bits(*c1, *c4));
}

TEST(layers_exec, CancellationStopsEveryParallelEntryPoint) {
    const DeepImage d = small_deep();
    const Exec stop = cancelled_exec();

    auto flat = flatten_deep(d, stop);
    ASSERT_FALSE(flat);
    EXPECT_EQ(flat.status().code(), StatusCode::Cancelled);

    auto layers = layers_from_deep(d, LayerSplit{}, {}, stop);
    ASSERT_FALSE(layers);
    EXPECT_EQ(layers.status().code(), StatusCode::Cancelled);

    ImageSet set;
    set.parts.emplace_back(d);
    auto parts = layers_from_parts(set, PositionSource{}, stop);
    ASSERT_FALSE(parts);
    EXPECT_EQ(parts.status().code(), StatusCode::Cancelled);
    ASSERT_TRUE(layers_from_parts(set, PositionSource{}));  // the same call runs without the cancel

    auto ok = layers_from_deep(d, LayerSplit{});
    ASSERT_TRUE(ok);
    std::vector<const Image*> ptrs;
    for (const Layer& l : *ok) ptrs.push_back(&l.image);
    auto comp = composite_layers(ptrs, d.data_window(), stop);
    ASSERT_FALSE(comp);
    EXPECT_EQ(comp.status().code(), StatusCode::Cancelled);
}
