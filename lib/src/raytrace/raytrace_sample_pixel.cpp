// One pixel's samples: generate ray -> trace segments -> shade -> accumulate
// -> adaptive stop. Everything is seeded by (pixel, sample), never by thread.
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "raytrace/sample_pixel.h"

namespace gdof::rt {

namespace {

// Welford running variance of one quantity of the samples (the adaptive stop).
struct RunningStats {
    int n = 0;
    double mean = 0, m2 = 0;
    void add(double l) {
        ++n;
        const double d = l - mean;
        mean += d / n;
        m2 += d * (l - mean);
    }
    bool converged(double threshold) const {
        if (n < 2) return false;
        const double se = std::sqrt(m2 / (n - 1) / n);
        return se <= threshold * std::max(mean, 0.01);
    }
};

// The adaptive stop: the beauty's luminance and, when the render writes it,
// the albedo's (so a pixel whose beauty is black but whose surfaces differ,
// a shadowed floor at a silhouette, is not left with its first samples),
// both within the threshold; tested only at sample counts 2^k, where the
// pixel's samples are a whole (0, k, 2)-net of the aperture.
struct AdaptiveStop {
    RunningStats beauty, albedo;
    bool with_albedo = false;
    void add(const Sample& s) {
        beauty.add(luminance(s.radiance));
        if (with_albedo) albedo.add(luminance(s.albedo));
    }
    bool done(int n, int min_spp, double threshold) const {
        if (threshold <= 0 || n < min_spp || (n & (n - 1)) != 0) return false;
        return beauty.converged(threshold) && (!with_albedo || albedo.converged(threshold));
    }
};

// The first hit along a polyline ray, and the segment that found it.
struct PolylineHit {
    RayHit hit;
    Vec3 origin, direction;  // of the last segment traced
};

// Traces segment by segment, stopping at the first hit. Each segment reaches
// a little past its end vertex: a surface at an in-focus depth holds the
// vertex, and in float arithmetic neither segment would find it exactly at
// t = 1 / t = 0.
PolylineHit trace_polyline(const RayTracer& tracer, const PolylineRay& ray, std::uint64_t& segments) {
    PolylineHit h;
    const std::size_t n = ray.points.size();
    for (std::size_t i = 0; i < n && !h.hit.hit(); ++i) {
        h.origin = ray.points[i];
        const bool last = i + 1 == n;
        h.direction = last ? ray.far_direction : ray.points[i + 1] - h.origin;
        ++segments;
        h.hit = tracer.intersect(h.origin, h.direction, 0.0, last ? std::numeric_limits<double>::infinity() : 1.0 + 1e-4);
    }
    return h;
}

// The sample's radiance (the environment on a miss) and AOVs at its hit.
// The light samples are seeded by (seed, pixel_key, sample).
Sample shade(const PixelContext& ctx, const PolylineHit& h, std::uint64_t pixel_key, int sample,
             std::uint64_t& shadow_rays) {
    const Scene& scene = ctx.tracer.scene();
    Sample smp;
    smp.radiance = scene.environment;
    if (!h.hit.hit()) return smp;
    Rng rng(ctx.options.seed, pixel_key, std::uint64_t(sample));
    const SurfaceHit sh = ctx.tracer.surface(h.hit, h.origin, h.direction);
    smp.hit = true;
    smp.radiance = ctx.lights.shade(ctx.tracer, sh, h.direction, rng, ctx.options.light_samples, shadow_rays);
    smp.albedo = scene.materials[sh.material].kd;
    smp.p = sh.p;
    smp.n = sh.n;
    smp.z = ctx.camera.camera().project(sh.p).depth;
    smp.id = sh.object_id;
    return smp;
}

std::string pixel_name(int x, int y) { return "pixel (" + std::to_string(x) + ", " + std::to_string(y) + ")"; }

// The beauty is float: a sample beyond its range would write +inf.
Status check_float_range(const Sample& smp, int x, int y) {
    const double peak = std::max({smp.radiance.x, smp.radiance.y, smp.radiance.z});
    if (peak <= double(std::numeric_limits<float>::max())) return {};
    return Status::error(pixel_name(x, y) + ": radiance " + std::to_string(peak) +
                         " is beyond the float range of the beauty (a light's intensity or a "
                         "material's emission is too large)");
}

}  // namespace

Status sample_pixel(const PixelContext& ctx, int x, int y, PixelScratch& scratch, RenderCounters& counters) {
    const RenderOptions& o = ctx.options;
    // A field that cannot be sampled here is an error, never a silent pinhole.
    if (Status st = ctx.camera.prepare_pixel(x + 0.5, y + 0.5, scratch.cone); !st)
        return Status::error("blur field at " + pixel_name(x, y) + ": " + st.message());
    const PixelSampler sampler(x, y, o.seed, ctx.jitter);
    const std::uint64_t pixel_key = hash(std::uint64_t(std::uint32_t(x)), std::uint32_t(y));
    AdaptiveStop stop;
    stop.with_albedo = has(o.aovs, RenderAov::Albedo);
    scratch.samples.clear();
    for (int s = 0; s < o.spp; ++s) {
        if (stop.done(s, ctx.min_spp, o.adaptive_threshold)) break;
        ctx.camera.generate_ray(scratch.cone, sampler.sample(std::uint32_t(s)), scratch.ray);
        ++counters.primary;
        const PolylineHit h = trace_polyline(ctx.tracer, scratch.ray, counters.segments);
        const Sample smp = shade(ctx, h, pixel_key, s, counters.shadow);
        if (Status st = check_float_range(smp, x, y); !st) return st;
        stop.add(smp);
        scratch.samples.push_back(smp);
    }
    return {};
}

std::uint32_t central_object_id(const PixelContext& ctx, int x, int y, const std::vector<Sample>& samples,
                                RenderCounters& counters) {
    if (ctx.sample0_central) return samples[0].hit ? samples[0].id : 0;
    const CameraRay cr = ctx.camera.camera().central_ray(x + 0.5, y + 0.5);
    ++counters.id;
    const RayHit h = ctx.tracer.intersect(cr.origin, cr.direction, 0.0, std::numeric_limits<double>::infinity());
    return h.hit() ? ctx.tracer.scene().meshes[h.mesh].object_id[h.prim] : 0;
}

}  // namespace gdof::rt
