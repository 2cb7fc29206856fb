// Internal: the blur-field expression tree (not installed).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "gdof/blur_field.h"
#include "gdof/camera.h"

namespace gdof::bf {

constexpr std::size_t kChunk = 256;  // points per evaluation chunk (stack buffers)

// What a node reads from a batch.
enum Needs : unsigned { kWorld = 1u, kPixel = 2u, kDepth = 4u };

// Structure-of-arrays chunk of at most kChunk samples. Arrays a node does not
// need (per needs()) may be null.
struct Batch {
    std::size_t n = 0;
    const double *x = nullptr, *y = nullptr, *z = nullptr;        // world position
    const double *px = nullptr, *py = nullptr, *depth = nullptr;  // pixel, depth
    const Camera* camera = nullptr;
};

// A central ray, parametrised by depth.
struct Ray {
    const Camera* camera = nullptr;
    DepthLine line;
    double px = 0, py = 0;
};

class Node {
public:
    virtual ~Node() = default;
    // out[i] = B at sample i (double), i < b.n <= kChunk.
    virtual void eval(const Batch& b, double* out) const = 0;
    virtual unsigned needs() const = 0;
    // Appends the depths in [a, b] where this node has a kink, a step, a zero
    // boundary or a region boundary along the ray (unsorted, may repeat).
    virtual void breakpoints(const Ray& r, double a, double b, std::vector<double>& out) const = 0;
    // Exactly linear in depth between consecutive breakpoints (no subdivision needed).
    virtual bool linear_between_breakpoints() const = 0;
    virtual std::string describe() const = 0;
    // This node with every thin lens in it focused at `focus_distance`, or
    // null when it holds no thin lens (nothing to refocus). The lens with its
    // new focus must be valid (else an error naming the distance).
    virtual Result<std::shared_ptr<const Node>> refocused(double focus_distance) const;
};

using NodePtr = std::shared_ptr<const Node>;

// B of a node at depths along a ray (any count; chunked internally).
void eval_on_ray(const Node& node, const Ray& r, const double* depths, std::size_t n, double* out);
double eval_on_ray(const Node& node, const Ray& r, double depth);

// Depths in [a, b] where f(d) - level changes sign, searched on a grid through
// the given sorted points (each gap split into `splits` parts, geometric for
// wide positive ranges) and refined by bisection to ~1e-13 relative.
template <class F>
void level_crossings(const F& f, double level, const std::vector<double>& grid_points, int splits,
                     std::vector<double>& out);

// Sorted, deduplicated grid: {a, b} plus the given points inside [a, b].
std::vector<double> make_grid(double a, double b, std::vector<double> pts);
// A point strictly between a and b (geometric mean for wide positive ranges).
double split_point(double a, double b);

// --- leaves ---
NodePtr make_thin_lens(const ThinLens& lens);
struct FocalPlanesSpec {
    std::vector<double> depths;  // sorted, distinct, > 0
    double max_blur;             // +inf if not given
    double slope;                // 0 if not given
    bool smooth;
};
NodePtr make_focal_planes(const FocalPlanesSpec& s);
enum class Shape { Sphere, Box, Plane };
struct RegionSpec {
    Shape shape = Shape::Sphere;
    bool focus_mode = true;  // true: sharp inside; false: blurred inside
    double blur = 0, falloff = 0;
    bool smooth = true;
    Vec3 center;                 // sphere / box
    double radius = 0;           // sphere
    Vec3 half_size;              // box
    Vec3 rot_x{1, 0, 0}, rot_y{0, 1, 0}, rot_z{0, 0, 1};  // box local axes in world space
    Vec3 point, normal{0, 0, 1};  // plane (normal unit)
    double half_thickness = 0;    // plane
};
NodePtr make_region(const RegionSpec& s);
NodePtr make_image_map(std::shared_ptr<const Image> img, int channel, double scale, std::string name);

// --- combinators ---
enum class Op { Min, Max, Add, Mul };
NodePtr make_nary(Op op, std::vector<NodePtr> children);
NodePtr make_scale(NodePtr child, double factor);
NodePtr make_clamp(NodePtr child, double lo, double hi);
NodePtr make_zero();

// ---------------------------------------------------------------------------

template <class F>
void level_crossings(const F& f, double level, const std::vector<double>& grid_points, int splits,
                     std::vector<double>& out) {
    if (grid_points.size() < 2) return;
    auto refine = [&](double lo, double flo, double hi) {
        const bool lo_above = flo > level;
        for (int it = 0; it < 200; ++it) {
            const double m = split_point(lo, hi);
            if (!(m > lo && m < hi)) break;
            if ((f(m) > level) == lo_above) lo = m;
            else hi = m;
            if (hi - lo <= 1e-14 * std::max(std::abs(lo), std::abs(hi))) break;
        }
        out.push_back(0.5 * (lo + hi));
    };
    double prev = grid_points[0];
    double fprev = f(prev);
    for (std::size_t i = 1; i < grid_points.size(); ++i) {
        const double a = grid_points[i - 1], b = grid_points[i];
        for (int k = 1; k <= splits; ++k) {
            double d;
            if (k == splits) d = b;
            else if (a > 0 && b > 4 * a) d = a * std::pow(b / a, double(k) / splits);
            else d = a + (b - a) * double(k) / splits;
            const double fd = f(d);
            if (!std::isnan(fd) && !std::isnan(fprev) && ((fd > level) != (fprev > level))) refine(prev, fprev, d);
            prev = d;
            fprev = fd;
        }
    }
}

}  // namespace gdof::bf
