// A pixel's cone (NonlinearCamera::prepare), in the steps of docs/raytrace.md
// "The polyline": the blur field sampled along the central ray, signed cone
// radii at its vertices, vertices dropped where rho is straight, segments
// subdivided where the exact rho is curved, then the lens plane and the far end.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "gdof/lens_rays.h"

namespace gdof {

namespace {

// The cone radius as a polyline in depth while it is built: vertex depths,
// signed radii, and the vertices simplification must keep (in focus).
struct RadiusPolyline {
    std::vector<double> d, r;
    std::vector<char> keep;
};

// How far (scene units) the polyline's rho may stray at a depth.
struct RadiusTolerance {
    const NonlinearCamera& camera;
    double px;  // output pixels
    double operator()(double z) const { return px * camera.footprint(z); }
};

// The pixel's central ray and an empty (pinhole) cone.
void reset_cone(const Camera& camera, double px, double py, PixelCone& out) {
    out.px = px;
    out.py = py;
    out.central = camera.central_ray(px, py);
    out.line = camera.depth_line(px, py);
    out.depth.clear();
    out.rho.clear();
    out.in_focus.clear();
    out.far_slope = 0;
    out.max_blur_px = 0;
    out.pinhole = true;
}

// Signed cone radius at the profile vertices: |rho| = B * footprint, the sign
// flipping when B leaves a run of zeros (an in-focus depth or interval). Also
// fills out.max_blur_px, out.in_focus and out.pinhole (B == 0 everywhere).
Status signed_radii(const NonlinearCamera& camera, const RayProfile& p, PixelCone& out, RadiusPolyline& poly) {
    const std::size_t n = p.size();
    poly.d.assign(n, 0.0);
    poly.r.assign(n, 0.0);
    poly.keep.assign(n, 0);
    double sign = 1.0;
    bool in_zero = false, any = false;
    for (std::size_t i = 0; i < n; ++i) {
        const double b = p.radius[i];
        // A cone wider than 1e20 scene units is meaningless and its ray
        // coordinates overflow floats (e.g. a field scaled by 1e300).
        const double rho = b * camera.footprint(p.depth[i]);
        if (!std::isfinite(b) || b < 0 || !(rho <= 1e20)) {
            char buf[200];
            std::snprintf(buf, sizeof buf, "nonlinear camera: blur field gives %g px%s at depth %g on the ray of pixel (%g, %g)",
                          b, rho > 1e20 ? " (a cone over 1e20 scene units wide)" : "", p.depth[i], out.px, out.py);
            return Status::error(buf);
        }
        out.max_blur_px = std::max(out.max_blur_px, b);
        if (b == 0.0) {
            if (!in_zero) out.in_focus.push_back(p.depth[i]);
            in_zero = true;
            poly.keep[i] = 1;
        } else {
            if (in_zero && any) sign = -sign;  // the rays cross at the in-focus depth
            in_zero = false;
            any = true;
        }
        poly.d[i] = p.depth[i];
        poly.r[i] = b == 0.0 ? 0.0 : sign * b * camera.footprint(p.depth[i]);
        if (p.kind[i] == RayProfile::InFocus) poly.keep[i] = 1;
    }
    out.pinhole = !any;
    return {};
}

// Simplification of the polyline (d, r) in one pass: keeps vertex 0, the
// last one and every `keep` vertex; a run of vertices is replaced by the chord
// between kept vertices when every vertex of the run lies within tol(d) of it
// (tracked as the interval of admissible chord slopes from the anchor).
void drop_straight_vertices(RadiusPolyline& poly, const RadiusTolerance& tol) {
    std::vector<double>& d = poly.d;
    std::vector<double>& r = poly.r;
    const std::size_t n = d.size();
    if (n <= 2) return;
    std::size_t out = 1;  // d[0], r[0] stay
    std::size_t anchor = 0;
    double lo = -HUGE_VAL, hi = HUGE_VAL;
    auto emit = [&](std::size_t v) {
        anchor = v;
        d[out] = d[v];
        r[out] = r[v];
        ++out;
        lo = -HUGE_VAL;
        hi = HUGE_VAL;
    };
    std::size_t e = 1;
    while (e < n) {
        const double dd = d[e] - d[anchor];
        const double slope = (r[e] - r[anchor]) / dd;
        if (e != anchor + 1 && !(slope >= lo && slope <= hi)) {
            emit(e - 1);  // the chord to e misses a vertex in between: keep e - 1,
            continue;     // and re-examine e from there
        }
        if (poly.keep[e] || e == n - 1) {
            emit(e);
        } else {
            const double t = tol(d[e]);
            lo = std::max(lo, (r[e] - t - r[anchor]) / dd);
            hi = std::min(hi, (r[e] + t - r[anchor]) / dd);
        }
        ++e;
    }
    d.resize(out);
    r.resize(out);
}

// The sign of rho on segment i (it only changes at a vertex where rho == 0):
// from the segment's ends, else from the next non-zero vertex.
double segment_sign(const std::vector<double>& r, std::size_t i) {
    if (r[i + 1] != 0.0) return r[i + 1] > 0 ? 1.0 : -1.0;
    if (r[i] != 0.0) return r[i] > 0 ? 1.0 : -1.0;
    for (std::size_t k = i + 2; k < r.size(); ++k)
        if (r[k] != 0.0) return r[k] > 0 ? 1.0 : -1.0;
    return 1.0;
}

struct Chord {
    double za, ra, zb, rb;
    int level;
};

// Halves `chord` (depth first, left half first) until the exact rho at 1/4,
// 1/2 and 3/4 of each piece is within tolerance; appends the piece ends.
template <class Exact>
void subdivide_chord(const Chord& chord, const Exact& rho_exact, const RadiusTolerance& tol,
                     std::size_t max_vertices, std::vector<double>& od, std::vector<double>& orr,
                     std::vector<Chord>& stack) {
    stack.push_back(chord);
    while (!stack.empty()) {
        const Chord c = stack.back();
        stack.pop_back();
        const double len = c.zb - c.za;
        bool split = false;
        double rm = 0;
        if (c.level < 40 && len > 1e-9 * c.zb) {
            for (double t : {0.25, 0.5, 0.75}) {
                const double z = c.za + len * t;
                const double ex = rho_exact(z);
                if (!(std::fabs(ex - (c.ra + (c.rb - c.ra) * t)) <= tol(z))) split = true;
                if (t == 0.5) rm = ex;
            }
        }
        // The vertex budget bounds the work for absurd fields (e.g.
        // B = 1e300 px, where no chord is within tolerance).
        const bool budget = od.size() + stack.size() < max_vertices;
        if (split && std::isfinite(rm) && budget) {
            const double zm = c.za + 0.5 * len;
            // Right half pushed first: the left half is emitted first.
            stack.push_back({zm, rm, c.zb, c.rb, c.level + 1});
            stack.push_back({c.za, c.ra, zm, rm, c.level + 1});
        } else {
            od.push_back(c.zb);
            orr.push_back(c.rb);
        }
    }
}

// Subdivides where rho (exact field) leaves the chord: rho = B * footprint
// is quadratic where B is linear, and so on.
void subdivide_where_curved(const NonlinearCamera& camera, double px, double py, const RadiusTolerance& tol,
                            RadiusPolyline& poly) {
    const std::vector<double>& d = poly.d;
    const std::vector<double>& r = poly.r;
    std::vector<double> od{d[0]}, orr{r[0]};
    std::vector<Chord> stack;
    const std::size_t max_vertices = std::size_t(camera.options().max_profile_vertices);
    for (std::size_t i = 0; i + 1 < d.size(); ++i) {
        const double sg = segment_sign(r, i);
        auto rho_exact = [&](double z) {
            return sg * camera.field().evaluate_on_ray(camera.camera(), px, py, z) * camera.footprint(z);
        };
        subdivide_chord({d[i], r[i], d[i + 1], r[i + 1], 0}, rho_exact, tol, max_vertices, od, orr, stack);
    }
    poly.d.swap(od);
    poly.r.swap(orr);
}

// Lens plane: the first segment extended to depth 0; if that would cross
// zero (a crossing B does not ask for), the lens-plane radius is clamped to 0.
void extend_to_lens_plane(std::vector<double>& d, std::vector<double>& r) {
    const double r0 = d.size() >= 2 ? r[0] - (r[1] - r[0]) * d[0] / (d[1] - d[0]) : r[0];
    if (r0 * r[0] < 0 || !std::isfinite(r0)) {
        d.insert(d.begin(), 0.0);
        r.insert(r.begin(), 0.0);
    } else if (r[0] == 0.0) {
        d.insert(d.begin(), 0.0);  // keep the in-focus vertex at depth_min
        r.insert(r.begin(), r0);
    } else {
        d[0] = 0.0;  // the depth_min vertex is on the extended segment: move it
        r[0] = r0;
    }
}

// The slope of rho beyond the last vertex (0 if not finite). The depth_max
// vertex lies on that extension: dropped unless it is in focus (thin_lens:
// lens point, focus point, then straight).
double far_slope_and_trim(std::vector<double>& d, std::vector<double>& r) {
    const std::size_t m = d.size();
    const double slope = (r[m - 1] - r[m - 2]) / (d[m - 1] - d[m - 2]);
    if (m > 2 && r[m - 1] != 0.0) {
        d.pop_back();
        r.pop_back();
    }
    return std::isfinite(slope) ? slope : 0.0;
}

}  // namespace

Status NonlinearCamera::prepare(double px, double py, PixelCone& out) const {
    reset_cone(camera_, px, py, out);
    RayProfileOptions po;
    po.tolerance_px = opts_.profile_tolerance_px;
    po.max_vertices = opts_.max_profile_vertices;
    auto profile = field_.sample_along_ray(camera_, px, py, opts_.depth_min, opts_.depth_max, po);
    if (!profile) return profile.status();
    if (profile->size() < 2) return Status::error("nonlinear camera: blur profile with fewer than 2 vertices");

    RadiusPolyline poly;
    if (Status st = signed_radii(*this, *profile, out, poly); !st) return st;
    if (out.pinhole) {  // B == 0 everywhere: the pinhole ray, nothing else
        out.in_focus.clear();
        out.depth.push_back(0.0);
        out.rho.push_back(0.0);
        return {};
    }
    const RadiusTolerance tol{*this, 0.5 * opts_.ray_tolerance_px};
    drop_straight_vertices(poly, tol);  // where rho is straight (thin_lens: all samples)
    subdivide_where_curved(*this, px, py, tol, poly);
    extend_to_lens_plane(poly.d, poly.r);
    out.far_slope = far_slope_and_trim(poly.d, poly.r);
    out.depth = std::move(poly.d);
    out.rho = std::move(poly.r);
    return {};
}

Result<PixelCone> NonlinearCamera::prepare(double px, double py) const {
    PixelCone c;
    if (auto s = prepare(px, py, c); !s) return s;
    return c;
}

}  // namespace gdof
