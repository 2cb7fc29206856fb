// The blur field B(x): circle-of-confusion radius in output pixels at a world
// point x. One description of the focus intent for all three methods
// (docs/blur_field.md has the JSON format, every kind and key).
//
// A BlurField is immutable after construction; every method is const and
// thread-safe (no caches, no allocation per point in the batch calls), so
// one field can be shared by all threads. Copies share the same tree.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "gdof/camera.h"
#include "gdof/export.h"
#include "gdof/image.h"
#include "gdof/status.h"

namespace gdof {

namespace bf {
class Node;  // internal
}

struct DepthInterval {
    double near = 0, far = 0;  // scene units (depth along the viewing axis)
    bool contains(double d) const { return d >= near && d <= far; }
};

// B along a pixel's central ray as a polyline in depth. Vertices are sorted by
// depth (a step in B gives two vertices a relative 1e-9 apart); the polyline
// interpolates B linearly in depth (= linearly along the ray).
struct GDOF_API RayProfile {
    enum Kind : std::uint8_t {
        Sample = 0,      // added by adaptive subdivision of a curved part
        Breakpoint = 1,  // a kink, a region boundary crossing, a range end, ...
        InFocus = 2,     // B == 0 here (a breakpoint where the aperture cone closes)
    };
    std::vector<double> depth;        // scene units, increasing
    std::vector<double> radius;       // B in output pixels at depth[i]
    std::vector<std::uint8_t> kind;   // Kind per vertex
    DepthLine line;                   // world point at depth d = line.at(d)
    double tolerance_px = 0;          // max |polyline - B| at the checked points (see docs)

    std::size_t size() const { return depth.size(); }
    // Linear interpolation of the polyline (clamped to the ends).
    double radius_at(double d) const;
    // Depths where B reaches 0 (vertices of kind InFocus).
    std::vector<double> in_focus_depths() const;
};

struct RayProfileOptions {
    double tolerance_px = 0.01;  // subdivision tolerance for curved parts (output pixels)
    int max_vertices = 20000;    // hard cap per ray (the tolerance may then not be met)
};

// Depth intervals along a central ray where B <= the acceptable CoC.
struct GDOF_API InFocusIntervals {
    std::vector<DepthInterval> intervals;  // sorted, disjoint; far may be +inf
    double min_depth = 0;                  // depth of the smallest B found (first if several)
    double min_radius = 0;                 // that smallest B
    bool empty() const { return intervals.empty(); }
    // "The" interval: the one containing min_depth; [min_depth, min_depth]
    // if B never gets down to the CoC.
    DepthInterval primary() const;
};

class GDOF_API BlurField {
public:
    // Supplies the images an image_map refers to (core does no file I/O).
    struct Context {
        // By name: "image": "mask" resolves here first.
        std::map<std::string, std::shared_ptr<const Image>> images;
        // Otherwise the string is a path: made absolute against base_dir when
        // relative, then passed to load_image (the CLI uses gdof::io).
        std::function<Result<std::shared_ptr<const Image>>(const std::string& path)> load_image;
        std::string base_dir;
    };

    // A field that is 0 everywhere.
    BlurField();

    // Parses {"blurfield": {...}, "max_radius": ...}. Errors name the key path
    // ("blurfield.children[1].radius: must be >= 0, got -2") or, for malformed
    // JSON, the line and column.
    static Result<BlurField> parse(std::string_view json_text, const Context& ctx = {});
    // A thin-lens field (image_width_px is ignored: the camera's width is used).
    static Result<BlurField> from_thin_lens(const ThinLens& lens);

    // B at world points. Spans must have equal sizes. Single-threaded over the
    // span; call from several threads on disjoint spans to parallelise.
    Status evaluate(const Camera& camera, std::span<const Vec3> points, std::span<float> radius_px) const;
    // B given the continuous pixel position and depth of each sample (skips the projection).
    Status evaluate(const Camera& camera, std::span<const PixelDepth> samples, std::span<float> radius_px) const;
    float evaluate(const Camera& camera, const Vec3& point) const;
    float evaluate_pixel(const Camera& camera, double px, double py, double depth) const;
    // Full double precision, for one point on the central ray of (px, py).
    double evaluate_on_ray(const Camera& camera, double px, double py, double depth) const;

    // B along the central ray of the continuous pixel position (px, py) for
    // 0 <= depth_min < depth_max < inf.
    Result<RayProfile> sample_along_ray(const Camera& camera, double px, double py, double depth_min,
                                        double depth_max, const RayProfileOptions& opts = {}) const;
    // Where B <= coc_px along the central ray in [depth_min, depth_max];
    // depth_max may be +inf (see docs/blur_field.md).
    Result<InFocusIntervals> in_focus_interval(const Camera& camera, double px, double py, double coc_px,
                                               double depth_min, double depth_max,
                                               const RayProfileOptions& opts = {}) const;
    // Convenience: in_focus_interval(...).primary().
    Result<DepthInterval> primary_in_focus_interval(const Camera& camera, double px, double py, double coc_px,
                                                    double depth_min, double depth_max) const;

    // The same field with every thin_lens in it focused at `focus_distance`
    // (scene units, finite and beyond the focal length): a focus picked from the picture
    // (plate.h depth_at). An error when the field has no thin_lens.
    Result<BlurField> refocused(double focus_distance) const;
    // Global clamp from "max_radius" (+inf if none).
    double max_radius() const { return max_radius_; }
    // True if B depends only on depth (thin_lens, focal_planes and their combinations).
    bool depth_only() const;
    // Short description of the tree, e.g. "min(thin_lens, region(sphere, focus))".
    std::string describe() const;

private:
    explicit BlurField(std::shared_ptr<const bf::Node> root, double max_radius);
    std::shared_ptr<const bf::Node> root_;
    double max_radius_;
};

}  // namespace gdof
