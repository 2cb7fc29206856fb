// Speckle removal (plate/plate_internal.h) against a plain reference: the
// 8-connected components of continuous neighbours found by breadth-first
// search, and the removal rule applied to them directly. Random depth maps
// with blobs of every size, sky, holes and kept pixels, across the row bands
// the library joins in parallel.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <deque>
#include <limits>
#include <vector>

#include "plate/plate_internal.h"

namespace gdof::plate_detail {
namespace {

constexpr double kContinuity = 1.05;

struct Rng {
    std::uint64_t s;
    double next() {
        s = s * 6364136223846793005ull + 1442695040888963407ull;
        return double(s >> 11) * (1.0 / 9007199254740992.0);
    }
    int below(int n) { return std::min(n - 1, int(next() * n)); }
};

// A ramp (a floor) with random-walk blobs of 1 to 60 px at other depths (a
// third of them close enough to merge with what is around), patches of sky,
// and holes.
std::vector<float> random_depth(int W, int H, Rng& rng) {
    std::vector<float> d(std::size_t(W) * std::size_t(H));
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) d[std::size_t(y) * std::size_t(W) + std::size_t(x)] = 2.0f + 0.01f * float(y);
    const int nblobs = 60;
    for (int b = 0; b < nblobs; ++b) {
        int x = rng.below(W), y = rng.below(H);
        const int size = 1 + rng.below(60);
        const double kind = rng.next();
        const float value = kind < 0.1 ? std::numeric_limits<float>::infinity()
                            : kind < 0.2 ? std::numeric_limits<float>::quiet_NaN()
                            : kind < 0.5 ? d[std::size_t(y) * std::size_t(W) + std::size_t(x)] * 1.02f
                                         : float(0.5 + 3.0 * rng.next());
        for (int k = 0; k < size; ++k) {
            d[std::size_t(y) * std::size_t(W) + std::size_t(x)] = value;
            x = std::clamp(x + rng.below(3) - 1, 0, W - 1);
            y = std::clamp(y + rng.below(3) - 1, 0, H - 1);
        }
    }
    return d;
}

// The rule of remove_speckles on components found by breadth-first search.
std::size_t reference(std::vector<float>& d, int W, int H, int max_px, const std::vector<unsigned char>& keep) {
    const std::size_t n = d.size();
    std::vector<int> comp(n, -1);
    std::vector<int> size;
    for (std::size_t s = 0; s < n; ++s) {
        if (comp[s] >= 0 || std::isnan(d[s])) continue;
        const int id = int(size.size());
        size.push_back(0);
        std::deque<std::size_t> q{s};
        comp[s] = id;
        while (!q.empty()) {
            const std::size_t i = q.front();
            q.pop_front();
            ++size.back();
            const int x = int(i % std::size_t(W)), y = int(i / std::size_t(W));
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const int xx = x + dx, yy = y + dy;
                    if (xx < 0 || xx >= W || yy < 0 || yy >= H) continue;
                    const std::size_t j = std::size_t(yy) * std::size_t(W) + std::size_t(xx);
                    if (comp[j] >= 0 || !continuous(d[i], d[j], kContinuity)) continue;
                    comp[j] = id;
                    q.push_back(j);
                }
        }
    }
    auto small = [&](std::size_t i) { return size[std::size_t(comp[i])] <= max_px; };
    std::vector<int> all(size.size(), 0), big(size.size(), 0);
    for (std::size_t i = 0; i < n; ++i) {
        if (std::isnan(d[i]) || !small(i)) continue;
        const int x = int(i % std::size_t(W)), y = int(i / std::size_t(W));
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
                const int xx = x + dx, yy = y + dy;
                if ((dx == 0 && dy == 0) || xx < 0 || xx >= W || yy < 0 || yy >= H) continue;
                const std::size_t j = std::size_t(yy) * std::size_t(W) + std::size_t(xx);
                if (std::isnan(d[j]) || comp[j] == comp[i]) continue;
                ++all[std::size_t(comp[i])];
                if (!small(j)) ++big[std::size_t(comp[i])];
            }
    }
    std::size_t removed = 0;
    std::vector<float> out = d;
    for (std::size_t i = 0; i < n; ++i) {
        if (std::isnan(d[i]) || keep[i] || !small(i)) continue;
        const int c = comp[i];
        if (all[std::size_t(c)] > 0 && 2 * big[std::size_t(c)] >= all[std::size_t(c)]) {
            out[i] = std::numeric_limits<float>::quiet_NaN();
            ++removed;
        }
    }
    d = out;
    return removed;
}

TEST(speckles, SameAsBreadthFirstComponentsOnRandomMapsForOneAndTwoThreads) {
    // 150 rows: three bands of 64 (joined after, across rows 63/64 and 127/128).
    const int W = 97, H = 150, max_px = 20;
    std::size_t total = 0;
    for (std::uint64_t seed = 1; seed <= 12; ++seed) {
        Rng rng{seed};
        const std::vector<float> depth = random_depth(W, H, rng);
        std::vector<unsigned char> keep(depth.size());
        for (auto& k : keep) k = rng.next() < 0.02 ? 1 : 0;
        std::vector<float> want = depth;
        const std::size_t want_removed = reference(want, W, H, max_px, keep);
        total += want_removed;
        for (int threads : {1, 2}) {
            Exec exec;
            exec.nthreads = threads;
            std::vector<float> got = depth;
            const std::size_t removed = remove_speckles(got, W, H, kContinuity, max_px, keep, exec);
            EXPECT_EQ(removed, want_removed) << "seed " << seed << ", " << threads << " thread(s)";
            ASSERT_EQ(got.size(), want.size());
            EXPECT_EQ(0, std::memcmp(got.data(), want.data(), got.size() * sizeof(float)))
                << "seed " << seed << ", " << threads << " thread(s)";
        }
    }
    EXPECT_GT(total, 100u) << "the maps must hold speckles for the comparison to mean anything";
}

}  // namespace
}  // namespace gdof::plate_detail
