// A layer prepared for vibrate_layers: its pixels, radii and blend weights
// over the region whose sources can matter, and per source the two measures
// that size its footprint (how fast it moves with the aperture sample, how
// much the warp stretches around it).
#include <algorithm>
#include <cmath>

#include "gdof/fill.h"
#include "psf_field/vibrate_internal.h"

namespace gdof::vibrate_detail {

namespace {

constexpr float kFarDepth = 1e30f;  // stands in for +inf depth in sums
constexpr double kStretchCap = 16.0;  // px: a larger jump is a tear, not a crack to fill

// Displacements at the four probe samples (+u, -u, +v, -v) of a point.
struct Probes {
    PsfDisplacement d[4];
};

Probes probe(const PsfField& f, const PsfPoint& p, const Roi& frame) {
    return {{f.displace(p, 1, 0, frame), f.displace(p, -1, 0, frame), f.displace(p, 0, 1, frame),
             f.displace(p, 0, -1, frame)}};
}

double length(const PsfDisplacement& d) { return std::hypot(d.dx, d.dy); }

// Content: any of R, G, B, A non-zero.
Roi content_box(const VibrateLayer& l) {
    const Image& img = *l.image;
    const Roi w = img.data_window();
    Roi box;
    const float* p[4] = {img.plane(l.rgba.r), img.plane(l.rgba.g), img.plane(l.rgba.b), img.plane(l.rgba.a)};
    for (int y = w.y0; y < w.y1; ++y) {
        int x0 = w.x1, x1 = w.x0;
        for (int x = w.x0; x < w.x1; ++x) {
            const std::size_t i = img.offset(x, y);
            if (p[0][i] != 0.0f || p[1][i] != 0.0f || p[2][i] != 0.0f || p[3][i] != 0.0f) {
                x0 = std::min(x0, x);
                x1 = x + 1;
            }
        }
        if (x1 > x0) box = unite(box, Roi{x0, y, x1, y + 1});
    }
    return box;
}

}  // namespace

Result<Sources> prepare_sources(const VibrateLayer& l, const PsfField& field, const Camera& camera, const Roi& frame,
                                const Roi& output, const Exec& exec) {
    Sources s;
    const Image& img = *l.image;
    const Roi win = img.data_window();
    const Roi content = intersect(content_box(l), output);
    if (content.empty()) return s;
    s.empty = false;
    const int nw = field.weight_count();
    auto radius_at = [&](int x, int y) {
        const int cx = std::clamp(x, output.x0, output.x1 - 1), cy = std::clamp(y, output.y0, output.y1 - 1);
        if (!l.radius || !l.radius_window.contains(cx, cy)) return 0.0f;
        const float r = l.radius[std::size_t(cy - l.radius_window.y0) * std::size_t(l.radius_window.width()) +
                                 std::size_t(cx - l.radius_window.x0)];
        return std::isfinite(r) ? std::max(r, 0.0f) : 0.0f;
    };
    // How far the content can move: its probes (weights taken as 0 here).
    std::vector<float> zero_w(std::size_t(std::max(nw, 1)), 0.0f);
    double dmax = 0.0, lmax = 0.0;
    for (int y = content.y0; y < content.y1; ++y)
        for (int x = content.x0; x < content.x1; ++x) {
            const float zc = win.contains(x, y) && l.z >= 0 ? img.plane(l.z)[img.offset(x, y)] : 0.0f;
            const PsfPoint p{x + 0.5, y + 0.5, double(zc), double(radius_at(x, y)), zero_w.data()};
            const Probes pr = probe(field, p, frame);
            for (const auto& d : pr.d) dmax = std::max(dmax, length(d));
            lmax = std::max(lmax, 0.5 * std::max(length({pr.d[0].dx - pr.d[1].dx, pr.d[0].dy - pr.d[1].dy, 0}),
                                                 length({pr.d[2].dx - pr.d[3].dx, pr.d[2].dy - pr.d[3].dy, 0})));
        }
    // Transparent sources matter only as far as the content's splats reach.
    // (A footprint's reach: 3 sigma, at most 1.5 * lmax for 4 samples or more,
    // or 3 * kStretchCap / 2.) Beyond the output only on the sides the content
    // touches: there the edge repeats.
    // A source beyond the output lands in it only within its own reach.
    const double reach = std::max(1.5 * lmax, 1.5 * kStretchCap);
    const int grow = int(std::ceil(2.0 * dmax + reach)) + 4;
    const int out_grow = int(std::ceil(dmax + reach)) + 4;
    Roi lim = output;
    if (content.x0 <= output.x0) lim.x0 -= out_grow;
    if (content.y0 <= output.y0) lim.y0 -= out_grow;
    if (content.x1 >= output.x1) lim.x1 += out_grow;
    if (content.y1 >= output.y1) lim.y1 += out_grow;
    s.region = intersect(content.grown(grow), lim);
    const Roi R = s.region;
    const std::size_t n = R.npixels();
    s.r.assign(n, 0.0f);
    s.g.assign(n, 0.0f);
    s.b.assign(n, 0.0f);
    s.a.assign(n, 0.0f);
    s.z.assign(n, std::numeric_limits<float>::quiet_NaN());
    s.blur.assign(n, 0.0f);
    s.weights.assign(n * std::size_t(nw), 0.0f);
    std::vector<float> known(n, 0.0f);
    const int W = R.width();
    parallel_for(exec, R.height(), [&](long r0, long r1) {
        for (int y = R.y0 + int(r0); y < R.y0 + int(r1); ++y)
            for (int x = R.x0; x < R.x1; ++x) {
                const std::size_t i = std::size_t(y - R.y0) * std::size_t(W) + std::size_t(x - R.x0);
                const int cx = std::clamp(x, output.x0, output.x1 - 1), cy = std::clamp(y, output.y0, output.y1 - 1);
                s.blur[i] = radius_at(x, y);
                if (!win.contains(cx, cy)) continue;
                const std::size_t o = img.offset(cx, cy);
                s.r[i] = img.plane(l.rgba.r)[o];
                s.g[i] = img.plane(l.rgba.g)[o];
                s.b[i] = img.plane(l.rgba.b)[o];
                s.a[i] = l.rgba.a >= 0 ? img.plane(l.rgba.a)[o] : 1.0f;
                const float z = l.z >= 0 ? img.plane(l.z)[o] : std::numeric_limits<float>::quiet_NaN();
                s.z[i] = z == std::numeric_limits<float>::infinity() ? kFarDepth : z;
                if (nw > 0 && s.a[i] > 0.0f && std::isfinite(z)) {
                    field.evaluate_weights(camera, cx + 0.5, cy + 0.5, z, &s.weights[i * std::size_t(nw)]);
                    known[i] = std::min(s.a[i], 1.0f);
                }
            }
    }, 8);
    // Blend weights beyond the coverage: extrapolated as the radii are.
    if (nw > 0) {
        std::vector<float> planes(n * std::size_t(nw));
        for (std::size_t i = 0; i < n; ++i)
            for (int c = 0; c < nw; ++c) planes[std::size_t(c) * n + i] = s.weights[i * std::size_t(nw) + std::size_t(c)];
        if (push_pull_fill(ImageView::planar(planes.data(), nw, R), ConstImageView::planar(known.data(), 1, R), exec))
            for (std::size_t i = 0; i < n; ++i)
                for (int c = 0; c < nw; ++c) s.weights[i * std::size_t(nw) + std::size_t(c)] = planes[std::size_t(c) * n + i];
    }
    // Probes of every source, then the footprint measures.
    std::vector<float> pd(n * 8);
    s.lipschitz.assign(n, 0.0f);
    double dmax_all = 0.0;
    std::vector<double> row_dmax(std::size_t(R.height()), 0.0);
    parallel_for(exec, R.height(), [&](long r0, long r1) {
        for (long yy = r0; yy < r1; ++yy)
            for (int xx = 0; xx < W; ++xx) {
                const std::size_t i = std::size_t(yy) * std::size_t(W) + std::size_t(xx);
                const float z = s.z[i];
                const PsfPoint p{R.x0 + xx + 0.5, R.y0 + int(yy) + 0.5, std::isfinite(z) ? double(z) : 0.0,
                                 double(s.blur[i]), nw > 0 ? &s.weights[i * std::size_t(nw)] : nullptr};
                const Probes pr = probe(field, p, frame);
                for (int k = 0; k < 4; ++k) {
                    pd[i * 8 + std::size_t(2 * k)] = float(pr.d[k].dx);
                    pd[i * 8 + std::size_t(2 * k + 1)] = float(pr.d[k].dy);
                    if (s.a[i] > 0.0f) row_dmax[std::size_t(yy)] = std::max(row_dmax[std::size_t(yy)], length(pr.d[k]));
                }
                s.lipschitz[i] = float(0.5 * std::max(length({pr.d[0].dx - pr.d[1].dx, pr.d[0].dy - pr.d[1].dy, 0}),
                                                      length({pr.d[2].dx - pr.d[3].dx, pr.d[2].dy - pr.d[3].dy, 0})));
            }
    }, 8);
    for (double d : row_dmax) dmax_all = std::max(dmax_all, d);
    s.max_displacement = dmax_all;
    s.still = std::all_of(s.lipschitz.begin(), s.lipschitz.end(), [](float lip) { return lip == 0.0f; });
    // Stretch: the largest change of any probe's displacement to the right
    // or lower neighbour (both sides of the gap get the footprint).
    s.stretch.assign(n, 0.0f);
    parallel_for(exec, R.height(), [&](long r0, long r1) {
        for (long yy = r0; yy < r1; ++yy)
            for (int xx = 0; xx < W; ++xx) {
                const std::size_t i = std::size_t(yy) * std::size_t(W) + std::size_t(xx);
                float m = 0.0f;
                auto against = [&](std::size_t j) {
                    for (int k = 0; k < 4; ++k)
                        m = std::max(m, std::hypot(pd[j * 8 + std::size_t(2 * k)] - pd[i * 8 + std::size_t(2 * k)],
                                                   pd[j * 8 + std::size_t(2 * k + 1)] - pd[i * 8 + std::size_t(2 * k + 1)]));
                };
                if (xx + 1 < W) against(i + 1);
                if (xx > 0) against(i - 1);
                if (yy + 1 < R.height()) against(i + std::size_t(W));
                if (yy > 0) against(i - std::size_t(W));
                s.stretch[i] = float(std::min(double(m), kStretchCap));
            }
    }, 8);
    if (exec.is_cancelled()) return Status::cancelled("vibrate");
    return s;
}

void set_levels(Sources& s, double spacing, double prefilter) {
    s.level.assign(s.lipschitz.size(), 0.0f);
    for (std::size_t i = 0; i < s.level.size(); ++i) {
        const double sigma = std::max(prefilter * spacing * double(s.lipschitz[i]), 0.5 * double(s.stretch[i]));
        // Level k's kernel has variance 4^k / 2 - 1/4 (splat_pyramid.cpp).
        const double l = 0.5 * std::log2(2.0 * sigma * sigma + 0.5);
        s.level[i] = sigma > 0.0 ? float(std::max(0.0, l)) : -1.0f;
    }
}

int levels_needed(const std::vector<Sources>& layers) {
    float top = 0.0f;
    for (const Sources& s : layers)
        for (float l : s.level) top = std::max(top, l);
    return int(std::floor(top)) + 2;
}

}  // namespace gdof::vibrate_detail
