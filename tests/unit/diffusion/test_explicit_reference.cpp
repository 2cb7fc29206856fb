// The explicit solver (iterations fused per pass over bands of rows) against
// a plain reference written here from its definition: one sweep over the
// whole grid per iteration, conductance min(D_p, D_q) * dt * weight on the
// 9-point stencil. Every value must be the same bit for bit, on grids of
// one row, one column, fewer rows than a band and several bands, and for
// 1 and 2 threads.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "diffusion/diffusion_test_helpers.h"
#include "gdof/diffusion.h"

using namespace gdof;

namespace {

// The definition: u' = u + sum over the 8 neighbours q of c_pq (u_q - u_p),
// c = dt * w * min(D_p, D_q), w = 4/6 (edges) or 1/6 (diagonals); the sum
// in the solver's documented order (E, W, S, SE, SW, N, NW, NE).
void reference(std::vector<std::vector<float>>& planes, const std::vector<float>& D, int W, int H, int iters) {
    const float dt = float(1.0 / iters);
    const float ke = 4.0f / 6.0f, kd = 1.0f / 6.0f;
    auto d = [&](int x, int y) { return D[std::size_t(y) * W + x]; };
    auto c = [&](int x0, int y0, int x1, int y1, float k) { return dt * k * std::min(d(x0, y0), d(x1, y1)); };
    for (auto& u : planes)
        for (int it = 0; it < iters; ++it) {
            std::vector<float> next(u.size());
            for (int y = 0; y < H; ++y)
                for (int x = 0; x < W; ++x) {
                    auto at = [&](int xx, int yy) { return u[std::size_t(yy) * W + xx]; };
                    const float up = at(x, y);
                    float acc = 0.0f;
                    if (x + 1 < W) acc += c(x, y, x + 1, y, ke) * (at(x + 1, y) - up);
                    if (x > 0) acc += c(x - 1, y, x, y, ke) * (at(x - 1, y) - up);
                    if (y + 1 < H) {
                        acc += c(x, y, x, y + 1, ke) * (at(x, y + 1) - up);
                        if (x + 1 < W) acc += c(x, y, x + 1, y + 1, kd) * (at(x + 1, y + 1) - up);
                        if (x > 0) acc += c(x, y, x - 1, y + 1, kd) * (at(x - 1, y + 1) - up);
                    }
                    if (y > 0) {
                        acc += c(x, y - 1, x, y, ke) * (at(x, y - 1) - up);
                        if (x > 0) acc += c(x - 1, y - 1, x, y, kd) * (at(x - 1, y - 1) - up);
                        if (x + 1 < W) acc += c(x + 1, y - 1, x, y, kd) * (at(x + 1, y - 1) - up);
                    }
                    next[std::size_t(y) * W + x] = up + acc;
                }
            u = next;
        }
}

}  // namespace

TEST(explicit_reference, FusedBandsEqualOneSweepPerIterationBitForBit) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> val(0.0f, 4.0f), rad(0.0f, 7.0f);
    const int sizes[][2] = {{1, 1}, {1, 9}, {9, 1}, {2, 2}, {17, 5}, {33, 64}, {31, 65}, {40, 150}, {23, 201}};
    for (auto [W, H] : sizes)
        for (int threads : {1, 2}) {
            const std::size_t n = std::size_t(W) * H;
            std::vector<std::vector<float>> planes(3, std::vector<float>(n));
            for (auto& p : planes)
                for (float& v : p) v = val(rng);
            std::vector<float> radius(n);
            for (float& r : radius) r = rng() % 4 == 0 ? 0.0f : rad(rng);  // sharp pixels insulate
            if (threads == 2 && H > 64) {  // a blurred island in a sharp frame: most rows and columns still
                for (int y = 0; y < H; ++y)
                    for (int x = 0; x < W; ++x)
                        if (y < H / 2 || y > H / 2 + 5 || x < W / 3 || x > W / 3 + 4) radius[std::size_t(y) * W + x] = 0.0f;
            }
            std::vector<float> D(n);
            float dmax = 0.0f;
            for (std::size_t i = 0; i < n; ++i) dmax = std::max(dmax, D[i] = float(diffusivity_from_radius(radius[i])));
            DiffusionOptions s;
            s.solver = DiffusionSolver::Explicit;
            const int iters = explicit_iterations(radius_from_diffusivity(dmax), s);
            std::vector<std::vector<float>> want = planes;
            reference(want, D, W, H, iters);
            std::vector<std::vector<float>*> ptrs;
            for (auto& p : planes) ptrs.push_back(&p);
            Exec e;
            e.nthreads = threads;
            ASSERT_TRUE(test::diffuse_vectors(ptrs, W, H, radius, s, e));
            for (std::size_t c = 0; c < planes.size(); ++c)
                for (std::size_t i = 0; i < n; ++i)
                    ASSERT_EQ(planes[c][i], want[c][i]) << W << "x" << H << " plane " << c << " pixel " << i << " threads "
                                                        << threads << " iterations " << iters;
        }
}
