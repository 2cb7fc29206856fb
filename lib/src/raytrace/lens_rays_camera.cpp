// The nonlinear camera of method 1: its options, polyline rays per aperture
// sample of a prepared cone (lens_rays_cone.cpp), and the straight-ray thin
// lens used as the reference.
#include <algorithm>
#include <cmath>
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
    if (c.pinhole) {
        out.set_straight(c.central);
        return;
    }
    out.points.clear();
    out.depth.clear();
    const Vec3 off = aperture_offset_world(a);
    const std::size_t n = c.depth.size();
    for (std::size_t i = 0; i < n; ++i) {
        out.points.push_back(vertex(c, off, i));  // rho == 0: exactly the central ray's point
        out.depth.push_back(c.depth[i]);
    }
    out.far_direction = far_direction(c, off);
}

void NonlinearCamera::generate_ray(const PixelCone& c, const CameraSample& sample, PolylineRay& out) const {
    const Vec2 j = sample.pixel_offset;
    if (c.pinhole) {
        out.set_straight(camera_.central_ray(c.px + j.x, c.py + j.y));
        return;
    }
    ray_from_unit(c, sample.aperture, out);
    if (j.x == 0 && j.y == 0) return;
    // The offset position's cone is this one moved by offset * footprint(depth)
    // (image y runs down, the camera's up vector up): move each vertex at its
    // depth, and aim the far segment at its point one depth unit further on.
    const Vec3 off = camera_.right() * j.x + camera_.up() * (-j.y);
    const std::size_t n = out.points.size();
    const double dl = out.depth[n - 1];
    const double dpt = dot(out.far_direction, camera_.forward());
    const Vec3 far_pt =
        out.points[n - 1] + out.far_direction * (1.0 / std::max(dpt, 1e-12)) + off * footprint(dl + 1.0);
    for (std::size_t i = 0; i < n; ++i) out.points[i] = out.points[i] + off * footprint(out.depth[i]);
    out.far_direction = normalize(far_pt - out.points[n - 1]);
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
