// Internal to the ray tracer: direct lighting and what a pixel writes.
#pragma once

#include <cstdint>
#include <vector>

#include "gdof/deep.h"
#include "gdof/image.h"

#include "gdof/raytrace.h"
#include "raytrace/hash.h"

namespace gdof::rt {

inline double luminance(const Vec3& c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; }
inline Vec3 mul(const Vec3& a, const Vec3& b) { return {a.x * b.x, a.y * b.y, a.z * b.z}; }

// Emissive triangles, picked with probability proportional to area * luminance(Ke).
class LightSampler {
public:
    explicit LightSampler(const Scene& scene);
    bool empty() const { return tris_.empty(); }
    // Outgoing radiance towards -dir at a hit: emission + direct lighting from
    // point lights, area lights and the environment (light_samples each).
    Vec3 shade(const RayTracer& rt, const SurfaceHit& s, const Vec3& dir, Rng& rng, int light_samples,
               std::uint64_t& shadow_rays) const;

private:
    struct Tri {
        std::uint32_t mesh, prim;
        double area;
    };
    std::vector<Tri> tris_;
    std::vector<double> cdf_;  // normalised, last = 1
};

// One aperture sample of a pixel, as the pixel writers need it.
struct Sample {
    bool hit = false;
    Vec3 radiance{0, 0, 0};  // environment when no hit
    Vec3 albedo{0, 0, 0}, p{0, 0, 0}, n{0, 0, 0};
    double z = 0;
    std::uint32_t id = 0;
};

// Flat output: channel indices (-1: AOV not written).
struct FlatLayout {
    int r = 0, g = 1, b = 2, a = 3;
    int albedo = -1, z = -1, p = -1, n = -1, id = -1;  // first of each group
    static FlatLayout make(RenderAov aovs, std::vector<ChannelSpec>& specs);
};
// Averages a pixel's samples into the flat image (beauty + AOVs).
void write_flat_pixel(Image& img, const FlatLayout& l, std::size_t offset, const std::vector<Sample>& samples,
                      std::uint32_t central_id, bool env_opaque);

// Deep output: one pixel's surfaces (see render_deep in raytrace.h).
struct DeepSurface {
    Vec3 rgb{0, 0, 0};  // premultiplied
    double alpha = 0, z = 0;
    Vec3 albedo{0, 0, 0}, p{0, 0, 0}, n{0, 0, 0};
    std::uint32_t id = 0;
};
// Groups the hits into surfaces; `samples` is reordered.
void deep_pixel(std::vector<Sample>& samples, const Vec3& environment, bool env_opaque,
                std::vector<DeepSurface>& out);
// Assembles the deep image from every pixel's surfaces (row-major over window).
Result<DeepImage> make_deep_image(const Roi& window, RenderAov aovs, std::vector<std::vector<DeepSurface>>& pixels);

}  // namespace gdof::rt
