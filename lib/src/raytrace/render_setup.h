// Internal to the ray tracer: what a render is set up with before its pixels
// (the options checked, the camera it traces).
#pragma once

#include <string>

#include "gdof/lens_rays.h"
#include "gdof/raytrace.h"

namespace gdof::rt {

// Errors name the option (spp, min_spp, tile_size, ...).
Status check_render_options(const RenderOptions& options);

struct RenderSetup {
    RenderCamera camera;
    std::string label;  // RenderStats::camera, the gdof:renderCamera attribute
};

// The camera of the options: a pinhole (options.pinhole, or a scene camera
// without f-number / focus distance), the straight thin lens, or the polyline
// rays of options.blur_field or of the camera's thin lens, sampled over the
// depths the scene occupies. `camera` has options.lens applied.
Result<RenderSetup> make_render_setup(const Scene& scene, const Camera& camera, const RenderOptions& options);

}  // namespace gdof::rt
