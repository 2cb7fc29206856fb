// Which slice is seen nearest behind each pixel (background_owners) against
// brute force, unbounded and bounded by a reach (plates: only owners within
// the extension's reach matter).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "layers/layers_internal.h"

using namespace gdof;
using gdof::layers_detail::background_owners;

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

struct Map {
    int W, H, nslices;
    std::vector<int> slice, fg;
};

// Rectangles of random slices over a background slice (or emptiness), and a
// few mixed pixels with a foreground slice.
Map random_map(unsigned seed, bool with_empty) {
    std::mt19937 rng(seed);
    Map m{53, 41, 6, {}, {}};
    const std::size_t n = std::size_t(m.W) * std::size_t(m.H);
    m.slice.assign(n, with_empty ? -1 : m.nslices - 1);
    m.fg.assign(n, -1);
    for (int r = 0; r < 9; ++r) {
        const int k = int(rng() % unsigned(m.nslices - 1));
        if (k == 2) continue;  // one slice stays empty
        const int x0 = int(rng() % unsigned(m.W)), y0 = int(rng() % unsigned(m.H));
        const int x1 = std::min(m.W, x0 + 2 + int(rng() % 15)), y1 = std::min(m.H, y0 + 2 + int(rng() % 12));
        for (int y = y0; y < y1; ++y)
            for (int x = x0; x < x1; ++x) m.slice[std::size_t(y) * m.W + x] = k;
    }
    for (int r = 0; r < 12; ++r) {
        const std::size_t i = rng() % n;
        if (m.slice[i] > 0) m.fg[i] = int(rng() % unsigned(m.slice[i]));
    }
    return m;
}

// For each pixel: the nearest (Euclidean) pixel of each slice behind its
// front slice, the nearest of those (ties: the nearer slice); -1 where
// emptiness is strictly nearer or nothing is behind.
layers_detail::BackgroundOwners brute_force(const Map& m) {
    const std::size_t n = m.slice.size();
    layers_detail::BackgroundOwners out;
    out.owner.assign(n, -1);
    out.distance.assign(n, kInf);
    auto front = [&](std::size_t i) { return m.fg[i] >= 0 && m.fg[i] < m.slice[i] ? m.fg[i] : m.slice[i]; };
    for (int y = 0; y < m.H; ++y)
        for (int x = 0; x < m.W; ++x) {
            const std::size_t i = std::size_t(y) * m.W + x;
            const int k0 = front(i);
            if (k0 < 0) continue;
            std::vector<double> d(std::size_t(m.nslices) + 1, std::numeric_limits<double>::infinity());
            for (int v = 0; v < m.H; ++v)
                for (int u = 0; u < m.W; ++u) {
                    const std::size_t j = std::size_t(v) * m.W + u;
                    const double dd = std::sqrt(double((x - u) * (x - u) + (y - v) * (y - v)));
                    if (m.slice[j] < 0) d[std::size_t(m.nslices)] = std::min(d[std::size_t(m.nslices)], dd);
                    for (int k : {m.slice[j], m.fg[j]})
                        if (k > k0) d[std::size_t(k)] = std::min(d[std::size_t(k)], dd);
                }
            int best = -1;
            double bd = d[std::size_t(m.nslices)];  // emptiness
            for (int k = m.nslices - 1; k > k0; --k)
                if (d[std::size_t(k)] <= bd && std::isfinite(d[std::size_t(k)])) bd = d[std::size_t(k)], best = k;
            out.owner[i] = best;
            out.distance[i] = best >= 0 ? float(bd) : kInf;
        }
    return out;
}

}  // namespace

TEST(background_owners, UnboundedMatchesBruteForce) {
    for (unsigned seed = 1; seed <= 6; ++seed)
        for (bool empty : {false, true}) {
            const Map m = random_map(seed, empty);
            const auto want = brute_force(m);
            const auto got = background_owners(m.slice, m.fg, m.nslices, m.W, m.H);
            for (std::size_t i = 0; i < want.owner.size(); ++i) {
                ASSERT_EQ(got.owner[i], want.owner[i]) << "seed " << seed << " pixel " << i;
                if (want.owner[i] >= 0) {
                    ASSERT_FLOAT_EQ(got.distance[i], want.distance[i]) << "seed " << seed;
                }
            }
        }
}

TEST(background_owners, BoundedKeepsOwnersWithinTheBound) {
    // Within the bound: the same owner and distance; beyond it: an owner
    // >= 0 exactly where some slice is behind, distance +inf. With emptiness
    // the bound is not used (emptiness competes at every distance).
    for (unsigned seed = 1; seed <= 6; ++seed)
        for (double bound : {0.0, 3.0, 7.5}) {
            const Map m = random_map(seed, false);
            const auto want = brute_force(m);
            Exec two;
            two.nthreads = 2;
            const auto got = background_owners(m.slice, m.fg, m.nslices, m.W, m.H, two, bound);
            for (std::size_t i = 0; i < want.owner.size(); ++i) {
                if (want.owner[i] >= 0 && want.distance[i] <= bound) {
                    ASSERT_EQ(got.owner[i], want.owner[i]) << "seed " << seed << " bound " << bound << " pixel " << i;
                    ASSERT_FLOAT_EQ(got.distance[i], want.distance[i]);
                } else {
                    ASSERT_EQ(got.owner[i] >= 0, want.owner[i] >= 0) << "seed " << seed << " pixel " << i;
                    ASSERT_EQ(got.distance[i], kInf);
                }
            }
            const Map e = random_map(seed, true);
            const auto want_e = brute_force(e);
            const auto got_e = background_owners(e.slice, e.fg, e.nslices, e.W, e.H, two, bound);
            EXPECT_EQ(got_e.owner, want_e.owner) << "seed " << seed;
        }
}
