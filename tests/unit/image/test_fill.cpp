#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "gdof/fill.h"

using namespace gdof;

TEST(fill, ConstantStaysConstantAndKnownPixelsAreKept) {
    const int W = 37, H = 21;
    std::vector<float> v(W * H, 0.0f), w(W * H, 0.0f);
    for (int y = 5; y < 12; ++y)
        for (int x = 20; x < 30; ++x) {
            v[y * W + x] = 3.25f;
            w[y * W + x] = 1.0f;
        }
    v[0] = -7.0f;  // garbage where the weight is 0 must be overwritten
    float* p = v.data();
    ASSERT_TRUE(push_pull_fill(std::span<float* const>(&p, 1), w.data(), W, H));
    for (float x : v) EXPECT_FLOAT_EQ(x, 3.25f);
}

TEST(fill, ExtrapolationIsSmoothAndBetweenTheKnownValues) {
    // Two known blocks, 1 on the left and 5 on the right: the fill stays in
    // [1, 5], is monotonic in x along the middle row, and keeps the blocks.
    const int W = 64, H = 16;
    std::vector<float> v(W * H, 0.0f), w(W * H, 0.0f);
    for (int y = 0; y < H; ++y) {
        for (int x = 0; x < 8; ++x) {
            v[y * W + x] = 1.0f;
            w[y * W + x] = 1.0f;
        }
        for (int x = 56; x < 64; ++x) {
            v[y * W + x] = 5.0f;
            w[y * W + x] = 1.0f;
        }
    }
    float* p = v.data();
    ASSERT_TRUE(push_pull_fill(std::span<float* const>(&p, 1), w.data(), W, H));
    for (int x = 0; x < W; ++x) {
        const float a = v[8 * W + x];
        EXPECT_GE(a, 1.0f - 1e-5f);
        EXPECT_LE(a, 5.0f + 1e-5f);
        if (x > 0) {
            EXPECT_GE(a, v[8 * W + x - 1] - 1e-5f) << x;
        }
    }
    EXPECT_EQ(v[8 * W + 3], 1.0f);
    EXPECT_EQ(v[8 * W + 60], 5.0f);
    EXPECT_GT(v[8 * W + 40], v[8 * W + 20]);
}

TEST(fill, NoWeightMeansNothingToFill) {
    std::vector<float> v(6, 2.0f), w(6, 0.0f);
    float* p = v.data();
    EXPECT_FALSE(push_pull_fill(std::span<float* const>(&p, 1), w.data(), 3, 2));
    for (float x : v) EXPECT_EQ(x, 2.0f);
}
