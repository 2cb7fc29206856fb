// Holes in a depth map filled from their surroundings, guided by the plate.
//
// Hole pixels are visited in rings, from the hole's edge inwards (ring k:
// 4-connected distance k to the nearest known pixel). A pixel of ring k
// looks at the known depths (rings < k) in the 7x7 window around it, each
// weighted by closeness and by how alike its colour is to the pixel's:
//   1. which surface: the weighted median of those depths. A median picks
//      one surface where the window straddles a silhouette (an average
//      would invent a depth between them), and the colour weight makes the
//      fill follow the plate's edges;
//   2. where on it: a weighted least-squares plane through the inverse
//      depths of that surface's pixels (those within kSameSurface of the
//      median), evaluated at the pixel. Inverse depth is linear across the
//      image for any plane in the world, so floors and walls are continued
//      exactly, not flattened; a poorly conditioned fit falls back to the
//      surface's weighted mean.
// A pixel whose window holds nothing of its colour looks further
// (kWideWindow); with nothing alike there either, but its colour on the
// hole's rim (the first known pixel in one of 8 directions, within
// kRimSearch) and the hole inside the frame, it waits for later rings (up
// to kMaxWait), as the fill from that side may bring its own surface within
// reach; otherwise, or after that, it falls back to the window's best
// guess.
// Rings are computed one after another, the pixels of a ring in parallel:
// each reads only earlier rings, so the result does not depend on the
// thread count.
#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>
#include <mutex>

#include "plate/plate_internal.h"

namespace gdof::plate_detail {

namespace {

constexpr int kWindow = 3;             // 7x7
constexpr double kSpatialSigma = 2.0;  // px
constexpr double kColourSigma = 0.05;  // in sqrt(colour)
// When nothing in the 7x7 window looks like the pixel (its best colour
// affinity below kColourMatch, 2 sigma), the surface it belongs to is not in
// reach yet: a thin pole crossed by a hole would otherwise take the ground's
// depth from the hole's edge. The wide window then looks for it further, with
// a spatial weight that lets colour decide.
constexpr int kWideWindow = 12;
constexpr double kWideSpatialSigma = 6.0;
const double kColourMatch = std::exp(-2.0);
constexpr double kSameSurface = 1.10;  // depth ratio to the median: the same surface
// The windows are in pixels, so a hole wider than the wide window can hold
// a pole's edge that the ground's fill reaches first (the pole's own side
// beyond the wide window: the benchmark's 1920x1080 degraded depth); each of its
// pixels would then take the ground's depth from the one before, and the
// pole's edge would blur as the ground. Such a pixel waits, ring by ring,
// until the pole's fill comes within reach (or kMaxWait rings have passed).
// Only a surface seen on the rim is waited for, and not in a hole that
// reaches the frame's edge (a sensor's missing sky, open to what lies
// outside the frame): there, black sky waited for some dark rim pixel and
// was then swept in streaks by that side's depth.
constexpr int kMaxWait = 2 * kWideWindow;
constexpr int kRimSearch = 64;

// Calls f(j) for each 4-neighbour j of pixel i inside the W x H frame.
template <class F>
void for_each_4_neighbour(int i, int W, int H, F&& f) {
    const int x = i % W, y = i / W;
    if (x + 1 < W) f(i + 1);
    if (x > 0) f(i - 1);
    if (y + 1 < H) f(i + W);
    if (y > 0) f(i - W);
}

struct Candidate {
    float depth;
    double weight;
    int dx, dy;
};

float weighted_median(std::vector<Candidate>& c) {
    std::sort(c.begin(), c.end(), [](const Candidate& a, const Candidate& b) { return a.depth < b.depth; });
    double total = 0;
    for (const Candidate& k : c) total += k.weight;
    double acc = 0;
    for (const Candidate& k : c) {
        acc += k.weight;
        if (acc >= 0.5 * total) return k.depth;
    }
    return c.back().depth;
}

// Step 2: the plane through the inverse depths of the median's surface.
float continue_surface(const std::vector<Candidate>& c, float median) {
    if (!std::isfinite(median)) return median;  // sky continues as sky
    // Weighted sums for u = a + b dx + c dy over the surface's candidates.
    double s[3][3] = {}, r[3] = {}, wsum = 0, umean = 0, umin = 1e300, umax = -1e300;
    int count = 0;
    for (const Candidate& k : c) {
        if (!std::isfinite(k.depth)) continue;
        const double hi = std::max(k.depth, median), lo = std::min(k.depth, median);
        if (hi > lo * kSameSurface) continue;
        const double u = 1.0 / k.depth, w = k.weight;
        const double v[3] = {1.0, double(k.dx), double(k.dy)};
        for (int i = 0; i < 3; ++i) {
            for (int j = 0; j < 3; ++j) s[i][j] += w * v[i] * v[j];
            r[i] += w * v[i] * u;
        }
        wsum += w, umean += w * u, umin = std::min(umin, u), umax = std::max(umax, u);
        ++count;
    }
    if (count == 0 || !(wsum > 0)) return median;
    umean /= wsum;
    // Cramer's rule for a; conditioning relative to the weights' spread.
    const double det = s[0][0] * (s[1][1] * s[2][2] - s[1][2] * s[2][1]) -
                       s[0][1] * (s[1][0] * s[2][2] - s[1][2] * s[2][0]) +
                       s[0][2] * (s[1][0] * s[2][1] - s[1][1] * s[2][0]);
    const double scale = s[0][0] * s[1][1] * s[2][2];
    if (count < 6 || !(std::abs(det) > 1e-3 * scale)) return float(1.0 / umean);
    const double deta = r[0] * (s[1][1] * s[2][2] - s[1][2] * s[2][1]) - s[0][1] * (r[1] * s[2][2] - s[1][2] * r[2]) +
                        s[0][2] * (r[1] * s[2][1] - s[1][1] * r[2]);
    double a = deta / det;
    // Extrapolate, but never far beyond what the surface shows.
    const double span = umax - umin;
    a = std::clamp(a, std::max(umin - span, 0.5 * umin), umax + span);
    return a > 0 ? float(1.0 / a) : float(1.0 / umean);
}

}  // namespace

Guide make_guide(const Image& plate, const Exec& exec) {
    Guide g;
    const RgbaIndices ix = find_rgba(plate);
    const int ch[3] = {ix.r, ix.g, ix.b};
    for (int c : ch)
        if (c < 0 || !plate.plane(c)) return g;
    const long n = long(plate.npixels());
    for (int k = 0; k < 3; ++k) {
        const float* p = plate.plane(ch[k]);
        float* q = (g.c[k].resize(std::size_t(n)), g.c[k].data());
        parallel_for(exec, n, [&](long i0, long i1) {
            for (long i = i0; i < i1; ++i) q[i] = std::isfinite(p[i]) ? std::sqrt(std::clamp(p[i], 0.0f, 16.0f)) : 0.0f;
        }, 65536);
    }
    return g;
}

Status fill_holes(std::vector<float>& depth, int W, int H, const Guide& guide, const Exec& exec, std::size_t& filled) {
    const std::size_t n = depth.size();
    filled = 0;
    // Rings by breadth-first search from the known pixels: ring 0 the known
    // ones, ring 1 the holes beside them (found in parallel), then outwards
    // from ring 1 only (most of a map is known: it is not queued). The order
    // within a ring does not matter: its pixels read earlier rings only.
    std::vector<int> ring(n);
    std::vector<std::size_t> row_known(std::size_t(H), 0);
    std::vector<std::vector<int>> row_ring1(static_cast<std::size_t>(H));
    // A cancelled pass counts some rows' known pixels as none: stop before
    // that reads as "nothing to fill from".
    const bool ringed = parallel_for(exec, H, [&](long y0, long y1) {
        for (long y = y0; y < y1; ++y)
            for (std::size_t i = std::size_t(y) * std::size_t(W); i < std::size_t(y + 1) * std::size_t(W); ++i) {
                const bool known = !std::isnan(depth[i]);
                ring[i] = known ? 0 : -1;
                row_known[std::size_t(y)] += known ? 1 : 0;
            }
    }, 16);
    if (!ringed) return Status::cancelled("hole fill");
    std::size_t nknown = 0;
    for (std::size_t k : row_known) nknown += k;
    if (nknown == 0) return Status::error("the depth map has no valid value to fill its holes from");
    if (nknown == n) return Status::ok();
    const bool beside_known = parallel_for(exec, H, [&](long y0, long y1) {
        for (long y = y0; y < y1; ++y)
            for (int x = 0; x < W; ++x) {
                const std::size_t i = std::size_t(y) * std::size_t(W) + std::size_t(x);
                if (ring[i] == 0) continue;
                const bool beside = (x > 0 && ring[i - 1] == 0) || (x + 1 < W && ring[i + 1] == 0) ||
                                    (y > 0 && ring[i - std::size_t(W)] == 0) || (y + 1 < H && ring[i + std::size_t(W)] == 0);
                if (beside) row_ring1[std::size_t(y)].push_back(int(i));
            }
    }, 16);
    if (!beside_known) return Status::cancelled("hole fill");
    std::vector<std::vector<int>> rings(2);
    std::deque<int> queue;
    for (const std::vector<int>& row : row_ring1)
        for (int i : row) {
            ring[std::size_t(i)] = 1;
            rings[1].push_back(i);
            queue.push_back(i);
        }
    while (!queue.empty()) {
        const int i = queue.front();
        queue.pop_front();
        for_each_4_neighbour(i, W, H, [&](int j) {
            if (ring[std::size_t(j)] >= 0) return;
            const int r = ring[std::size_t(i)] + 1;
            ring[std::size_t(j)] = r;
            if (int(rings.size()) <= r) rings.resize(std::size_t(r) + 1);
            rings[std::size_t(r)].push_back(j);
            queue.push_back(j);
        });
    }
    // The holes that reach the frame's edge (flooded from their pixels on
    // it): their pixels never wait.
    std::vector<unsigned char> open(guide.empty() ? 0 : n, 0);
    if (!guide.empty()) {
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x) {
                const int i = y * W + x;
                if ((x == 0 || y == 0 || x == W - 1 || y == H - 1) && ring[std::size_t(i)] > 0) {
                    open[std::size_t(i)] = 1;
                    queue.push_back(i);
                }
            }
        while (!queue.empty()) {
            const int i = queue.front();
            queue.pop_front();
            for_each_4_neighbour(i, W, H, [&](int j) {
                if (ring[std::size_t(j)] == 0 || open[std::size_t(j)]) return;
                open[std::size_t(j)] = 1;
                queue.push_back(j);
            });
        }
    }
    const double inv_s = 1.0 / (2 * kSpatialSigma * kSpatialSigma);
    const double inv_wide = 1.0 / (2 * kWideSpatialSigma * kWideSpatialSigma);
    const double inv_c = 1.0 / (2 * kColourSigma * kColourSigma);
    // The spatial weights of both windows, once (the same values as computed
    // per candidate).
    auto spatial_table = [](int radius, double inv_spatial) {
        std::vector<double> t;
        for (int dy = -radius; dy <= radius; ++dy)
            for (int dx = -radius; dx <= radius; ++dx) t.push_back(std::exp(-(dx * dx + dy * dy) * inv_spatial));
        return t;
    };
    const std::vector<double> near_weight = spatial_table(kWindow, inv_s), wide_weight = spatial_table(kWideWindow, inv_wide);
    // How alike pixels i and j look in the plate (1: the same colour).
    auto affinity = [&](std::size_t i, std::size_t j) {
        double dc = 0;
        for (int c = 0; c < 3; ++c) {
            const double v = guide.c[c][i] - guide.c[c][j];
            dc += v * v;
        }
        return std::exp(-dc * inv_c);
    };
    std::vector<unsigned char> waits(guide.empty() ? 0 : n, 0);
    // Whether the first known pixel (ring 0: known from the start) in one of
    // the 8 directions from (x, y), within kRimSearch, has pixel i's colour.
    auto colour_on_rim = [&](int x, int y, int i) {
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
                if (dx == 0 && dy == 0) continue;
                for (int k = 1; k <= kRimSearch; ++k) {
                    const int xx = x + k * dx, yy = y + k * dy;
                    if (xx < 0 || xx >= W || yy < 0 || yy >= H) break;
                    const std::size_t j = std::size_t(yy) * std::size_t(W) + std::size_t(xx);
                    if (ring[j] != 0) continue;
                    if (affinity(std::size_t(i), j) >= kColourMatch) return true;
                    break;
                }
            }
        return false;
    };
    std::mutex waiting_lock;
    for (std::size_t r = 1; r < rings.size(); ++r) {
        const std::vector<int>& pixels = rings[r];
        std::vector<int> waiting;  // for ring r + 1: nothing alike in reach yet, or no known pixel in the window
        Status st = parallel_run(exec, long(pixels.size()), [&](long b, long e) {
            std::vector<Candidate> cand, sorted;
            std::vector<int> wait_here;
            for (long k = b; k < e; ++k) {
                const int i = pixels[std::size_t(k)];
                const int x = i % W, y = i / W;
                // The known pixels (earlier rings) within `radius`; returns
                // the best colour affinity among them.
                auto gather = [&](int radius, const std::vector<double>& spatial) {
                    cand.clear();
                    double best = 0;
                    for (int dy = -radius; dy <= radius; ++dy)
                        for (int dx = -radius; dx <= radius; ++dx) {
                            const int xx = x + dx, yy = y + dy;
                            if (xx < 0 || xx >= W || yy < 0 || yy >= H) continue;
                            const int j = yy * W + xx;
                            const int rj = ring[std::size_t(j)];
                            if (rj < 0 || std::size_t(rj) >= r) continue;
                            double w = spatial[std::size_t(dy + radius) * std::size_t(2 * radius + 1) + std::size_t(dx + radius)];
                            if (!guide.empty()) {
                                const double a = affinity(std::size_t(i), std::size_t(j));
                                best = std::max(best, a);
                                w *= a + 1e-6;  // never all zero
                            }
                            cand.push_back({depth[std::size_t(j)], w, dx, dy});
                        }
                    return best;
                };
                if (gather(kWindow, near_weight) < kColourMatch && !guide.empty()) {
                    const std::vector<Candidate> near = cand;
                    if (!(gather(kWideWindow, wide_weight) >= kColourMatch)) {  // nothing alike further either
                        const unsigned char waited = waits[std::size_t(i)];
                        if (!open[std::size_t(i)] && waited < kMaxWait && (waited > 0 || colour_on_rim(x, y, i))) {
                            wait_here.push_back(i);
                            continue;
                        }
                        cand = near;
                    }
                }
                // Empty only when the pixels that made its ring waited.
                if (cand.empty()) {
                    wait_here.push_back(i);
                    continue;
                }
                sorted = cand;
                depth[std::size_t(i)] = continue_surface(cand, weighted_median(sorted));
            }
            if (!wait_here.empty()) {
                const std::lock_guard<std::mutex> hold(waiting_lock);
                waiting.insert(waiting.end(), wait_here.begin(), wait_here.end());
            }
            return Status::ok();
        }, 256, "depth hole fill");
        if (!st) return st;
        filled += pixels.size() - waiting.size();
        if (waiting.empty()) continue;
        // Each pixel decided from earlier rings only: the same set for any
        // thread count (sorted: the same order too).
        std::sort(waiting.begin(), waiting.end());
        if (rings.size() <= r + 1) rings.resize(r + 2);
        for (int i : waiting) {
            ring[std::size_t(i)] = int(r + 1);
            if (!waits.empty() && waits[std::size_t(i)] < kMaxWait) ++waits[std::size_t(i)];
            rings[r + 1].push_back(i);
        }
    }
    return Status::ok();
}

}  // namespace gdof::plate_detail
