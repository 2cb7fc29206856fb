// Internal to the ray tracer: one pixel's samples, from camera ray to shaded
// sample, up to the adaptive stop.
#pragma once

#include <cstdint>
#include <vector>

#include "gdof/lens_rays.h"
#include "raytrace/raytrace_internal.h"

namespace gdof::rt {

// What the pixels of a render read (immutable, shared by the threads).
struct PixelContext {
    const RayTracer& tracer;
    const RenderCamera& camera;
    const LightSampler& lights;
    const RenderOptions& options;
    int min_spp;           // min(options.min_spp, options.spp)
    bool jitter;           // options.pixel_jitter && options.spp > 1
    bool sample0_central;  // an unjittered pinhole: sample 0 is the pixel's central ray
};

// What a thread reuses from pixel to pixel.
struct PixelScratch {
    PixelCone cone;
    PolylineRay ray;
    std::vector<Sample> samples;  // the last pixel's samples
};

// Ray counts (RenderStats) of the pixels one thread rendered.
struct RenderCounters {
    std::uint64_t primary = 0, segments = 0, shadow = 0, id = 0;
};

// The samples of pixel (x, y) into scratch.samples: per sample, generate the
// camera ray, trace its segments to the first hit, shade; stops once the
// adaptive test is met (after min_spp). Errors name the pixel: a blur field
// that cannot be sampled there, a radiance beyond the float range.
Status sample_pixel(const PixelContext& ctx, int x, int y, PixelScratch& scratch, RenderCounters& counters);

// The object on the pixel's central ray (0: none): sample 0's when that is
// the central ray, else a central ray traced for it.
std::uint32_t central_object_id(const PixelContext& ctx, int x, int y, const std::vector<Sample>& samples,
                                RenderCounters& counters);

}  // namespace gdof::rt
