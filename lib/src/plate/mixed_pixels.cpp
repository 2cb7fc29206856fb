// Mixed pixels at silhouettes: a renderer's filtered Z (the mean depth of the
// samples that hit) and a depth sensor's "flying pixels" put a silhouette
// pixel at a depth between the foreground's and the background's, where no
// surface is. Such a pixel takes the nearer surface's depth: part of it is
// the foreground, whose blur must carry it (left between, it would land in a
// slice of its own, with a blur that neither surface has). Splitting it into
// a foreground share and a background part instead measured worse at every
// depth edge of the benchmark (docs/diffusion.md, "Mixed pixels"), except at
// the edge of a front sharper than its background (sharp_fronts.cpp).
//
// Candidates (for speckle removal, which leaves them alone) are sandwiched:
// an adjacent pixel nearer and one farther than it by more than `continuity`
// (a pixel of a sloping surface next to a silhouette is continued by its own
// surface on one side).
#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include "plate/plate_internal.h"

namespace gdof::plate_detail {

namespace {

// Each pixel's 3x3 minimum and maximum over the depths `keep` accepts (the
// others, and beyond the image, count as lo_none / hi_none), a row at a time
// from rows' 3-wide spans kept in a ring of three: whole-row loops that the
// compiler vectorises. A first look for the mixed-pixel tests below, which
// look again, exactly, only where the span is large. Rows in order from the
// first asked for (one per task).
template <class Keep>
class Span3x3 {
public:
    Span3x3(const std::vector<float>& depth, int W, int H, Keep keep, float lo_none, float hi_none)
        : d_(depth.data()), w_(std::size_t(W)), h_(H), keep_(keep), lo_none_(lo_none), hi_none_(hi_none),
          pad_lo_(w_ + 2), pad_hi_(w_ + 2), ring_lo_(3 * w_), ring_hi_(3 * w_), lo_(w_), hi_(w_) {}
    // The spans of row y: lo()[x], hi()[x].
    void row(int y) {
        if (!primed_)
            for (int r = std::max(0, y - 1); r <= y; ++r) row_span(r);
        if (y + 1 < h_) row_span(y + 1);
        primed_ = true;
        const int ya = std::max(0, y - 1), yb = std::min(h_ - 1, y + 1);
        std::copy_n(ring_lo_.data() + std::size_t(ya % 3) * w_, w_, lo_.data());
        std::copy_n(ring_hi_.data() + std::size_t(ya % 3) * w_, w_, hi_.data());
        float *lo = lo_.data(), *hi = hi_.data();
        const std::size_t w = w_;
        for (int yy = ya + 1; yy <= yb; ++yy) {
            const float* rl = ring_lo_.data() + std::size_t(yy % 3) * w;
            const float* rh = ring_hi_.data() + std::size_t(yy % 3) * w;
            for (std::size_t x = 0; x < w; ++x) {
                lo[x] = std::min(lo[x], rl[x]);
                hi[x] = std::max(hi[x], rh[x]);
            }
        }
    }
    const float* lo() const { return lo_.data(); }
    const float* hi() const { return hi_.data(); }

private:
    void row_span(int y) {
        const float* d = d_ + std::size_t(y) * w_;
        float *pl = pad_lo_.data(), *ph = pad_hi_.data();
        const std::size_t w = w_;
        const float ln = lo_none_, hn = hi_none_;
        pl[0] = pl[w + 1] = ln;
        ph[0] = ph[w + 1] = hn;
        for (std::size_t x = 0; x < w; ++x) {
            const bool k = keep_(d[x]);
            pl[x + 1] = k ? d[x] : ln;
            ph[x + 1] = k ? d[x] : hn;
        }
        float* lo = ring_lo_.data() + std::size_t(y % 3) * w;
        float* hi = ring_hi_.data() + std::size_t(y % 3) * w;
        for (std::size_t x = 0; x < w; ++x) {
            lo[x] = std::min(std::min(pl[x], pl[x + 1]), pl[x + 2]);
            hi[x] = std::max(std::max(ph[x], ph[x + 1]), ph[x + 2]);
        }
    }
    const float* d_;
    std::size_t w_;
    int h_;
    bool primed_ = false;  // the ring holds the rows before the one asked for
    Keep keep_;
    float lo_none_, hi_none_;
    std::vector<float> pad_lo_, pad_hi_, ring_lo_, ring_hi_, lo_, hi_;
};

}  // namespace

std::vector<unsigned char> mixed_candidates(const std::vector<float>& depth, int W, int H, double continuity,
                                            const Exec& exec) {
    std::vector<unsigned char> cand(depth.size(), 0);
    // A candidate's two sides differ by more than continuity^2 in 1 / depth,
    // so its 3x3 depths (finite ones) do too: a pixel whose 3x3 spans less
    // (most of a plate) is skipped without the divisions below. The margin
    // covers their rounding.
    const double flat_span = continuity * continuity * 0.999;
    // 1 / depth at (x, y); NaN outside the image or without a finite depth.
    auto inv = [&](int x, int y) {
        if (x < 0 || x >= W || y < 0 || y >= H) return std::numeric_limits<double>::quiet_NaN();
        const float q = depth[std::size_t(y) * std::size_t(W) + std::size_t(x)];
        return std::isfinite(q) ? 1.0 / double(q) : std::numeric_limits<double>::quiet_NaN();
    };
    const int dirs[4][2] = {{1, 0}, {0, 1}, {1, 1}, {1, -1}};
    parallel_for(exec, H, [&, W, H, flat_span](long r0, long r1) {
        // The 3x3 span of the finite depths (+inf and 0 where none).
        auto finite = [](float v) { return std::abs(v) <= std::numeric_limits<float>::max(); };
        Span3x3 span(depth, W, H, finite, std::numeric_limits<float>::infinity(), 0.0f);
        const std::size_t w = std::size_t(W);
        std::vector<unsigned char> steep(w);
        for (int y = int(r0); y < int(r1); ++y) {
            span.row(y);
            const float *near = span.lo(), *far = span.hi();
            for (std::size_t x = 0; x < w; ++x) steep[x] = double(far[x]) > double(near[x]) * flat_span;
            for (int x = 0; x < W; ++x) {
                if (!steep[std::size_t(x)]) continue;
                const double d = inv(x, y);
                if (std::isnan(d)) continue;
                for (const auto& dir : dirs) {
                    // Along a line through the pixel: one side nearer, the other
                    // farther, each by more than `continuity` (sky and holes have
                    // no depth to mix with) ...
                    const double a = inv(x - dir[0], y - dir[1]), b = inv(x + dir[0], y + dir[1]);
                    if (std::isnan(a) || std::isnan(b)) continue;
                    const double hi = std::max(a, b), lo = std::min(a, b);
                    if (!(hi > d * continuity && d > lo * continuity)) continue;
                    // ... and the two sides much flatter than the jump: a step with
                    // one pixel between, not a surface receding steeply (a floor at
                    // a grazing angle, where 1/depth is a straight ramp).
                    const double a2 = inv(x - 2 * dir[0], y - 2 * dir[1]);
                    const double b2 = inv(x + 2 * dir[0], y + 2 * dir[1]);
                    const double sa = std::isnan(a2) ? 0.0 : std::abs(a2 - a);
                    const double sb = std::isnan(b2) ? 0.0 : std::abs(b2 - b);
                    if (sa + sb < 0.5 * (hi - lo)) {
                        cand[std::size_t(y) * w + std::size_t(x)] = 1;
                        break;
                    }
                }
            }
        }
    }, 16);
    return cand;
}

namespace {

// "Between" the nearest and farthest neighbours: more than 2% from each. A
// ramp of mixed pixels (a wide anti-aliasing filter) moves whole; a surface
// next to the step, whose pixels vary by less, stays. (5% left a third of
// the gain at the Cornell box's edges; 0 eroded the background's pixels
// beside every silhouette.)
constexpr double kBetween = 1.02;
// Halfway between a step (the 5x5 window spans what the 3x3 does) and a
// ramp (twice as much), in log depth.
constexpr double kRamp = 1.5;

// A pixel beside another mixed pixel sees that one's depth, which is no
// surface's, as its nearest neighbour (a sphere's pixel next to a pole's
// anti-aliased edge took the edge's depth, and a blur of no surface there).
// Each is looked at again among its unmoved neighbours only: one whose depth
// is within kBetween of one of theirs lies on that surface and stays; the
// others take the nearest of their unmoved depths that is nearer than their
// own, where there is one (else the first look's).
void drop_on_surfaces(std::vector<std::vector<MixedStep>>& rows, const std::vector<float>& depth, int W, int H,
                      const Exec& exec) {
    if (std::all_of(rows.begin(), rows.end(), [](const auto& row) { return row.empty(); })) return;
    std::vector<unsigned char> moved(depth.size(), 0);
    for (const auto& row : rows)
        for (const MixedStep& m : row) moved[m.index] = 1;
    parallel_for(exec, H, [&, W, H](long r0, long r1) {
        for (long y = r0; y < r1; ++y) {
            auto& row = rows[std::size_t(y)];
            std::size_t kept = 0;
            for (MixedStep m : row) {
                const int x = int(m.index % std::size_t(W));
                const double d = depth[m.index];
                bool on_surface = false;
                float near = std::numeric_limits<float>::infinity();
                for (long yy = std::max(0L, y - 1); yy <= std::min(long(H) - 1, y + 1); ++yy)
                    for (int xx = std::max(0, x - 1); xx <= std::min(W - 1, x + 1); ++xx) {
                        const std::size_t j = std::size_t(yy) * std::size_t(W) + std::size_t(xx);
                        const float q = depth[j];
                        if (moved[j] || !std::isfinite(q)) continue;
                        if (d <= double(q) * kBetween && double(q) <= d * kBetween) on_surface = true;
                        if (double(q) * kBetween < d) near = std::min(near, q);
                    }
                if (on_surface) continue;
                if (std::isfinite(near)) m.near = near;
                row[kept++] = m;
            }
            row.resize(kept);
        }
    }, 16);
}

}  // namespace

std::size_t mixed_to_nearer(std::vector<float>& depth, int W, int H, double mixed_step, const Exec& exec,
                            std::vector<MixedStep>* steps) {
    // Decisions read the depths as measured: the changes (few) are listed
    // per row and written after.
    std::vector<std::vector<MixedStep>> row_changes(static_cast<std::size_t>(H));
    // The nearest and farthest depth of the (2r+1)^2 window around (x, y),
    // from (near, far) on (sky is farthest; holes do not count).
    auto window = [&](int x, int y, int r, float& near, float& far) {
        for (int yy = std::max(0, y - r); yy <= std::min(H - 1, y + r); ++yy)
            for (int xx = std::max(0, x - r); xx <= std::min(W - 1, x + r); ++xx) {
                const float q = depth[std::size_t(yy) * std::size_t(W) + std::size_t(xx)];
                if (std::isnan(q)) continue;
                near = std::min(near, q);
                far = std::max(far, q);
            }
    };
    parallel_for(exec, H, [&, W, H, mixed_step](long r0, long r1) {
        // A first look at every pixel's 3x3 span of the depths that are not
        // holes (sky counts: it is farthest); only a pixel whose span reaches
        // a step is looked at again, exactly, below.
        auto not_hole = [](float v) { return v == v; };
        constexpr float kInfF = std::numeric_limits<float>::infinity();
        Span3x3 span(depth, W, H, not_hole, kInfF, -kInfF);
        const std::size_t w = std::size_t(W);
        std::vector<unsigned char> step(w);
        for (int y = int(r0); y < int(r1); ++y) {
            span.row(y);
            const float *lo3 = span.lo(), *hi3 = span.hi();
            // The window holds the pixel itself, so its span is the exact
            // test's but for the sign of a zero, which no comparison sees.
            for (std::size_t x = 0; x < w; ++x) step[x] = double(hi3[x]) >= double(lo3[x]) * mixed_step;
            for (int x = 0; x < W; ++x) {
                if (!step[std::size_t(x)]) continue;
                const std::size_t i = std::size_t(y) * std::size_t(W) + std::size_t(x);
                const float d = depth[i];
                if (!std::isfinite(d)) continue;
                float near = d, far = d;
                window(x, y, 1, near, far);
                if (!(double(far) >= double(near) * mixed_step)) continue;
                if (!(double(d) > double(near) * kBetween && double(d) * kBetween < double(far))) continue;
                // A step, not a surface receding steeply (a floor at a grazing
                // angle, a ramp in a proxy's depth): the 5x5 window spans
                // little more than the 3x3 (in log depth: a ramp doubles it).
                if (std::isfinite(far)) {
                    float near5 = near, far5 = far;
                    window(x, y, 2, near5, far5);
                    if (std::log(double(far5) / double(near5)) > kRamp * std::log(double(far) / double(near))) continue;
                }
                row_changes[std::size_t(y)].push_back({i, near, far});
            }
        }
    }, 16);
    drop_on_surfaces(row_changes, depth, W, H, exec);
    std::size_t n = 0;
    for (const auto& row : row_changes) {
        for (const MixedStep& m : row) depth[m.index] = m.near;
        n += row.size();
        if (steps) steps->insert(steps->end(), row.begin(), row.end());
    }
    return n;
}

// Holes at silhouettes (plate_internal.h): the colour of a filled hole next
// to a depth step says which surface it shows, or how much of each.
std::vector<MixedPixel> split_silhouette_holes(std::vector<float>& depth, const std::vector<unsigned char>& was_hole,
                                               const std::vector<unsigned char>& candidate, int W, int H,
                                               double continuity, double mixed_step, const float* const rgb[3],
                                               std::size_t& recoloured) {
    std::vector<MixedPixel> out;
    recoloured = 0;
    if (!rgb[0] || !rgb[1] || !rgb[2]) return out;
    constexpr int kR = 3;  // a 7x7 window
    // Only holes are written below, so the measured pixels the decisions read
    // keep their depths throughout.
    auto pure = [&](std::size_t j) { return !was_hole[j] && !candidate[j] && std::isfinite(depth[j]); };
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const std::size_t i = std::size_t(y) * std::size_t(W) + std::size_t(x);
            if (!was_hole[i] || !std::isfinite(depth[i])) continue;
            // fn(j, squared distance) for the measured pixels of the window.
            auto for_each_pure = [&](auto&& fn) {
                for (int yy = std::max(0, y - kR); yy <= std::min(H - 1, y + kR); ++yy)
                    for (int xx = std::max(0, x - kR); xx <= std::min(W - 1, x + kR); ++xx) {
                        const std::size_t j = std::size_t(yy) * std::size_t(W) + std::size_t(xx);
                        if (pure(j)) fn(j, (xx - x) * (xx - x) + (yy - y) * (yy - y));
                    }
            };
            float near = std::numeric_limits<float>::infinity(), far = -near;
            for_each_pure([&](std::size_t j, int) {
                near = std::min(near, depth[j]);
                far = std::max(far, depth[j]);
            });
            if (!(far >= near) || double(far) < double(near) * mixed_step) continue;
            // Each surface's measured pixels nearest to the hole (all at the
            // least distance): their mean colour and depth. And a step, not a
            // surface receding steeply (a floor at a grazing angle spans the
            // ratio in a few rows): the measured depths form two groups, with
            // at most a quarter of them between.
            SideColour fg, bg;
            int between = 0, total = 0;
            for_each_pure([&](std::size_t j, int d2) {
                const float q = depth[j];
                ++total;
                const bool is_fg = double(q) <= double(near) * continuity, is_bg = double(q) * continuity >= double(far);
                if (!is_fg && !is_bg) {
                    ++between;
                    return;
                }
                (is_fg ? fg : bg).add(d2, rgb, j, q);
            });
            if (between * 4 > total) continue;
            if (!fg.n || !bg.n) continue;
            double f[3], b[3];
            fg.mean(f);
            bg.mean(b);
            const float pixel[3] = {rgb[0][i], rgb[1][i], rgb[2][i]};
            const double share = colour_share(f, b, pixel);
            if (std::isnan(share)) continue;
            const float fg_depth = float(fg.depth / fg.n), bg_depth = float(bg.depth / bg.n);
            ++recoloured;
            if (share >= 1.0 - kPureShare) {
                depth[i] = fg_depth;
                continue;
            }
            if (share <= kPureShare) {
                depth[i] = bg_depth;
                continue;
            }
            MixedPixel m;
            m.index = i;
            m.fg_depth = fg_depth;
            m.fg_share = float(share);
            unmix(m, pixel, f, b);
            depth[i] = bg_depth;
            out.push_back(m);
        }
    return out;
}

}  // namespace gdof::plate_detail
