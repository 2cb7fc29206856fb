// Mixed pixels at silhouettes: a renderer's filtered Z (the mean depth of the
// samples that hit) and a depth sensor's "flying pixels" put a silhouette
// pixel at a depth between the foreground's and the background's, where no
// surface is. Such a pixel takes the nearer surface's depth: part of it is
// the foreground, whose blur must carry it (left between, it would land in a
// slice of its own, with a blur that neither surface has). Splitting it into
// a foreground share and a background part instead measured worse at every
// depth edge of the benchmark (docs/diffusion.md, "Mixed pixels").
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
    // The 3x3 span from each row's 3-wide minimum and maximum of its finite
    // depths (+inf and 0 where none), rows y - 1 .. y + 1 kept in a ring:
    // loops over whole rows that the compiler vectorises.
    const std::size_t w = std::size_t(W);
    std::vector<float> pad_lo(w + 2), pad_hi(w + 2), ring_lo(3 * w), ring_hi(3 * w), near(w), far(w);
    std::vector<unsigned char> steep(w);
    auto row_span = [&](int y) {
        const float* d = depth.data() + std::size_t(y) * w;
        pad_lo[0] = pad_lo[w + 1] = std::numeric_limits<float>::infinity();
        pad_hi[0] = pad_hi[w + 1] = 0.0f;
        for (std::size_t x = 0; x < w; ++x) {
            const bool finite = std::abs(d[x]) <= std::numeric_limits<float>::max();
            pad_lo[x + 1] = finite ? d[x] : std::numeric_limits<float>::infinity();
            pad_hi[x + 1] = finite ? d[x] : 0.0f;
        }
        float* lo = ring_lo.data() + std::size_t(y % 3) * w;
        float* hi = ring_hi.data() + std::size_t(y % 3) * w;
        for (std::size_t x = 0; x < w; ++x) {
            lo[x] = std::min(std::min(pad_lo[x], pad_lo[x + 1]), pad_lo[x + 2]);
            hi[x] = std::max(std::max(pad_hi[x], pad_hi[x + 1]), pad_hi[x + 2]);
        }
    };
    for (int y = std::max(0, int(r0) - 1); y < std::min(H, int(r0) + 1); ++y) row_span(y);
    for (int y = int(r0); y < int(r1); ++y) {
        if (y + 1 < H) row_span(y + 1);
        const int ya = std::max(0, y - 1), yb = std::min(H - 1, y + 1);
        std::copy_n(ring_lo.data() + std::size_t(ya % 3) * w, w, near.data());
        std::copy_n(ring_hi.data() + std::size_t(ya % 3) * w, w, far.data());
        for (int yy = ya + 1; yy <= yb; ++yy) {
            const float* lo = ring_lo.data() + std::size_t(yy % 3) * w;
            const float* hi = ring_hi.data() + std::size_t(yy % 3) * w;
            for (std::size_t x = 0; x < w; ++x) {
                near[x] = std::min(near[x], lo[x]);
                far[x] = std::max(far[x], hi[x]);
            }
        }
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
                const double a2 = inv(x - 2 * dir[0], y - 2 * dir[1]), b2 = inv(x + 2 * dir[0], y + 2 * dir[1]);
                const double sa = std::isnan(a2) ? 0.0 : std::abs(a2 - a), sb = std::isnan(b2) ? 0.0 : std::abs(b2 - b);
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

// Silhouette holes (split_silhouette_holes): the two surfaces' colours must
// differ by this fraction of the larger channel value to be told apart; the
// pixel may lie this far off the line between them (in units of their
// difference) and its share this far outside [0, 1]; a share within
// kPureShare of 0 or 1 is all background or all foreground.
constexpr double kDistinctColours = 0.1;
constexpr double kResidual = 0.35;
constexpr double kShareSlack = 0.25;
constexpr double kPureShare = 0.1;

// The parts' colours: each surface's colour (`fg`, `bg`), both moved by the
// residual so that the parts composite back exactly:
// share * fg + (1 - share) * bg = pixel.
void unmix(MixedPixel& m, const float pixel[3], const double fg[3], const double bg[3]) {
    for (int c = 0; c < 3; ++c) {
        const double r = pixel[c] - (m.fg_share * fg[c] + (1.0 - m.fg_share) * bg[c]);
        m.fg_rgb[c] = float(fg[c] + r);
        m.bg_rgb[c] = float(bg[c] + r);
        // No negative light: give the deficit to the other part.
        if (m.fg_rgb[c] < 0) {
            m.fg_rgb[c] = 0;
            m.bg_rgb[c] = float(pixel[c] / (1.0 - m.fg_share));
        } else if (m.bg_rgb[c] < 0) {
            m.bg_rgb[c] = 0;
            m.fg_rgb[c] = float(pixel[c] / m.fg_share);
        }
    }
}

}  // namespace

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

}  // namespace

std::size_t mixed_to_nearer(std::vector<float>& depth, int W, int H, double mixed_step, const Exec& exec) {
    // Decisions read the depths as measured: the changes (few) are listed
    // per row and written after.
    std::vector<std::vector<std::pair<std::size_t, float>>> row_changes(static_cast<std::size_t>(H));
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
        // A first look at every pixel's 3x3 span from rows' 3-wide minima and
        // maxima of the non-hole depths (whole-row loops the compiler
        // vectorises, rows y - 1 .. y + 1 in a ring); only a pixel whose span
        // reaches a step is looked at again, exactly, below.
        const std::size_t w = std::size_t(W);
        constexpr float kInfF = std::numeric_limits<float>::infinity();
        std::vector<float> pad_lo(w + 2), pad_hi(w + 2), ring_lo(3 * w), ring_hi(3 * w), lo3(w), hi3(w);
        std::vector<unsigned char> step(w);
        auto row_span = [&](int y) {
            const float* d = depth.data() + std::size_t(y) * w;
            pad_lo[0] = pad_lo[w + 1] = kInfF;
            pad_hi[0] = pad_hi[w + 1] = -kInfF;
            for (std::size_t x = 0; x < w; ++x) {
                const bool hole = d[x] != d[x];  // NaN
                pad_lo[x + 1] = hole ? kInfF : d[x];
                pad_hi[x + 1] = hole ? -kInfF : d[x];
            }
            float* lo = ring_lo.data() + std::size_t(y % 3) * w;
            float* hi = ring_hi.data() + std::size_t(y % 3) * w;
            for (std::size_t x = 0; x < w; ++x) {
                lo[x] = std::min(std::min(pad_lo[x], pad_lo[x + 1]), pad_lo[x + 2]);
                hi[x] = std::max(std::max(pad_hi[x], pad_hi[x + 1]), pad_hi[x + 2]);
            }
        };
        for (int y = std::max(0, int(r0) - 1); y < std::min(H, int(r0) + 1); ++y) row_span(y);
        for (int y = int(r0); y < int(r1); ++y) {
            if (y + 1 < H) row_span(y + 1);
            const int ya = std::max(0, y - 1), yb = std::min(H - 1, y + 1);
            std::copy_n(ring_lo.data() + std::size_t(ya % 3) * w, w, lo3.data());
            std::copy_n(ring_hi.data() + std::size_t(ya % 3) * w, w, hi3.data());
            for (int yy = ya + 1; yy <= yb; ++yy) {
                const float* lo = ring_lo.data() + std::size_t(yy % 3) * w;
                const float* hi = ring_hi.data() + std::size_t(yy % 3) * w;
                for (std::size_t x = 0; x < w; ++x) {
                    lo3[x] = std::min(lo3[x], lo[x]);
                    hi3[x] = std::max(hi3[x], hi[x]);
                }
            }
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
                row_changes[std::size_t(y)].push_back({i, near});
            }
        }
    }, 16);
    std::size_t n = 0;
    for (const auto& row : row_changes) {
        for (const auto& [i, near] : row) depth[i] = near;
        n += row.size();
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
            struct Side {
                int dist2 = std::numeric_limits<int>::max(), n = 0;
                double rgb[3] = {0, 0, 0}, depth = 0;
            } fg, bg;
            int between = 0, total = 0;
            for_each_pure([&](std::size_t j, int d2) {
                const float q = depth[j];
                ++total;
                const bool is_fg = double(q) <= double(near) * continuity, is_bg = double(q) * continuity >= double(far);
                if (!is_fg && !is_bg) {
                    ++between;
                    return;
                }
                Side& sd = is_fg ? fg : bg;
                if (d2 > sd.dist2) return;
                if (d2 < sd.dist2) sd = Side{d2, 0, {0, 0, 0}, 0};
                for (int c = 0; c < 3; ++c) sd.rgb[c] += rgb[c][j];
                sd.depth += q;
                ++sd.n;
            });
            if (between * 4 > total) continue;
            if (!fg.n || !bg.n) continue;
            double f[3], b[3], p[3], den = 0, num = 0, fb_scale = 0;
            for (int c = 0; c < 3; ++c) {
                f[c] = fg.rgb[c] / fg.n;
                b[c] = bg.rgb[c] / bg.n;
                p[c] = rgb[c][i];
                den += (f[c] - b[c]) * (f[c] - b[c]);
                num += (p[c] - b[c]) * (f[c] - b[c]);
                fb_scale = std::max({fb_scale, std::abs(f[c]), std::abs(b[c])});
            }
            // Surfaces too alike in colour to tell apart: the fill stays.
            if (!(den > 0.0) || std::sqrt(den) < kDistinctColours * fb_scale) continue;
            const double share = num / den;
            // The pixel must lie near the line between the two colours
            // (texture or a third surface otherwise): the fill stays.
            double res = 0;
            for (int c = 0; c < 3; ++c) {
                const double m = share * f[c] + (1.0 - share) * b[c];
                res += (p[c] - m) * (p[c] - m);
            }
            if (share < -kShareSlack || share > 1.0 + kShareSlack || res > kResidual * kResidual * den) continue;
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
            const float pixel[3] = {rgb[0][i], rgb[1][i], rgb[2][i]};
            unmix(m, pixel, f, b);
            depth[i] = bg_depth;
            out.push_back(m);
        }
    return out;
}

}  // namespace gdof::plate_detail
