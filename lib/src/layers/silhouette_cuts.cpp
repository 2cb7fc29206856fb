// Auto's blur cuts for plates, at their silhouettes (SilhouetteGrid in
// layers_internal.h): which pairs of neighbours need a slice bound between
// their depths, what a bound at each depth would hide, and the fewest bounds
// that hide the least.
#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>

#include "layers/layers_internal.h"

namespace gdof::layers_detail {

namespace {

// The nearest depth within about `reach` px of each pixel: the least finite
// depth of cells of reach / 2 px, then the least over the cells within
// `reach` (a square of cells, min filter by rows then columns).
struct NearestAround {
    long cell = 1, gw = 0, gh = 0;
    std::vector<float> depth;  // per cell; +inf: nothing finite within reach
    float at(long x, long y) const { return depth[std::size_t(y / cell) * std::size_t(gw) + std::size_t(x / cell)]; }
};

NearestAround nearest_around(const SilhouetteGrid& g, double reach, const Exec& exec) {
    NearestAround n;
    const long W = g.width, H = g.height;
    // Past the frame's size every cell sees the whole frame; a blur field
    // may give absurd radii (a depth near 0 through a thin lens: 1e31 px),
    // which the diffusion refuses later, but not before this runs.
    const double frame_reach = double(W + H);
    if (!(reach < frame_reach)) reach = frame_reach;
    n.cell = std::max(1L, long(reach / 2.0));
    n.gw = (W + n.cell - 1) / n.cell;
    n.gh = (H + n.cell - 1) / n.cell;
    std::vector<float> v(std::size_t(n.gw * n.gh), float(kInf));
    const float* depth = g.depth;
    const unsigned char* present = g.present;
    parallel_for(exec, n.gh, [&](long c0, long c1) {
        for (long cy = c0; cy < c1; ++cy)
            for (long y = cy * n.cell; y < std::min(H, (cy + 1) * n.cell); ++y)
                for (long x = 0; x < W; ++x) {
                    const std::size_t i = std::size_t(y) * std::size_t(W) + std::size_t(x);
                    float& c = v[std::size_t(cy * n.gw + x / n.cell)];
                    if (present[i] && depth[i] > 0.0f) c = std::min(c, depth[i]);
                }
    });
    const long k = std::max(1L, long(std::ceil(reach / double(n.cell))));
    auto min_filter = [&](long len, long count, long along, long across) {
        std::vector<float> line(static_cast<std::size_t>(len));
        for (long a = 0; a < count; ++a) {
            for (long t = 0; t < len; ++t) line[std::size_t(t)] = v[std::size_t(a * across + t * along)];
            for (long t = 0; t < len; ++t) {
                float m = float(kInf);
                for (long u = std::max(0L, t - k); u <= std::min(len - 1, t + k); ++u) m = std::min(m, line[std::size_t(u)]);
                v[std::size_t(a * across + t * along)] = m;
            }
        }
    };
    min_filter(n.gw, n.gh, 1, n.gw);
    min_filter(n.gh, n.gw, n.gw, 1);
    n.depth = std::move(v);
    return n;
}

// How much a silhouette needs a bound, from the nearer side's radius minus
// the farther's: all of it where the nearer is more blurred (in one layer the
// sharper background would insulate its spread), a kReverseNeed-th where the
// farther is (one layer only reflects the background's blur at the front's
// edge instead of continuing it behind; that matters for thin fronts, poles,
// when the difference is large).
float need_weight(float near_minus_far) {
    return near_minus_far >= 0.0f ? near_minus_far : -near_minus_far / float(kReverseNeed);
}

}  // namespace

SilhouetteScan scan_silhouettes(const LogHistogram& h, const SilhouetteGrid& g, double min_dr, double reach,
                                const Exec& exec) {
    const long W = g.width, H = g.height, nb = h.nbins;
    // The cost needs every pixel's bin (a log per pixel): above 2 Mpx it is
    // counted on every `stride`-th row only, enough to rank positions.
    const long stride = std::max(1L, long(std::sqrt(double(W) * double(H) / 2.0e6)));
    // Fixed bands (not one per thread): the same sums and needs for any
    // thread count.
    const long nbands = std::min(H, 32L);
    std::vector<std::vector<double>> diff(static_cast<std::size_t>(nbands));
    std::vector<std::vector<CutNeed>> needs(static_cast<std::size_t>(nbands));
    const float* depth = g.depth;
    const float* radius = g.radius;
    const unsigned char* present = g.present;
    const double ratio = g.continuity;
    auto bin = [&](float z) { return h.bin_of(std::log(double(z))); };
    const NearestAround around = nearest_around(g, reach, exec);
    const float *cr = g.rgb[0], *cg = g.rgb[1], *cb = g.rgb[2];
    const bool scanned = parallel_for(exec, nbands, [&](long b0, long b1) {
        for (long band = b0; band < b1; ++band) {
            std::vector<double>& d = diff[std::size_t(band)];
            std::vector<CutNeed>& nd = needs[std::size_t(band)];
            d.assign(std::size_t(nb) + 2, 0);
            auto pair = [&](std::size_t i, std::size_t j) {
                const float za = depth[i], zb = depth[j];
                if (!(za > 0.0f) || !(zb > 0.0f) || same_surface(za, zb, ratio)) return;
                if (std::isinf(za) && std::isinf(zb)) return;  // sky next to sky
                const float near = std::min(za, zb), far = std::max(za, zb);
                const float dr = need_weight(za < zb ? radius[i] - radius[j] : radius[j] - radius[i]);
                if (!(dr > min_dr)) return;
                const long a = bin(near), f = std::isinf(far) ? nb : bin(far);
                if (a < f) nd.push_back({a, f, dr});
            };
            const long y0 = H * band / nbands, y1 = H * (band + 1) / nbands;
            for (long y = y0; y < y1; ++y) {
                const bool costs = y % stride == 0;
                const std::size_t row = std::size_t(y) * std::size_t(W);
                for (long x = 0; x < W; ++x) {
                    const std::size_t i = row + std::size_t(x);
                    if (!present[i]) continue;
                    if (x + 1 < W && present[i + 1]) pair(i, i + 1);
                    if (y + 1 < H && present[i + std::size_t(W)]) pair(i, i + std::size_t(W));
                    if (!costs || !(depth[i] > 0.0f) || std::isinf(depth[i])) continue;
                    // Behind every bound between the nearest depth around and its own.
                    const float m = around.at(x, y);
                    const double light = std::fabs(double(cr[i])) + std::fabs(double(cg[i])) + std::fabs(double(cb[i]));
                    if (!(m < depth[i]) || !std::isfinite(light)) continue;
                    const long bm = bin(m), bi = bin(depth[i]);
                    if (bm >= bi) continue;
                    d[std::size_t(bm) + 1] += light;  // edges bm+1..bi
                    d[std::size_t(bi) + 1] -= light;
                }
            }
        }
    });
    SilhouetteScan out;
    out.cost.assign(std::size_t(nb) + 1, 0);
    // Cancelled: bands the loop skipped have no sums; the caller reports it.
    if (!scanned) return out;
    double run = 0;
    for (long e = 0; e <= nb; ++e) {
        for (const auto& d : diff) run += d[std::size_t(e)];
        out.cost[std::size_t(e)] = e == nb ? 0 : run;  // the sky is not counted
    }
    std::vector<CutNeed> all;
    for (const auto& nd : needs) all.insert(all.end(), nd.begin(), nd.end());
    for (const SilhouetteGrid::Front& m : g.fronts) {
        const float dr = need_weight(m.fg_radius - m.radius);
        if (!(m.fg_depth > 0.0f) || !(dr > min_dr) || !(m.depth > m.fg_depth)) continue;
        const long a = bin(m.fg_depth), f = std::isinf(m.depth) ? nb : bin(m.depth);
        if (a < f) all.push_back({a, f, dr});
    }
    std::sort(all.begin(), all.end(), [](const CutNeed& p, const CutNeed& q) { return p.a != q.a ? p.a < q.a : p.f < q.f; });
    for (const CutNeed& c : all) {
        if (!out.needs.empty() && out.needs.back().a == c.a && out.needs.back().f == c.f)
            out.needs.back().dr = std::max(out.needs.back().dr, c.dr);
        else
            out.needs.push_back(c);
    }
    return out;
}

// The fewest bounds that separate every need with dr > step not already
// separated by `fixed` (the gaps), and of those the set that hides the least
// light (SilhouetteScan::cost): a dynamic programme over the edges, best[e]
// the best set whose last bound is at e; the bound before e may lie only
// where no need falls between the two (after last_a[e]), a window slid with
// a monotone queue.
std::vector<double> silhouette_cuts(const LogHistogram& h, const SilhouetteScan& scan, const std::vector<double>& fixed,
                                    double step, double zmax) {
    const long nb = h.nbins;
    std::vector<long> fixed_edges;  // the gaps' bins: a gap at depth g separates a < bin(g) <= f
    for (double gd : fixed) fixed_edges.push_back(h.bin_of(std::log(gd)));
    // last_a[e]: the largest near bin of the needs whose far bin is < e.
    std::vector<long> last_a(std::size_t(nb) + 2, -1);
    long max_a = -1;
    for (const CutNeed& c : scan.needs) {
        if (!(double(c.dr) > step)) continue;
        bool separated = false;
        for (long fe : fixed_edges) separated = separated || (c.a < fe && fe <= c.f);
        if (separated) continue;
        last_a[std::size_t(c.f) + 1] = std::max(last_a[std::size_t(c.f) + 1], c.a);
        max_a = std::max(max_a, c.a);
    }
    if (max_a < 0) return {};
    for (long e = 1; e <= nb + 1; ++e) last_a[std::size_t(e)] = std::max(last_a[std::size_t(e)], last_a[std::size_t(e) - 1]);
    // Cost of a set: (number of bounds, light hidden), compared in that order.
    struct Cost {
        long n = 0;
        double light = 0;
        bool operator<(const Cost& o) const { return n != o.n ? n < o.n : light < o.light; }
    };
    const Cost kNone{std::numeric_limits<long>::max(), 0};
    std::vector<Cost> best(std::size_t(nb) + 1, kNone);
    std::vector<long> prev(std::size_t(nb) + 1, 0);  // 0: none before
    std::deque<long> q;                               // edges in the window, best[] increasing
    long next_in = 1;
    for (long e = 1; e <= nb; ++e) {
        // The window for the bound before e: (last_a[e], e).
        while (next_in < e) {
            if (best[std::size_t(next_in)].n != kNone.n) {
                while (!q.empty() && !(best[std::size_t(q.back())] < best[std::size_t(next_in)])) q.pop_back();
                q.push_back(next_in);
            }
            ++next_in;
        }
        while (!q.empty() && q.front() <= last_a[std::size_t(e)]) q.pop_front();
        Cost c = kNone;
        if (last_a[std::size_t(e)] < 0) {
            c = Cost{1, scan.cost[std::size_t(e)]};
            prev[std::size_t(e)] = 0;
        }
        if (!q.empty()) {
            const Cost& p = best[std::size_t(q.front())];
            const Cost via{p.n + 1, p.light + scan.cost[std::size_t(e)]};
            if (via < c) {
                c = via;
                prev[std::size_t(e)] = q.front();
            }
        }
        best[std::size_t(e)] = c;
    }
    long end = 0;
    for (long e = max_a + 1; e <= nb; ++e)
        if (best[std::size_t(e)].n != kNone.n && (end == 0 || best[std::size_t(e)] < best[std::size_t(end)])) end = e;
    std::vector<double> cuts;
    for (long e = end; e > 0; e = prev[std::size_t(e)])
        cuts.push_back(e == nb ? zmax * (1.0 + 1e-12) : h.edge_depth(e));
    std::sort(cuts.begin(), cuts.end());
    return cuts;
}


}  // namespace gdof::layers_detail
