// Method 1: nonlinear distributed ray tracing (Kosloff & Barsky, section 2).
//
// A scene (scene.h) is rendered with Embree 3: each pixel's aperture samples
// are rays (straight for a pinhole or thin lens; polylines bent by the blur
// field), traced segment by segment, shaded with direct lighting (point
// lights, emissive triangles as sampled area lights, a constant environment;
// no global illumination). One multilayer image comes out with the beauty
// and AOVs averaged over the samples. Randomness is seeded per pixel and
// sample, so the image is bit-identical for any thread count or tile order.
//
// Built with GDOF_WITH_EMBREE=OFF, RayTracer::build and render return the
// error "built without Embree".
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "gdof/aperture.h"
#include "gdof/blur_field.h"
#include "gdof/deep.h"
#include "gdof/exec.h"
#include "gdof/export.h"
#include "gdof/image.h"
#include "gdof/scene.h"
#include "gdof/status.h"

namespace gdof {

// A ray's first hit. mesh indexes Scene::meshes, prim its triangles;
// (u, v) are the barycentrics of vertices 1 and 2.
struct RayHit {
    static constexpr std::uint32_t kNone = 0xffffffffu;
    double t = 0;
    std::uint32_t mesh = kNone, prim = kNone;
    double u = 0, v = 0;
    bool hit() const { return mesh != kNone; }
};

// What shading needs at a hit.
struct SurfaceHit {
    Vec3 p;                     // world position (origin + t * direction)
    Vec3 n;                     // shading normal, unit, facing the incoming ray
    Vec3 ng;                    // geometric normal, unit, facing the incoming ray
    std::uint32_t material = 0; // index into Scene::materials
    std::uint32_t object_id = 0;
};

// The acceleration structure over a scene's meshes (Embree BVH). Immutable
// after build; intersect/occluded are const and thread-safe. The scene must
// outlive the tracer.
class GDOF_API RayTracer {
public:
    static Result<std::shared_ptr<const RayTracer>> build(const Scene& scene);
    ~RayTracer();
    RayTracer(const RayTracer&) = delete;
    RayTracer& operator=(const RayTracer&) = delete;

    // First hit with t in [tnear, tfar] along origin + t * dir (dir need not be unit).
    RayHit intersect(const Vec3& origin, const Vec3& dir, double tnear, double tfar) const;
    // Anything hit with t in [tnear, tfar]?
    bool occluded(const Vec3& origin, const Vec3& dir, double tnear, double tfar) const;
    // Position, normals, material and object of a hit of the ray (origin, dir).
    SurfaceHit surface(const RayHit& hit, const Vec3& origin, const Vec3& dir) const;
    const Scene& scene() const { return *scene_; }

private:
    RayTracer() = default;
    struct Impl;
    std::unique_ptr<Impl> impl_;
    const Scene* scene_ = nullptr;
};

// Arbitrary output variables written beside the beauty: a set of flags.
enum class RenderAov : unsigned {
    None = 0,
    Albedo = 1u << 0,    // albedo.R/G/B
    Depth = 1u << 1,     // Z
    Position = 1u << 2,  // P.x/y/z
    Normal = 1u << 3,    // N.x/y/z
    Id = 1u << 4,        // id (uint)
    All = 0x1fu,
};
constexpr RenderAov operator|(RenderAov a, RenderAov b) { return RenderAov(unsigned(a) | unsigned(b)); }
constexpr RenderAov operator&(RenderAov a, RenderAov b) { return RenderAov(unsigned(a) & unsigned(b)); }
// The complement within the known flags.
constexpr RenderAov operator~(RenderAov a) { return RenderAov(~unsigned(a) & unsigned(RenderAov::All)); }
constexpr RenderAov& operator|=(RenderAov& a, RenderAov b) { return a = a | b; }
// True when `set` holds every flag of `flags` (and flags is not None).
constexpr bool has(RenderAov set, RenderAov flags) { return flags != RenderAov::None && (set & flags) == flags; }
// "albedo,Z,P,N,id" (any subset, any order), "all" or "none"; errors name
// the unknown entry.
GDOF_API Result<RenderAov> parse_render_aovs(const std::string& list);
GDOF_API std::string format_render_aovs(RenderAov aovs);

struct RenderOptions {
    int spp = 64;                   // cap on aperture samples per pixel
    int min_spp = 16;               // samples every pixel gets before the adaptive test (4 stopped silhouettes too early)
    // Adaptive stop: a pixel stops once the standard error of its mean
    // luminance is <= adaptive_threshold * max(mean, 0.01) (a relative
    // error), and so is its albedo's when the albedo AOV is written; tested
    // at 2^k samples only (k >= log2 min_spp). 0 disables (every pixel gets
    // spp samples).
    double adaptive_threshold = 0.01;
    bool pinhole = false;           // all in focus: one central ray per sample, no lens
    // Without a blur field: trace the scene camera's thin lens with straight
    // rays (thin_lens_ray) instead of the polyline camera of its thin_lens
    // field (the two agree; this is the reference path).
    bool straight_thin_lens = false;
    // Blur field driving the aperture rays; nullptr: the scene camera's thin
    // lens when its f-number and focus distance are set, else pinhole.
    const BlurField* blur_field = nullptr;
    // Polyline rays: how far (output pixels) the cone radius may stray from
    // the blur field's exact value; larger = fewer segments per ray.
    double polyline_tolerance_px = 0.1;
    int light_samples = 2;          // area-light (and environment) samples per hit
    bool pixel_jitter = true;       // samples spread over the pixel (false: all at its centre)
    std::uint64_t seed = 0;
    int tile_size = 16;
    RenderAov aovs = RenderAov::All;  // which AOVs beside the beauty (deep output: Z always)
    // Replaces the scene camera's lens information (f-number, focus
    // distance, ...) for this render: the thin lens used without a blur field,
    // and the lens written in the metadata. What a focus/aperture stack
    // render changes per reference (render_stack.h).
    std::optional<LensInfo> lens;
    // The iris the aperture samples are drawn from (aperture.h); its
    // radius 1 is the blur radius. The cat's eye is not supported here.
    Aperture aperture;
};

struct GDOF_API RenderStats {
    std::uint64_t primary_rays = 0;   // camera rays (aperture samples)
    std::uint64_t segments = 0;       // camera-ray segments traced (rtcIntersect1 calls)
    std::uint64_t shadow_rays = 0;    // rtcOccluded1 calls
    std::uint64_t id_rays = 0;        // central rays traced for the id channel (when no sample was central)
    std::uint64_t sample_cap = 0;     // pixels * spp
    double seconds = 0;               // tracing + shading
    std::string camera;               // "pinhole", "thin lens", "blur field ..."
    double segments_per_ray() const { return primary_rays ? double(segments) / double(primary_rays) : 0; }
    double mrays_per_second() const {
        return seconds > 0 ? double(segments + shadow_rays + id_rays) / seconds * 1e-6 : 0;
    }
    // Fraction of the sample cap adaptive sampling did not take.
    double adaptive_savings() const {
        return sample_cap ? 1.0 - double(primary_rays) / double(sample_cap) : 0;
    }
    std::string report() const;  // multi-line summary
};

// Renders the scene's camera. The image's channels are R,G,B,A (beauty,
// premultiplied; A = fraction of samples that hit geometry, or 1 everywhere
// when the scene's environment is not black), then the AOVs of
// settings.aovs: albedo.R/G/B, Z (depth along the view axis), P.x/y/z
// (world), N.x/y/z (shading normal), id (uint: object on the pixel's central
// ray, 0 = none). Z, P, N, albedo average the samples that hit (Z = +inf,
// P = N = NaN where none did). The camera attributes (Camera::to_metadata)
// are in its metadata. A pixel whose blur field cannot be sampled (e.g. a
// NaN from an image_map) is an error naming the pixel.
GDOF_API Result<Image> render(const Scene& scene, const RenderOptions& settings, RenderStats* stats = nullptr,
                              const Exec& exec = {});
// The same with a tracer already built for `scene`.
GDOF_API Result<Image> render(const RayTracer& tracer, const RenderOptions& settings, RenderStats* stats = nullptr,
                              const Exec& exec = {});

// The same samples as a deep image (for method 3): each pixel's samples that
// hit are grouped into surfaces (same object id, depths within 5% of each
// other), one deep sample per surface, sorted by depth: Z = ZBack = the
// mean depth of its hits, colour = mean radiance x alpha (premultiplied),
// alpha = its hits / the samples not already taken by nearer surfaces, so
// flattening the deep pixel (front to back `over`) gives exactly the flat
// render's R, G, B, A. A non-black environment adds a sample at Z = +inf.
// Channels: R, G, B, A, Z, ZBack, then the AOVs (albedo, P, N: the
// surface's mean; id: the surface's object).
GDOF_API Result<DeepImage> render_deep(const RayTracer& tracer, const RenderOptions& settings, RenderStats* stats = nullptr,
                                       const Exec& exec = {});

// Raw ray throughput of the tracer on this scene, for comparison in --stats:
// the pinhole central ray of every pixel traced `repeats` times with
// rtcIntersect1 only (no camera model, no shading), tiles in parallel.
// Returns million rays per second (0 if cancelled).
GDOF_API double raw_primary_mrays(const RayTracer& tracer, int repeats = 4, const Exec& exec = {});

}  // namespace gdof
