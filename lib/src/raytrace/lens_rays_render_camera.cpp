// RenderCamera: the pinhole, the straight-ray thin lens and the polyline
// camera behind one pixel -> cone -> ray interface.
#include "gdof/lens_rays.h"

namespace gdof {

RenderCamera RenderCamera::pinhole(const Camera& camera) { return RenderCamera(Kind::Pinhole, camera); }

RenderCamera RenderCamera::straight_thin_lens(const Camera& camera, double lens_radius, double focus_depth) {
    RenderCamera c(Kind::StraightThinLens, camera);
    c.lens_radius_ = lens_radius;
    c.focus_depth_ = focus_depth;
    return c;
}

Result<RenderCamera> RenderCamera::polyline(const NonlinearCamera& camera) {
    RenderCamera c(Kind::Polyline, camera.camera());
    c.nonlinear_ = camera;
    // A depth-only field (thin_lens, focal_planes, ...) has the same cone at
    // every pixel: sample the field once and only move the central ray per pixel.
    if (camera.depth_only()) {
        const Roi d = camera.camera().display_window();
        PixelCone cone;
        if (Status st = camera.prepare(d.x0 + 0.5, d.y0 + 0.5, cone); !st) return st;
        c.shared_cone_ = std::move(cone);
    }
    return c;
}

Status RenderCamera::prepare_pixel(double px, double py, PixelCone& cone) const {
    if (kind_ != Kind::Polyline) {
        cone.px = px;
        cone.py = py;
        return {};
    }
    if (!shared_cone_) return nonlinear_->prepare(px, py, cone);
    cone = *shared_cone_;  // reuses cone's buffers
    nonlinear_->retarget(cone, px, py);
    return {};
}

void RenderCamera::generate_ray(const PixelCone& cone, const CameraSample& sample, PolylineRay& out) const {
    if (kind_ == Kind::Polyline) {
        nonlinear_->generate_ray(cone, sample, out);
        return;
    }
    const double x = cone.px + sample.pixel_offset.x, y = cone.py + sample.pixel_offset.y;
    out.set_straight(kind_ == Kind::StraightThinLens
                         ? thin_lens_ray(camera_, x, y, lens_radius_, focus_depth_, concentric_disc(sample.aperture))
                         : camera_.central_ray(x, y));
}

}  // namespace gdof
