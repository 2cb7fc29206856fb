// Method 1 camera side: aperture sampling, the nonlinear (polyline) lens rays
// of a blur field, and the camera a renderer traces (RenderCamera: pixel +
// sample -> ray; see docs/raytrace.md, "Camera").
//
// Per pixel, the blur field B is sampled once along the pixel's central ray
// and turned into a signed cone radius rho(z) in world units:
//     |rho(z)| = B(z) * footprint(z),   footprint(z) = world size of one output
//                                        pixel at depth z (z / fx, perspective)
// with the sign flipping each time B returns from 0 (an in-focus depth): the
// rays cross there, as behind a lens. An aperture offset (u, v) in the
// aperture shape (inside the unit disc for the disc shape) gives the ray
//     p(z) = central(z) + rho(z) * (u * right + v * up)
// which is a polyline in z with a vertex at each kept breakpoint of B.
// By construction a point at depth z on the central ray is reached by the rays
// of exactly the pixels within B(z) output pixels: the image of a point is a
// disc of radius B (the aperture shape scaled by B).
//
// Everything here is deterministic and thread-safe: samples depend only on
// (pixel, sample index, seed), never on threads or tile order.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "gdof/aperture.h"
#include "gdof/blur_field.h"
#include "gdof/camera.h"
#include "gdof/export.h"
#include "gdof/image.h"
#include "gdof/math.h"
#include "gdof/status.h"

namespace gdof {

struct Vec2 {
    double x = 0, y = 0;
    constexpr bool operator==(const Vec2&) const = default;
};

// ---------------------------------------------------------------------------
// Aperture samples in the unit square
// ---------------------------------------------------------------------------

// Per-pixel seed: a hash of the integer pixel (x, y) and a global seed.
GDOF_API std::uint64_t pixel_seed(int x, int y, std::uint64_t global_seed);

// Sample `index` of a pixel's sequence in [0, 1)^2: an Owen-scrambled
// (hash-based nested uniform scramble) 2D Sobol (0,2)-sequence with shuffled
// order. Every prefix of 2^k samples is a (0,k,2)-net: each elementary
// interval of area 2^-k (1 x 2^k, 2 x 2^(k-1), ..., 2^k x 1 cells) holds
// exactly one sample; for n = 4^m the sqrt(n) x sqrt(n) grid is hit once per
// cell. Prefixes of any length are well spread (progressive, for adaptive
// sample counts).
GDOF_API Vec2 unit_square_sample(std::uint64_t pixel_seed, std::uint32_t index);
// Samples [first, first + out.size()) of the pixel's sequence.
GDOF_API void unit_square_samples(std::uint64_t pixel_seed, std::uint32_t first, std::span<Vec2> out);

// One sample of a pixel, as a camera turns it into a ray (pbrt's CameraSample).
struct CameraSample {
    Vec2 pixel_offset;  // from the pixel centre in pixel coordinates (y down): [-0.5, 0.5)^2; (0, 0) unjittered
    Vec2 aperture;      // in [0, 1)^2; the camera maps it into its aperture
};

// A pixel's camera samples: sample i depends only on (x, y, global_seed, i).
// The aperture sample is unit_square_sample(pixel_seed(x, y, global_seed), i);
// the jitter (when asked for) is a second, independent sequence of the pixel.
class GDOF_API PixelSampler {
public:
    PixelSampler(int x, int y, std::uint64_t global_seed, bool jitter);
    CameraSample sample(std::uint32_t index) const;

    // The scramble seeds of one pixel's sequence, derived once per pixel
    // rather than once per sample (unit_square_sample derives them each call).
    struct GDOF_API Sequence {
        std::uint32_t order = 0, x = 0, y = 0;
        explicit Sequence(std::uint64_t pixel_seed);
        Vec2 at(std::uint32_t index) const;
    };

private:
    Sequence aperture_, jitter_seq_;
    bool jitter_;
};

// ---------------------------------------------------------------------------
// Aperture shapes
// ---------------------------------------------------------------------------

// Maps unit-square samples to aperture offsets (u, v) (u along the camera's
// right, v along up), area-preserving (uniform in the shape). Sizes:
//   disc:    the unit disc (radius 1 = the blur radius B).
//   polygon: a regular N-gon inscribed in the unit circle (circumradius 1),
//            rotated by rotation_deg (0: a vertex on +u).
//   mask:    the image's data window fitted into [-1, 1]^2 (longer side = 2,
//            centred, y down in the image = -v), density proportional to the
//            chosen channel (values < 0 count as 0); sampled by inverting the
//            mask's CDF (rows then columns, continuous inside the pixel), so
//            stratification of the input carries over.
// Copyable; the mask's CDF is copied at construction (the Image may go away).
class GDOF_API ApertureShape {
public:
    enum class Kind { Disc, Polygon, Mask };

    ApertureShape() = default;  // the unit disc
    static ApertureShape disc();
    // blades >= 3.
    static Result<ApertureShape> polygon(int blades, double rotation_deg = 0.0);
    // channel -1: "A" if present, else channel 0. Errors: empty image, bad
    // channel, non-finite values, no positive value.
    static Result<ApertureShape> mask(const Image& image, int channel = -1);

    Kind kind() const { return kind_; }
    int blades() const { return blades_; }
    // Unit square [0,1)^2 -> aperture offset.
    Vec2 map(Vec2 unit) const;
    // Area of the shape in (u, v) units (pi for the disc).
    double area() const;

private:
    Kind kind_ = Kind::Disc;
    int blades_ = 0;
    double rotation_rad_ = 0.0;
    // Mask: marginal CDF over rows, conditional CDF per row, geometry.
    int mask_w_ = 0, mask_h_ = 0;
    std::vector<double> row_cdf_;   // size h + 1
    std::vector<double> col_cdf_;   // size h * (w + 1)
    double mask_scale_ = 1.0;       // (u, v) units per mask pixel
    double mask_area_ = 0.0;
};

// The sampler of an aperture description: disc and plain polygons as
// themselves, rounded or squeezed polygons and image kernels as a mask of
// the shape (its luminance for a colour kernel). The cat's eye (a shape that
// changes across the frame) is an error.
GDOF_API Result<ApertureShape> aperture_shape(const Aperture& aperture);

// Concentric (Shirley-Chiu) map of [0,1)^2 onto the unit disc.
GDOF_API Vec2 concentric_disc(Vec2 unit);

// ---------------------------------------------------------------------------
// Polyline rays
// ---------------------------------------------------------------------------

// One aperture sample's ray: vertices points[0..n-1] (points[0] on the lens
// plane, depth 0; depth[i] their depths), then straight on from points[n-1]
// along far_direction (unit) to infinity. Segment i (i < n-1) goes from
// points[i] to points[i+1]. With a single vertex the ray is straight:
// origin points[0], direction far_direction.
struct PolylineRay {
    std::vector<Vec3> points;
    std::vector<double> depth;
    Vec3 far_direction;

    std::size_t segments() const { return points.size(); }  // incl. the infinite last one
    // A straight ray: one vertex (its origin, depth 0), then its direction.
    void set_straight(const CameraRay& r) {
        points.assign(1, r.origin);
        depth.assign(1, 0.0);
        far_direction = r.direction;
    }
};

struct NonlinearCameraOptions {
    // Depth range over which B is sampled (scene units, 0 < depth_min < depth_max < inf).
    // Before depth_min the first segment is extended to the lens plane; beyond
    // depth_max the last segment continues to infinity.
    double depth_min = 1e-3;
    double depth_max = 1e5;
    // Tolerance of the B profile (output pixels), see RayProfileOptions.
    double profile_tolerance_px = 0.01;
    int max_profile_vertices = 20000;
    // Accuracy of the polyline: max |rho_polyline - B * footprint| in output
    // pixels at the checked points (1/4, 1/2, 3/4 of each segment, against the
    // exact field). Note rho = B * footprint is not linear where B is (it is
    // linear for thin_lens), so segments are subdivided in rho, and redundant
    // profile vertices (straight in rho) are dropped; in-focus vertices are kept.
    double ray_tolerance_px = 0.01;
};

// A pixel's cone, prepared once and shared by all its aperture samples.
struct PixelCone {
    double px = 0, py = 0;           // continuous pixel position
    CameraRay central;               // Camera::central_ray(px, py), bit for bit
    DepthLine line;                  // Camera::depth_line(px, py)
    std::vector<double> depth;       // vertex depths; depth[0] = 0 (lens plane)
    std::vector<double> rho;         // signed cone radius (scene units) at each vertex
    double far_slope = 0;            // d rho / d depth beyond the last vertex
    std::vector<double> in_focus;    // depths where B == 0 (the rays cross)
    double max_blur_px = 0;          // largest B on the profile (adaptive sampling hint)
    bool pinhole = true;             // rho == 0 everywhere: the pinhole ray
};

class GDOF_API NonlinearCamera {
public:
    // Validates the options. The camera and field are copied (both are cheap:
    // a BlurField shares its tree).
    static Result<NonlinearCamera> create(const Camera& camera, const BlurField& field,
                                          const NonlinearCameraOptions& opts = {},
                                          const ApertureShape& shape = {});

    // Samples B along the central ray of (px, py) (pixel (i, j): pass i + 0.5,
    // j + 0.5) and fills `out` (its buffers are reused).
    Status prepare(double px, double py, PixelCone& out) const;
    Result<PixelCone> prepare(double px, double py) const;

    // When field().depth_only() (thin_lens, focal_planes, ...), rho(z) is the
    // same for every pixel: a cone prepared for one pixel is moved to another
    // pixel by replacing its central ray (identical to prepare(px, py) up to
    // the profile tolerance, exact for thin_lens). Much cheaper than prepare.
    bool depth_only() const { return field_.depth_only(); }
    void retarget(PixelCone& cone, double px, double py) const;

    // The ray for an aperture offset (u, v) already in the shape (e.g. from
    // shape().map(...)). A pinhole cone gives exactly {central.origin},
    // far_direction = central.direction. `out`'s buffers are reused.
    void ray(const PixelCone& cone, Vec2 aperture_offset, PolylineRay& out) const;
    // Convenience: unit-square sample -> shape -> ray.
    void ray_from_unit(const PixelCone& cone, Vec2 unit_sample, PolylineRay& out) const {
        ray(cone, shape_.map(unit_sample), out);
    }
    // The ray of one camera sample of the cone's pixel (pbrt's GenerateRay):
    // ray_from_unit(sample.aperture), every vertex then moved by the pixel
    // offset at its depth (offset * footprint(depth): the cone of the offset
    // position, exact for a depth-only field). A pinhole cone gives the
    // central ray of the offset position (Camera::central_ray, bit for bit).
    void generate_ray(const PixelCone& cone, const CameraSample& sample, PolylineRay& out) const;
    // Lazy alternative to ray() for tracers that stop at the first hit: the
    // world offset of an aperture sample, then vertex i (depth cone.depth[i])
    // = cone.line.at(depth) + offset * rho[i] (exactly line.at(depth) where
    // rho == 0), and the far direction after the last vertex. For a pinhole
    // cone use cone.central (ray() does) to get the pinhole ray bit for bit.
    Vec3 aperture_offset_world(Vec2 a) const { return camera_.right() * a.x + camera_.up() * a.y; }
    static Vec3 vertex(const PixelCone& cone, const Vec3& offset_world, std::size_t i) {
        const Vec3 c = cone.line.at(cone.depth[i]);
        return cone.rho[i] == 0.0 ? c : c + offset_world * cone.rho[i];
    }
    static Vec3 far_direction(const PixelCone& cone, const Vec3& offset_world) {
        return normalize(cone.line.per_depth + offset_world * cone.far_slope);
    }

    // World point of the aperture offset's ray at a depth (no allocation).
    Vec3 point_at(const PixelCone& cone, Vec2 aperture_offset, double depth) const;
    // Signed cone radius at a depth (linear between vertices).
    static double rho_at(const PixelCone& cone, double depth);

    const Camera& camera() const { return camera_; }
    const BlurField& field() const { return field_; }
    const ApertureShape& shape() const { return shape_; }
    const NonlinearCameraOptions& options() const { return opts_; }
    // World size of one output pixel at a depth: footprint0 + footprint1 * depth.
    double footprint(double depth) const { return fp0_ + fp1_ * depth; }

private:
    Camera camera_;
    BlurField field_;
    NonlinearCameraOptions opts_;
    ApertureShape shape_;
    double fp0_ = 0, fp1_ = 0;
};

// ---------------------------------------------------------------------------
// Straight-ray thin lens (the reference)
// ---------------------------------------------------------------------------

// pbrt-style thin lens: ray origin = the pixel's central-ray origin +
// lens_radius * (u * right + v * up) ((u, v) in the unit disc), through the
// point where the central ray meets the plane depth = focus_depth. The
// direction is unit; depth_per_t as in CameraRay.
GDOF_API CameraRay thin_lens_ray(const Camera& camera, double px, double py, double lens_radius, double focus_depth,
                                 Vec2 aperture_offset);

// The lens radius (scene units) of the straight thin lens that method 1
// driven by BlurField::from_thin_lens(lens) equals exactly:
//     R = f / (2 N) * s / (s - f)     (scene units)
// gdof cameras keep the focal-length field of view (fx = f W / sensor width)
// while ThinLens::coc_radius_px images at the sensor distance v = s f / (s - f);
// the factor v / f = s / (s - f) reconciles them (docs/raytrace.md).
GDOF_API double thin_lens_equivalent_radius(const ThinLens& lens);
// f / (2 N) in scene units (the textbook / pbrt aperture radius).
GDOF_API double thin_lens_aperture_radius(const ThinLens& lens);

// ---------------------------------------------------------------------------
// The camera a renderer traces
// ---------------------------------------------------------------------------

// One of the three cameras of method 1 behind one interface: per pixel
// prepare_pixel, then generate_ray per camera sample. Copyable, immutable,
// thread-safe; every ray depends only on (pixel, sample).
class GDOF_API RenderCamera {
public:
    enum class Kind {
        Pinhole,           // Camera::central_ray of the sample's position
        StraightThinLens,  // thin_lens_ray (aperture: concentric_disc)
        Polyline,          // NonlinearCamera::generate_ray
    };
    static RenderCamera pinhole(const Camera& camera);
    static RenderCamera straight_thin_lens(const Camera& camera, double lens_radius, double focus_depth);
    // A depth-only field's cone is prepared here, once, at the centre of the
    // display window's first pixel; errors: the field cannot be sampled there.
    static Result<RenderCamera> polyline(const NonlinearCamera& camera);

    Kind kind() const { return kind_; }
    const Camera& camera() const { return camera_; }

    // Readies `cone` (its buffers are reused from pixel to pixel) for the pixel
    // at (px, py) (pixel (i, j): i + 0.5, j + 0.5). Polyline: the cone of the
    // pixel (NonlinearCamera::prepare, or the shared cone of a depth-only field
    // moved there); the other kinds only set cone.px, cone.py. Errors: the
    // blur field cannot be sampled along the pixel's ray.
    Status prepare_pixel(double px, double py, PixelCone& cone) const;
    // The ray to trace for one sample of the prepared pixel; a straight ray is
    // a single vertex (its origin) and far_direction. `out`'s buffers are reused.
    void generate_ray(const PixelCone& cone, const CameraSample& sample, PolylineRay& out) const;

private:
    RenderCamera(Kind kind, const Camera& camera) : kind_(kind), camera_(camera) {}
    Kind kind_;
    Camera camera_;
    double lens_radius_ = 0, focus_depth_ = 0;   // StraightThinLens
    std::optional<NonlinearCamera> nonlinear_;   // Polyline
    std::optional<PixelCone> shared_cone_;       // Polyline of a depth-only field
};

}  // namespace gdof
