// The nonlinear camera of method 1: a pixel's signed cone radius from the
// blur field along its central ray, polyline rays per aperture sample, and the
// straight-ray thin lens used as the reference.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "gdof/lens_rays.h"

namespace gdof {

Result<NonlinearCamera> NonlinearCamera::create(const Camera& camera, const BlurField& field,
                                                const NonlinearCameraOptions& opts, const ApertureShape& shape) {
    if (!(opts.depth_min > 0) || !std::isfinite(opts.depth_min))
        return Status::error("nonlinear camera: depth_min must be > 0 and finite, got " + std::to_string(opts.depth_min));
    if (!(opts.depth_max > opts.depth_min) || !std::isfinite(opts.depth_max))
        return Status::error("nonlinear camera: depth_max must be finite and > depth_min, got " +
                             std::to_string(opts.depth_max));
    if (!(opts.profile_tolerance_px > 0) || !std::isfinite(opts.profile_tolerance_px))
        return Status::error("nonlinear camera: profile_tolerance_px must be > 0, got " +
                             std::to_string(opts.profile_tolerance_px));
    if (!(opts.ray_tolerance_px > 0) || !std::isfinite(opts.ray_tolerance_px))
        return Status::error("nonlinear camera: ray_tolerance_px must be > 0, got " +
                             std::to_string(opts.ray_tolerance_px));
    if (opts.max_profile_vertices < 2)
        return Status::error("nonlinear camera: max_profile_vertices must be >= 2, got " +
                             std::to_string(opts.max_profile_vertices));
    NonlinearCamera c;
    c.camera_ = camera;
    c.field_ = field;
    c.opts_ = opts;
    c.shape_ = shape;
    // The footprint is affine in depth (perspective: z / fx; orthographic: constant).
    c.fp0_ = camera.pixel_footprint(0.0);
    c.fp1_ = camera.pixel_footprint(1.0) - c.fp0_;
    if (!std::isfinite(c.fp0_) || !std::isfinite(c.fp1_) || !(c.fp0_ + c.fp1_ > 0))
        return Status::error("nonlinear camera: the camera has no valid pixel footprint");
    return c;
}

Result<PixelCone> NonlinearCamera::prepare(double px, double py) const {
    PixelCone c;
    if (auto s = prepare(px, py, c); !s) return s;
    return c;
}

namespace {

// Simplification of the polyline (d, r) in one pass: keeps vertex 0, the
// last one and every `keep` vertex; a run of vertices is replaced by the chord
// between kept vertices when every vertex of the run lies within tol(d) of it
// (tracked as the interval of admissible chord slopes from the anchor).
template <class Tol>
void simplify(std::vector<double>& d, std::vector<double>& r, const std::vector<char>& keep, Tol tol) {
    const std::size_t n = d.size();
    if (n <= 2) return;
    std::size_t out = 1;  // d[0], r[0] stay
    std::size_t anchor = 0;
    double lo = -HUGE_VAL, hi = HUGE_VAL;
    std::size_t e = 1;
    while (e < n) {
        const double dd = d[e] - d[anchor];
        const double slope = (r[e] - r[anchor]) / dd;
        const bool fits = e == anchor + 1 || (slope >= lo && slope <= hi);
        if (!fits) {
            // The chord to e misses a vertex in between: keep e - 1.
            anchor = e - 1;
            d[out] = d[anchor];
            r[out] = r[anchor];
            ++out;
            lo = -HUGE_VAL;
            hi = HUGE_VAL;
            continue;  // re-examine e from the new anchor
        }
        if (keep[e] || e == n - 1) {
            anchor = e;
            d[out] = d[e];
            r[out] = r[e];
            ++out;
            lo = -HUGE_VAL;
            hi = HUGE_VAL;
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

}  // namespace

Status NonlinearCamera::prepare(double px, double py, PixelCone& out) const {
    out.px = px;
    out.py = py;
    out.central = camera_.central_ray(px, py);
    out.line = camera_.depth_line(px, py);
    out.depth.clear();
    out.rho.clear();
    out.in_focus.clear();
    out.far_slope = 0;
    out.max_blur_px = 0;
    out.pinhole = true;

    RayProfileOptions po;
    po.tolerance_px = opts_.profile_tolerance_px;
    po.max_vertices = opts_.max_profile_vertices;
    auto prof = field_.sample_along_ray(camera_, px, py, opts_.depth_min, opts_.depth_max, po);
    if (!prof) return prof.status();
    const RayProfile& p = *prof;
    const std::size_t n = p.size();
    if (n < 2) return Status::error("nonlinear camera: blur profile with fewer than 2 vertices");

    // Signed cone radius at the profile vertices: |rho| = B * footprint, the
    // sign flips when B leaves a run of zeros (an in-focus depth or interval).
    // Slot 0 is a placeholder (the lens plane is added at the end).
    std::vector<double> d(n + 1), r(n + 1);
    std::vector<char> keep(n + 1, 0);
    double sign = 1.0;
    bool in_zero = false;
    bool any = false;
    for (std::size_t i = 0; i < n; ++i) {
        const double b = p.radius[i];
        // A cone wider than 1e20 scene units is meaningless and its ray
        // coordinates overflow floats (e.g. a field scaled by 1e300).
        const double rho = b * footprint(p.depth[i]);
        if (!std::isfinite(b) || b < 0 || !(rho <= 1e20)) {
            char buf[200];
            std::snprintf(buf, sizeof buf, "nonlinear camera: blur field gives %g px%s at depth %g on the ray of pixel (%g, %g)",
                          b, rho > 1e20 ? " (a cone over 1e20 scene units wide)" : "", p.depth[i], px, py);
            return Status::error(buf);
        }
        out.max_blur_px = std::max(out.max_blur_px, b);
        if (b == 0.0) {
            if (!in_zero) out.in_focus.push_back(p.depth[i]);
            in_zero = true;
            keep[i + 1] = 1;
        } else {
            if (in_zero && any) sign = -sign;  // the rays cross at the in-focus depth
            in_zero = false;
            any = true;
        }
        d[i + 1] = p.depth[i];
        r[i + 1] = b == 0.0 ? 0.0 : sign * b * footprint(p.depth[i]);
        if (p.kind[i] == RayProfile::InFocus) keep[i + 1] = 1;
    }
    if (!any) {
        // B == 0 everywhere: the pinhole ray, nothing else.
        out.in_focus.clear();
        out.depth.push_back(0.0);
        out.rho.push_back(0.0);
        return {};
    }
    out.pinhole = false;
    const double tol_px = 0.5 * opts_.ray_tolerance_px;
    auto tol = [&](double z) { return tol_px * footprint(z); };
    // Drop profile vertices where rho is straight (thin_lens: all samples).
    {
        std::vector<double> dd(d.begin() + 1, d.end()), rr(r.begin() + 1, r.end());
        std::vector<char> kk(keep.begin() + 1, keep.end());
        simplify(dd, rr, kk, tol);
        d.swap(dd);
        r.swap(rr);
    }
    // Subdivide where rho (exact field) leaves the chord: rho = B * footprint
    // is quadratic where B is linear, and so on.
    {
        std::vector<double> od{d[0]}, orr{r[0]};
        struct Seg {
            double za, ra, zb, rb;
            int level;
        };
        std::vector<Seg> stack;
        for (std::size_t i = 0; i + 1 < d.size(); ++i) {
            double sg = 1.0;
            if (r[i + 1] != 0.0) sg = r[i + 1] > 0 ? 1.0 : -1.0;
            else if (r[i] != 0.0) sg = r[i] > 0 ? 1.0 : -1.0;
            else
                for (std::size_t k = i + 2; k < d.size(); ++k)
                    if (r[k] != 0.0) {
                        sg = r[k] > 0 ? 1.0 : -1.0;
                        break;
                    }
            auto rho_exact = [&](double z) {
                return sg * field_.evaluate_on_ray(camera_, px, py, z) * footprint(z);
            };
            stack.push_back({d[i], r[i], d[i + 1], r[i + 1], 0});
            while (!stack.empty()) {
                const Seg sgm = stack.back();
                stack.pop_back();
                const double len = sgm.zb - sgm.za;
                bool split = false;
                double rm = 0;
                if (sgm.level < 40 && len > 1e-9 * sgm.zb) {
                    for (double t : {0.25, 0.5, 0.75}) {
                        const double z = sgm.za + len * t;
                        const double ex = rho_exact(z);
                        if (!(std::fabs(ex - (sgm.ra + (sgm.rb - sgm.ra) * t)) <= tol(z))) split = true;
                        if (t == 0.5) rm = ex;
                    }
                }
                // The vertex budget bounds the work for absurd fields (e.g.
                // B = 1e300 px, where no chord is within tolerance).
                const bool budget = od.size() + stack.size() < std::size_t(opts_.max_profile_vertices);
                if (split && std::isfinite(rm) && budget) {
                    const double zm = sgm.za + 0.5 * len;
                    // Right half pushed first: the left half is emitted first.
                    stack.push_back({zm, rm, sgm.zb, sgm.rb, sgm.level + 1});
                    stack.push_back({sgm.za, sgm.ra, zm, rm, sgm.level + 1});
                } else {
                    od.push_back(sgm.zb);
                    orr.push_back(sgm.rb);
                }
            }
        }
        d.swap(od);
        r.swap(orr);
    }
    // Lens plane: the first segment extended to depth 0; if that would cross
    // zero (a crossing B does not ask for), the lens-plane radius is clamped to 0.
    {
        double r0 = d.size() >= 2 ? r[0] - (r[1] - r[0]) * d[0] / (d[1] - d[0]) : r[0];
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
    std::size_t m = d.size();
    const double slope_far = (r[m - 1] - r[m - 2]) / (d[m - 1] - d[m - 2]);
    // The depth_max vertex lies on the far extension (same slope): drop it
    // unless it is in focus (thin_lens: lens point, focus point, then straight).
    if (m > 2 && r[m - 1] != 0.0) {
        d.pop_back();
        r.pop_back();
        --m;
    }
    out.depth = std::move(d);
    out.rho = std::move(r);
    out.far_slope = std::isfinite(slope_far) ? slope_far : 0.0;
    return {};
}

double NonlinearCamera::rho_at(const PixelCone& c, double depth) {
    const std::size_t n = c.depth.size();
    if (n == 0) return 0.0;
    if (depth >= c.depth[n - 1]) return c.rho[n - 1] + c.far_slope * (depth - c.depth[n - 1]);
    if (depth <= c.depth[0]) {
        if (n == 1) return c.rho[0];
        return c.rho[0] + (c.rho[1] - c.rho[0]) * (depth - c.depth[0]) / (c.depth[1] - c.depth[0]);
    }
    const std::size_t k = std::size_t(std::upper_bound(c.depth.begin(), c.depth.end(), depth) - c.depth.begin());
    const double t = (depth - c.depth[k - 1]) / (c.depth[k] - c.depth[k - 1]);
    return c.rho[k - 1] + (c.rho[k] - c.rho[k - 1]) * t;
}

Vec3 NonlinearCamera::point_at(const PixelCone& c, Vec2 a, double depth) const {
    if (c.pinhole) return c.line.at(depth);
    const Vec3 off = camera_.right() * a.x + camera_.up() * a.y;
    return c.line.at(depth) + off * rho_at(c, depth);
}

void NonlinearCamera::ray(const PixelCone& c, Vec2 a, PolylineRay& out) const {
    out.points.clear();
    out.depth.clear();
    if (c.pinhole) {
        out.points.push_back(c.central.origin);
        out.depth.push_back(0.0);
        out.far_direction = c.central.direction;
        return;
    }
    const Vec3 off = aperture_offset_world(a);
    const std::size_t n = c.depth.size();
    for (std::size_t i = 0; i < n; ++i) {
        out.points.push_back(vertex(c, off, i));  // rho == 0: exactly the central ray's point
        out.depth.push_back(c.depth[i]);
    }
    out.far_direction = far_direction(c, off);
}

void NonlinearCamera::retarget(PixelCone& c, double px, double py) const {
    c.px = px;
    c.py = py;
    c.central = camera_.central_ray(px, py);
    c.line = camera_.depth_line(px, py);
}

CameraRay thin_lens_ray(const Camera& camera, double px, double py, double lens_radius, double focus_depth,
                        Vec2 a) {
    const DepthLine line = camera.depth_line(px, py);
    const Vec3 focus = line.at(focus_depth);
    const Vec3 origin = line.origin + (camera.right() * a.x + camera.up() * a.y) * lens_radius;
    const Vec3 dir = focus - origin;
    const double len = length(dir);
    // Depth grows by focus_depth over the length of dir.
    return {origin, dir / len, focus_depth / len};
}

double thin_lens_aperture_radius(const ThinLens& lens) {
    return lens.focal_length_mm / (2.0 * lens.f_number) / lens.scene_unit_mm;
}

double thin_lens_equivalent_radius(const ThinLens& lens) {
    const double s = lens.focus_distance * lens.scene_unit_mm;
    const double f = lens.focal_length_mm;
    return thin_lens_aperture_radius(lens) * s / (s - f);
}

}  // namespace gdof
