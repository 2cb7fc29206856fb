// Ray-traced focus/aperture stacks for method 2: the scene rendered once per
// (focus distance, f-number) with the camera's thin lens, and the stack
// manifest (focal_stack.h) that `gdof --composite` reads.
//
// The spec (stack.json for `gdof --render scene.json --stack stack.json`,
// documented in docs/raytrace.md):
//
//   {
//     "coc_px": 1.0,                              // acceptable CoC radius for near/far
//     "focus_distances": [1.5, 2.0, 3.0],         // grid form: every focus distance ...
//     "focus_range": {"near": 1, "far": 50, "count": 12},  // ... (or evenly spaced in 1/distance) ...
//     "f_numbers": [2.8, 8],                      // ... with every f-number
//     "references": [{"focus_distance": 4.0, "f_number": 5.6}]   // and/or a list, after the grid
//   }
#pragma once

#include <string>
#include <vector>

#include "gdof/camera.h"
#include "gdof/export.h"
#include "gdof/focal_stack.h"
#include "gdof/raytrace.h"
#include "gdof/status.h"

namespace gdof {

struct RenderStackOptions {
    struct Reference {
        double focus_distance = 0;  // scene units
        double f_number = 0;
    };
    std::vector<Reference> references;  // grid (each focus with each f-number), then the list
    double coc_px = 1.0;
};

// Errors name the key path ("stack.json: references[2].f_number: ..."); duplicate
// (focus, f-number) pairs are errors naming both.
GDOF_API Result<RenderStackOptions> parse_render_stack_options(const std::string& json_text, const std::string& where = "stack.json");

// The manifest-to-be: each reference's lens and depth of field (near/far for
// coc_px) from the camera's focal length, sensor width and image width.
// File names are left empty. Errors: the camera has no focal length or
// sensor width, or a focus distance is not beyond the focal length.
GDOF_API Result<FocalStack> plan_render_stack(const Camera& camera, const RenderStackOptions& spec);

// Renders every reference of the plan with `settings` (its lens replaced by
// each reference's; settings.blur_field and pinhole must be unset) and hands
// each image to the sink. stats, when given, sums the renders.
GDOF_API Status render_stack(const RayTracer& tracer, const FocalStack& plan, const RenderOptions& settings,
                             const StackSink& sink, RenderStats* stats = nullptr, const Exec& exec = {});

}  // namespace gdof
