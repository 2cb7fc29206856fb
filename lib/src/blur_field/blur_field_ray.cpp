// Per-ray queries: B along a pixel's central ray as a polyline with its
// breakpoints, and the depth intervals where B is below an acceptable CoC.
#include <algorithm>
#include <cmath>
#include <limits>

#include "blur_field/blur_field_nodes.h"

namespace gdof {

namespace bf {

double split_point(double a, double b) {
    if (a > 0 && b > 4 * a) return std::sqrt(a) * std::sqrt(b);
    return 0.5 * (a + b);
}

std::vector<double> make_grid(double a, double b, std::vector<double> pts) {
    pts.push_back(a);
    pts.push_back(b);
    std::sort(pts.begin(), pts.end());
    std::vector<double> g;
    for (double d : pts) {
        if (!(d >= a && d <= b)) continue;
        if (!g.empty() && d - g.back() <= 1e-12 * std::max(std::fabs(d), std::fabs(g.back()))) {
            if (d == b) g.back() = b;  // keep the exact end
            continue;
        }
        g.push_back(d);
    }
    return g;
}

}  // namespace bf

namespace {

using bf::Node;
using bf::Ray;

struct Poly {
    std::vector<double> d, v;
    std::vector<std::uint8_t> k;
};

// Builds the polyline of B on [a, b] (finite, a < b).
Poly build_profile(const Node& root, const Ray& r, double a, double b, double tol, int max_vertices) {
    std::vector<double> bps;
    root.breakpoints(r, a, b, bps);
    std::vector<double> grid = bf::make_grid(a, b, bps);

    // Steps: a breakpoint whose one-sided neighbours differ from it by more
    // than the tolerance gets vertices just before / after it.
    {
        std::vector<double> extra;
        for (double d : grid) {
            const double eps = 1e-9 * std::max(std::fabs(d), 1e-300);
            const double v = bf::eval_on_ray(root, r, d);
            for (double e : {d - eps, d + eps}) {
                if (!(e > a && e < b)) continue;
                const double ve = bf::eval_on_ray(root, r, e);
                if (!(std::fabs(ve - v) <= tol)) extra.push_back(e);
            }
        }
        if (!extra.empty()) {
            grid.insert(grid.end(), extra.begin(), extra.end());
            std::sort(grid.begin(), grid.end());
            grid.erase(std::unique(grid.begin(), grid.end()), grid.end());
        }
    }
    std::vector<double> gv(grid.size());
    bf::eval_on_ray(root, r, grid.data(), grid.size(), gv.data());

    Poly p;
    const bool linear = root.linear_between_breakpoints();
    auto push = [&](double d, double v, std::uint8_t kind) {
        p.d.push_back(d);
        p.v.push_back(v);
        p.k.push_back(v == 0 ? std::uint8_t(RayProfile::InFocus) : kind);
    };
    push(grid[0], gv[0], RayProfile::Breakpoint);
    struct Seg {
        double a, fa, b, fb;
        int level;
    };
    std::vector<Seg> stack;
    for (std::size_t i = 1; i < grid.size(); ++i) {
        if (!linear) {
            stack.push_back({grid[i - 1], gv[i - 1], grid[i], gv[i], 0});
            while (!stack.empty()) {
                Seg s = stack.back();
                stack.pop_back();
                const double w = s.b - s.a;
                bool ok = s.level >= 60 || w <= 1e-9 * std::max(std::fabs(s.a), std::fabs(s.b)) ||
                          int(p.d.size() + stack.size() + (grid.size() - i)) >= max_vertices;
                if (!ok) {
                    const double t[3] = {s.a + 0.25 * w, s.a + 0.5 * w, s.a + 0.75 * w};
                    double ft[3];
                    bf::eval_on_ray(root, r, t, 3, ft);
                    ok = true;
                    for (int j = 0; j < 3; ++j) {
                        const double lin = s.fa + (s.fb - s.fa) * (0.25 * (j + 1));
                        if (std::isnan(ft[j]) && std::isnan(lin)) continue;
                        if (!(std::fabs(ft[j] - lin) <= tol)) ok = false;
                    }
                    if (std::isinf(s.fa) || std::isinf(s.fb)) ok = ok && s.level > 8;
                }
                if (ok) {
                    push(s.b, s.fb, RayProfile::Sample);
                } else if (const double m = bf::split_point(s.a, s.b); !(m > s.a && m < s.b)) {
                    // No representable depth strictly inside (denormal depths
                    // near a range starting at 0): splitting would emit the
                    // same depth twice, a zero-length segment.
                    push(s.b, s.fb, RayProfile::Sample);
                } else {
                    const double fm = bf::eval_on_ray(root, r, m);
                    // Right half first on the stack so the left half is emitted first.
                    stack.push_back({m, fm, s.b, s.fb, s.level + 1});
                    stack.push_back({s.a, s.fa, m, fm, s.level + 1});
                }
            }
            p.k.back() = p.v.back() == 0 ? std::uint8_t(RayProfile::InFocus) : std::uint8_t(RayProfile::Breakpoint);
        } else {
            push(grid[i], gv[i], RayProfile::Breakpoint);
        }
    }
    return p;
}

Status check_ray_args(double px, double py, double dmin, double dmax, bool allow_inf) {
    if (!std::isfinite(px) || !std::isfinite(py)) return Status::error("blur field ray: pixel position must be finite");
    if (!(dmin >= 0) || !std::isfinite(dmin))
        return Status::error("blur field ray: depth_min must be >= 0 and finite, got " + std::to_string(dmin));
    if (!(dmax > dmin)) return Status::error("blur field ray: depth_max must be > depth_min");
    if (!allow_inf && !std::isfinite(dmax)) return Status::error("blur field ray: depth_max must be finite");
    return {};
}

}  // namespace

double RayProfile::radius_at(double d) const {
    if (depth.empty()) return 0;
    if (d <= depth.front()) return radius.front();
    if (d >= depth.back()) return radius.back();
    const std::size_t i = std::size_t(std::upper_bound(depth.begin(), depth.end(), d) - depth.begin());
    const double t = (d - depth[i - 1]) / (depth[i] - depth[i - 1]);
    // An infinite end (a thin lens at depth 0) makes the chord infinite
    // (inf + t * -inf would be NaN); t < 1 here.
    if (std::isinf(radius[i - 1]) || std::isinf(radius[i]))
        return t == 0 ? radius[i - 1] : std::numeric_limits<double>::infinity();
    return radius[i - 1] + t * (radius[i] - radius[i - 1]);
}

std::vector<double> RayProfile::in_focus_depths() const {
    std::vector<double> r;
    for (std::size_t i = 0; i < depth.size(); ++i)
        if (kind[i] == InFocus) r.push_back(depth[i]);
    return r;
}

DepthInterval InFocusIntervals::primary() const {
    for (const auto& iv : intervals)
        if (iv.contains(min_depth)) return iv;
    return {min_depth, min_depth};
}

Result<RayProfile> BlurField::sample_along_ray(const Camera& camera, double px, double py, double depth_min,
                                               double depth_max, const RayProfileOptions& opts) const {
    if (auto s = check_ray_args(px, py, depth_min, depth_max, false); !s) return s;
    if (!(opts.tolerance_px > 0)) return Status::error("blur field ray: tolerance_px must be > 0");
    const Ray r{&camera, camera.depth_line(px, py), px, py};
    Poly p = build_profile(*root_, r, depth_min, depth_max, opts.tolerance_px, std::max(opts.max_vertices, 2));
    RayProfile out;
    out.depth = std::move(p.d);
    out.radius = std::move(p.v);
    out.kind = std::move(p.k);
    out.line = r.line;
    out.tolerance_px = opts.tolerance_px;
    return out;
}

Result<InFocusIntervals> BlurField::in_focus_interval(const Camera& camera, double px, double py, double coc_px,
                                                      double depth_min, double depth_max,
                                                      const RayProfileOptions& opts) const {
    if (auto s = check_ray_args(px, py, depth_min, depth_max, true); !s) return s;
    if (!(coc_px >= 0) || !std::isfinite(coc_px))
        return Status::error("blur field ray: coc_px must be >= 0 and finite, got " + std::to_string(coc_px));
    if (!(opts.tolerance_px > 0)) return Status::error("blur field ray: tolerance_px must be > 0");
    const bool open_end = std::isinf(depth_max);
    const double b = open_end ? 1e12 * std::max(depth_min, 1e-6) : depth_max;
    const Ray r{&camera, camera.depth_line(px, py), px, py};
    const Poly p = build_profile(*root_, r, depth_min, b, opts.tolerance_px, std::max(opts.max_vertices, 2));

    auto above = [&](double d) {
        const double v = bf::eval_on_ray(*root_, r, d);
        return !(v <= coc_px);
    };
    auto crossing = [&](double lo, double hi) {
        const bool lo_above = above(lo);
        for (int it = 0; it < 200; ++it) {
            const double m = bf::split_point(lo, hi);
            if (!(m > lo && m < hi)) break;
            if (above(m) == lo_above) lo = m;
            else hi = m;
            if (hi - lo <= 1e-15 * std::max(std::fabs(lo), std::fabs(hi))) break;
        }
        return 0.5 * (lo + hi);
    };

    InFocusIntervals res;
    res.min_depth = p.d[0];
    res.min_radius = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < p.d.size(); ++i)
        if (p.v[i] < res.min_radius) res.min_radius = p.v[i], res.min_depth = p.d[i];
    if (std::isinf(res.min_radius) && !p.v.empty() && std::isnan(p.v[0])) res.min_radius = p.v[0];

    bool inside = false;
    double start = 0;
    for (std::size_t i = 0; i < p.d.size(); ++i) {
        const bool in = p.v[i] <= coc_px;
        if (i == 0) {
            if (in) inside = true, start = p.d[0];
            continue;
        }
        if (in && !inside) {
            start = crossing(p.d[i - 1], p.d[i]);
            inside = true;
        } else if (!in && inside) {
            res.intervals.push_back({start, crossing(p.d[i - 1], p.d[i])});
            inside = false;
        }
    }
    if (inside) res.intervals.push_back({start, open_end ? std::numeric_limits<double>::infinity() : b});
    return res;
}

Result<DepthInterval> BlurField::primary_in_focus_interval(const Camera& camera, double px, double py, double coc_px,
                                                           double depth_min, double depth_max) const {
    auto r = in_focus_interval(camera, px, py, coc_px, depth_min, depth_max);
    if (!r) return r.status();
    return r->primary();
}

}  // namespace gdof
