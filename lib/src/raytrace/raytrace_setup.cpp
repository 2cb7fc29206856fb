// Before the pixels: the render options checked, and the camera chosen from
// them (pinhole, straight thin lens, or the polyline rays of a blur field).
#include <algorithm>
#include <cmath>
#include <limits>

#include "raytrace/render_setup.h"

namespace gdof::rt {

Status check_render_options(const RenderOptions& s) {
    if (s.spp < 1) return Status::error("spp: must be >= 1, got " + std::to_string(s.spp));
    if (s.min_spp < 1) return Status::error("min_spp: must be >= 1, got " + std::to_string(s.min_spp));
    if (s.tile_size < 1) return Status::error("tile_size: must be >= 1");
    if (!(s.adaptive_threshold >= 0)) return Status::error("adaptive_threshold: must be >= 0");
    if (!(s.polyline_tolerance_px > 0)) return Status::error("polyline_tolerance_px: must be > 0");
    if ((unsigned(s.aovs) & ~unsigned(RenderAov::All)) != 0) return Status::error("aovs: unknown AOV bits");
    return {};
}

namespace {

// Sample B only over the depths the scene occupies (beyond, the last
// segment runs straight on): much cheaper than the default range.
void fit_depth_range(const Scene& scene, const Camera& camera, NonlinearCameraOptions& opts) {
    double dmin = std::numeric_limits<double>::infinity(), dmax = 0;
    for (const TriangleMesh& m : scene.meshes)
        for (std::size_t v = 0; v < m.vertex_count(); ++v) {
            const double d = camera.project(m.vertex(v)).depth;
            if (d > 0) dmin = std::min(dmin, d), dmax = std::max(dmax, d);
        }
    if (dmax > 0) {
        opts.depth_min = std::max(opts.depth_min, 0.5 * dmin);
        opts.depth_max = std::max(opts.depth_min * 2, 1.01 * dmax);
    }
}

Result<RenderSetup> polyline_setup(const Scene& scene, const Camera& camera, const RenderOptions& s,
                                   const BlurField& field, std::string label) {
    NonlinearCameraOptions opts;
    opts.profile_tolerance_px = s.polyline_tolerance_px;
    opts.ray_tolerance_px = s.polyline_tolerance_px;
    fit_depth_range(scene, camera, opts);
    auto shape = aperture_shape(s.aperture);
    if (!shape) return shape.status();
    auto nc = NonlinearCamera::create(camera, field, opts, shape.value());
    if (!nc) return Status::error("camera: " + nc.message());
    auto rc = RenderCamera::polyline(nc.value());
    if (!rc) return rc.status().prefix("blur field");
    return RenderSetup{std::move(rc).value(), std::move(label)};
}

}  // namespace

Result<RenderSetup> make_render_setup(const Scene& scene, const Camera& camera, const RenderOptions& s) {
    if (s.pinhole) return RenderSetup{RenderCamera::pinhole(camera), "pinhole"};
    if (s.blur_field) return polyline_setup(scene, camera, s, *s.blur_field, "blur field " + s.blur_field->describe());
    if (!std::isfinite(camera.lens().f_number) || !std::isfinite(camera.lens().focus_distance))
        return RenderSetup{RenderCamera::pinhole(camera), "pinhole (the scene camera has no f_number / focus_distance)"};
    auto lens = camera.thin_lens();
    if (!lens) return Status::error("camera: " + lens.message());
    if (s.straight_thin_lens && !(s.aperture.kind == Aperture::Kind::Disc && s.aperture.squeeze == 1.0))
        return Status::error("straight_thin_lens: the reference thin lens samples the disc only; drop it to render "
                             "aperture " + format_aperture(s.aperture));
    if (s.straight_thin_lens)
        return RenderSetup{RenderCamera::straight_thin_lens(camera, thin_lens_equivalent_radius(lens.value()),
                                                            lens->focus_distance),
                           "thin lens (straight rays)"};
    auto field = BlurField::from_thin_lens(lens.value());
    if (!field) return field.status();
    return polyline_setup(scene, camera, s, field.value(), "thin lens (polyline rays)");
}

}  // namespace gdof::rt
