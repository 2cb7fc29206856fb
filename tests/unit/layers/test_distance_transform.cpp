// The layers' exact Euclidean distance transform against brute force.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "layers/layers_internal.h"

using namespace gdof;
using gdof::layers_detail::distance_transform;

namespace {

std::vector<float> brute_force(const std::vector<unsigned char>& mask, int W, int H) {
    std::vector<float> out(mask.size(), std::numeric_limits<float>::infinity());
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            double best = std::numeric_limits<double>::infinity();
            for (int v = 0; v < H; ++v)
                for (int u = 0; u < W; ++u)
                    if (mask[std::size_t(v) * W + u]) best = std::min(best, double((x - u) * (x - u) + (y - v) * (y - v)));
            out[std::size_t(y) * W + x] = float(std::sqrt(best));
        }
    return out;
}

void expect_exact(const std::vector<unsigned char>& mask, int W, int H, int threads) {
    FrameBuffer<float> got;
    Exec exec;
    exec.nthreads = threads;
    distance_transform(mask, W, H, got, exec);
    const std::vector<float> want = brute_force(mask, W, H);
    ASSERT_EQ(got.size(), want.size());
    for (std::size_t i = 0; i < want.size(); ++i) ASSERT_EQ(got[i], want[i]) << "pixel " << i % W << ", " << i / W;
}

}  // namespace

TEST(distance_transform, RandomMasksAreExact) {
    std::mt19937 rng(7);
    for (int trial = 0; trial < 40; ++trial) {
        const int W = 1 + int(rng() % 300), H = 1 + int(rng() % 40);
        const double density = std::pow(10.0, -3.0 * double(rng() % 1000) / 1000.0);  // 1 .. 0.001
        std::vector<unsigned char> mask(std::size_t(W) * H);
        std::bernoulli_distribution on(density);
        for (auto& m : mask) m = on(rng) ? 1 : 0;
        expect_exact(mask, W, H, 1 + trial % 2);
    }
}

TEST(distance_transform, EmptyFullAndSinglePixel) {
    const int W = 257, H = 9;  // more columns than one block of the column pass
    std::vector<unsigned char> mask(std::size_t(W) * H, 0);
    FrameBuffer<float> d;
    distance_transform(mask, W, H, d, Exec{});
    for (float v : d) EXPECT_TRUE(std::isinf(v));
    std::fill(mask.begin(), mask.end(), 1);
    distance_transform(mask, W, H, d, Exec{});
    for (float v : d) EXPECT_EQ(v, 0.0f);
    std::fill(mask.begin(), mask.end(), 0);
    mask[std::size_t(4) * W + 200] = 1;
    expect_exact(mask, W, H, 2);
}

// Masks of runs (a big slice's rows are long runs of set pixels, whose inner
// pixels the row pass skips), with and without a bound: within the bound
// exact, beyond it +inf.
TEST(distance_transform, RunsAndBoundsAreExact) {
    std::mt19937 rng(13);
    for (int trial = 0; trial < 40; ++trial) {
        const int W = 1 + int(rng() % 200), H = 1 + int(rng() % 60);
        std::vector<unsigned char> mask(std::size_t(W) * H, 0);
        const int nrect = int(rng() % 5);
        for (int k = 0; k < nrect; ++k) {
            const int x0 = int(rng() % W), y0 = int(rng() % H);
            const int x1 = std::min(W, x0 + 1 + int(rng() % 80)), y1 = std::min(H, y0 + 1 + int(rng() % 30));
            for (int y = y0; y < y1; ++y)
                for (int x = x0; x < x1; ++x) mask[std::size_t(y) * W + x] = 1;
        }
        if (trial % 3 == 0) mask[std::size_t(rng() % H) * W + rng() % W] = 1;
        const std::vector<float> exact = brute_force(mask, W, H);
        for (double bound : {std::numeric_limits<double>::infinity(), 0.0, 1.0, 2.5, 7.0, 23.4}) {
            FrameBuffer<float> got;
            Exec exec;
            exec.nthreads = 1 + trial % 2;
            distance_transform(mask, W, H, got, exec, bound);
            for (std::size_t i = 0; i < exact.size(); ++i) {
                const float want = double(exact[i]) <= bound ? exact[i] : std::numeric_limits<float>::infinity();
                ASSERT_EQ(got[i], want) << "bound " << bound << ", pixel " << i % W << ", " << i / W;
            }
        }
    }
}

TEST(distance_transform, SameBitsForAnyThreadCount) {
    const int W = 1031, H = 517;
    std::mt19937 rng(11);
    std::vector<unsigned char> mask(std::size_t(W) * H);
    for (auto& m : mask) m = rng() % 5000 == 0 ? 1 : 0;
    FrameBuffer<float> a, b;
    Exec one, two;
    one.nthreads = 1;
    two.nthreads = 2;
    distance_transform(mask, W, H, a, one);
    distance_transform(mask, W, H, b, two);
    EXPECT_EQ(a, b);
}
