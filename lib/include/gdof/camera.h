// Camera and lens model shared by the three methods (see docs/camera.md).
//
// Conventions:
// - Positions are world space, in scene units. Depth is the distance along the
//   camera's viewing axis, positive in front of the camera.
// - Matrices are gdof::Mat44, row vectors (p' = p * M) as in Imath / EXR.
//   worldToCamera follows OpenEXR (x right, y up, +z = viewing direction) unless
//   the camera is flagged ForwardAxis::NegZ (x right, y up, camera looks down -z,
//   as many renderers write it).
// - worldToNDC: NDC (0,0) is the top-left and (1,1) the bottom-right corner of
//   the display window, y down. Pixel (i, j) covers [i, i+1) x [j, j+1), so its
//   centre is (i + 0.5, j + 0.5); pixel x = display.x0 + ndc.x * display.width().
// - Lens: focal length and sensor width in mm; focus distance in scene units;
//   scene_unit_mm converts scene units to mm (default 1000: scene units are metres).
#pragma once

#include <cmath>
#include <limits>
#include <optional>
#include <span>
#include <string>

#include "gdof/export.h"
#include "gdof/image.h"
#include "gdof/math.h"
#include "gdof/metadata.h"
#include "gdof/status.h"

namespace gdof {

// ---------------------------------------------------------------------------
// Thin lens
// ---------------------------------------------------------------------------

// A thin lens focused at focus_distance. Circle-of-confusion (CoC) values are
// radii in output pixels: the sensor CoC diameter c (mm) is
//     c = (f / N) * f * |z - s| / (z * (s - f))      (f, z, s in mm)
// and radius_px = c / 2 * image_width_px / sensor_width_mm.
struct GDOF_API ThinLens {
    double focal_length_mm = 50.0;
    double f_number = 2.8;
    double focus_distance = 2.0;  // scene units
    double sensor_width_mm = 36.0;
    double image_width_px = 1920.0;
    double scene_unit_mm = 1000.0;  // mm per scene unit

    // Error naming the first bad parameter (<= 0, NaN/Inf, focus distance not
    // beyond the focal length), or ok.
    Status validate() const;

    // Output pixels per mm on the sensor.
    double pixels_per_mm() const { return image_width_px / sensor_width_mm; }
    // CoC diameter on the sensor in mm at depth z (scene units).
    // z = +inf gives the limit f^2 / (N (s - f)); z NaN gives NaN; z <= 0
    // (on or behind the lens plane, not imaged) gives +inf.
    double coc_diameter_mm(double depth) const;
    // CoC radius in output pixels at depth z (same special cases).
    double coc_radius_px(double depth) const;
    // The CoC radius for depth -> +inf (the limit value).
    double coc_radius_px_at_infinity() const;

    // Sensor CoC diameter (mm) of an acceptable CoC given as a radius in output pixels.
    double acceptable_coc_mm(double coc_radius_px) const { return 2.0 * coc_radius_px / pixels_per_mm(); }
    // Hyperfocal distance H = f^2 / (N c) + f (scene units) for an acceptable
    // CoC radius in output pixels (c its sensor diameter). +inf for coc <= 0.
    double hyperfocal_distance(double coc_radius_px) const;

    struct DofLimits {
        double near = 0;  // scene units
        double far = 0;   // scene units; +inf at or beyond the hyperfocal distance
    };
    // Depths where the CoC radius equals coc_radius_px (the standard limits):
    //   near = s (H - f) / (H + s - 2 f),  far = s (H - f) / (H - s)  (s < H), else +inf.
    // For coc_radius_px <= 0 both equal the focus distance.
    DofLimits dof_limits(double coc_radius_px) const;
};

// ---------------------------------------------------------------------------
// Camera
// ---------------------------------------------------------------------------

// Which camera-space axis the viewing direction is, in worldToCamera.
//   PosZ: OpenEXR / RenderMan (objects in front have positive z).
//   NegZ: OpenGL / Blender / USD style (objects in front have negative z).
//   Auto: only for reading: detected from worldToNDC for perspective
//         cameras, else PosZ (see docs/camera.md).
enum class ForwardAxis { Auto, PosZ, NegZ };
enum class Projection { Perspective, Orthographic };
GDOF_API const char* to_string(ForwardAxis a);
GDOF_API const char* to_string(Projection p);

// Optional lens data a camera carries (NaN = unknown). Written to and read
// from EXR lens attributes; the thin_lens blur field can be built from it.
struct LensInfo {
    double focal_length_mm = std::numeric_limits<double>::quiet_NaN();
    double sensor_width_mm = std::numeric_limits<double>::quiet_NaN();
    double f_number = std::numeric_limits<double>::quiet_NaN();
    double focus_distance = std::numeric_limits<double>::quiet_NaN();  // scene units
    double scene_unit_mm = 1000.0;
    // All of focal length, sensor width, f-number and focus distance are known.
    bool complete() const {
        return std::isfinite(focal_length_mm) && std::isfinite(sensor_width_mm) && std::isfinite(f_number) &&
               std::isfinite(focus_distance);
    }
};

// How a world's axes turn: which side of the image world +x lands on for a
// camera looking down world +z with world +y up.
enum class Handedness {
    // Right-handed world (OBJ, USD, Blender, Maya, Houdini; scene JSON): a
    // camera looking down -z sees +x on the right, so looking down +z it sees
    // +x on the left.
    Right,
    // Left-handed world (RenderMan, OpenEXR camera space): looking down +z,
    // +x is on the right. The camera built from lens flags for a plate (at the
    // origin, looking down +z) uses it: its world is its camera space.
    Left,
};
GDOF_API const char* to_string(Handedness h);

// An explicit camera description.
struct CameraDesc {
    Vec3 position{0, 0, 0};
    Vec3 look_at{0, 0, 1};
    Vec3 up{0, 1, 0};
    Handedness handedness = Handedness::Right;  // of the world position / look_at / up are given in
    Projection projection = Projection::Perspective;
    // Perspective: horizontal field of view from focal length and sensor width,
    // or hfov_deg when > 0 (then focal_length_mm is kept as lens information only).
    double focal_length_mm = 50.0;
    double sensor_width_mm = 36.0;
    double hfov_deg = 0.0;
    // Orthographic: width of the view in scene units.
    double ortho_width = 0.0;
    Roi display_window{0, 0, 1920, 1080};
    // Convention of the worldToCamera matrix this camera reports / writes (PosZ or NegZ).
    ForwardAxis forward_axis = ForwardAxis::PosZ;
    // Optional lens data (NaN = unknown).
    double f_number = std::numeric_limits<double>::quiet_NaN();
    double focus_distance = std::numeric_limits<double>::quiet_NaN();
    double scene_unit_mm = 1000.0;
};

// Options for reading a camera from EXR metadata.
struct CameraReadOptions {
    ForwardAxis forward_axis = ForwardAxis::Auto;  // overrides detection when not Auto
    // mm per scene unit; NaN: attribute "gdof:sceneUnitMm" if present, else 1000.
    double scene_unit_mm = std::numeric_limits<double>::quiet_NaN();
    // Used only when worldToNDC is absent and no sensor width attribute exists.
    double default_sensor_width_mm = 36.0;
};

// Pixel position (continuous, pixel centres at +0.5) and depth of a point.
struct PixelDepth {
    double x = 0, y = 0, depth = 0;
};

// A pixel's central ray: world point = origin + direction * t (direction is a
// unit vector); depth of that point = t * depth_per_t.
struct CameraRay {
    Vec3 origin;
    Vec3 direction;
    double depth_per_t = 1.0;
    Vec3 at(double t) const { return origin + direction * t; }
};

// The same ray parametrised by depth: world point at depth d = origin + per_depth * d.
struct DepthLine {
    Vec3 origin;
    Vec3 per_depth;
    Vec3 at(double depth) const { return origin + per_depth * depth; }
};

class GDOF_API Camera {
public:
    Camera() = default;  // identity camera, 1x1 display window; use a factory

    static Result<Camera> create(const CameraDesc& desc);
    // From worldToCamera (in the given convention; Auto detects from the
    // projection) and worldToNDC.
    static Result<Camera> from_matrices(const Mat44& world_to_camera, const Mat44& world_to_ndc,
                                        const Roi& display_window, ForwardAxis forward_axis = ForwardAxis::Auto,
                                        const LensInfo& lens = {});
    // From EXR attributes (see docs/camera.md for the names read).
    static Result<Camera> from_metadata(const Metadata& md, const Roi& display_window,
                                        const CameraReadOptions& opts = {});
    static Result<Camera> from_image(const Image& img, const CameraReadOptions& opts = {}) {
        return from_metadata(img.metadata, img.display_window(), opts);
    }
    // Writes worldToCamera (in this camera's forward-axis convention),
    // worldToNDC, gdof:forwardAxis, gdof:sceneUnitMm and the known lens
    // attributes (focalLength, sensorWidth, fNumber, aperture, focusDistance, focus).
    void to_metadata(Metadata& md) const;

    // World point -> continuous pixel position and depth.
    PixelDepth project(const Vec3& world) const;
    // Continuous pixel position and depth -> world point.
    Vec3 unproject(double px, double py, double depth) const;
    // Central ray of the continuous pixel position (px, py): for pixel (i, j)
    // pass (i + 0.5, j + 0.5). Perspective: origin = camera centre.
    // Orthographic: origin on the plane depth = 0.
    CameraRay central_ray(double px, double py) const;
    DepthLine depth_line(double px, double py) const;

    // Batch: points -> pixel/depth; spans must have equal sizes (else nothing is done).
    void project(std::span<const Vec3> world, std::span<PixelDepth> out) const;

    // World size of one pixel (horizontal step at the image centre) at a depth.
    double pixel_footprint(double depth) const;

    const Mat44& world_to_camera() const { return w2c_; }  // in forward_axis() convention
    const Mat44& world_to_ndc() const { return w2ndc_; }
    const Mat44& camera_to_world() const { return c2w_; }
    ForwardAxis forward_axis() const { return axis_; }
    Projection projection() const { return proj_; }
    const Roi& display_window() const { return display_; }
    int image_width() const { return display_.width(); }
    int image_height() const { return display_.height(); }
    const LensInfo& lens() const { return lens_; }
    void set_lens(const LensInfo& lens) { lens_ = lens; }
    // Camera centre (perspective) or the point on the view axis at depth 0 (orthographic).
    Vec3 position() const { return position_; }
    Vec3 forward() const { return fwd_; }  // unit viewing direction, world space
    Vec3 right() const { return right_; }  // unit, world space
    Vec3 up() const { return up_; }        // unit, world space
    // Horizontal focal length in pixels (perspective): pixel x = cx + fx * x/z.
    double focal_length_px() const { return fx_; }
    // Horizontal field of view in degrees (perspective, centred projection).
    double hfov_deg() const;
    // A thin lens from lens() and this camera's image width; error naming the
    // missing attribute if lens() is incomplete.
    Result<ThinLens> thin_lens() const;

private:
    Status init(const Mat44& w2c_file, const Mat44& w2ndc, const Roi& display, ForwardAxis axis);

    Mat44 w2c_;        // as reported (forward-axis convention)
    Mat44 w2ndc_;
    Mat44 c2w_;        // inverse of w2c_
    Mat44 w2ci_;       // world -> internal camera space (+z forward)
    Mat44 ci2w_;       // internal camera -> world
    Mat44 ci2ndc_;     // internal camera -> NDC (projective)
    Roi display_{0, 0, 1, 1};
    ForwardAxis axis_ = ForwardAxis::PosZ;
    Projection proj_ = Projection::Perspective;
    LensInfo lens_;
    Vec3 position_, fwd_{0, 0, 1}, right_{1, 0, 0}, up_{0, 1, 0};
    double fx_ = 1.0;
};

// Lens / camera values given by the user (CLI flags, OFX params) that
// override what a file's attributes say. Names as the JSON keys.
struct LensOverrides {
    std::optional<double> focal_length_mm, sensor_width_mm, f_number, focus_distance, scene_unit_mm;
    bool empty() const {
        return !focal_length_mm && !sensor_width_mm && !f_number && !focus_distance && !scene_unit_mm;
    }
};

// The camera of an image: its EXR attributes (worldToCamera / worldToNDC and
// lens data) with the overrides applied. Without camera attributes, a camera
// at the origin looking down +z is built when a focal length is given, with
// world = camera space: world +x is right in the image, +y up, depth = z
// (worldToCamera is the identity, as in OpenEXR / RenderMan); otherwise an
// error says what is missing.
GDOF_API Result<Camera> resolve_camera(const Metadata& md, const Roi& display_window, const LensOverrides& overrides = {});

// ---------------------------------------------------------------------------
// Depth encodings -> metric depth (scene units along the viewing axis)
// ---------------------------------------------------------------------------

enum class DepthEncoding {
    Metric,          // depth = v * scale (scale defaults to 1)
    Inverse,         // depth = scale / v (v = 1/Z times 1/scale); v = 0 -> +inf
    Scaled,          // depth = v * scale, v = 0 means "no measurement" (invalid).
                     // TUM RGB-D: raw uint16 counts: scale = 1/5000; values read
                     // normalised 0..1 (OIIO): scale = 65535/5000.
    NearFarLinear,   // depth = near + v * (far - near), v in 0..1
    NearFarInverse,  // 1/depth = 1/near + v * (1/far - 1/near), v in 0..1
    // Stereo disparity in pixels: depth = focal length (px) x baseline / v.
    // With `baseline` set the focal length is the camera's (resolve_depth_decode);
    // else `scale` is the product f_px x baseline. v <= 0 is invalid (most
    // disparity maps store 0 for "unknown").
    Disparity,
};
GDOF_API const char* to_string(DepthEncoding e);
// Parses "metric", "inverse", "scaled", "near_far_linear", "near_far_inverse", "disparity".
GDOF_API Result<DepthEncoding> parse_depth_encoding(const std::string& name);

// How a depth channel's stored values become metric depth, and what an
// invalid value (no measurement) becomes.
//
// Invalid values: NaN; a decoded depth that is not > 0; -inf; for Scaled and
// Disparity a stored 0; NearFar* values outside 0..1; the stored value
// `invalid_value` when given; decoded depths beyond `max_depth`. They become
// `invalid`: NaN, a **hole** (the default: plate preparation fills it from its
// surroundings, plate.h), or +inf, **sky** (infinitely far: what a user
// chooses for a depth sensor's out-of-range sky). An explicit +inf (a
// renderer's sky, Inverse 0) is always sky.
struct GDOF_API DepthDecode {
    DepthEncoding encoding = DepthEncoding::Metric;
    double scale = 1.0;
    double near = 0.0, far = 0.0;  // NearFar* only (scene units), 0 < near < far
    bool flip = false;             // NearFar*: use 1 - v (maps where 1 = near)
    // The value is distance along the pixel's ray (range), not along the
    // viewing axis; converted with the camera (depth_to_positions and plate
    // preparation).
    bool range = false;
    // What invalid samples become: NaN (a hole, the default) or +inf (sky).
    double invalid = std::numeric_limits<double>::quiet_NaN();
    // A stored value that means "no measurement" (e.g. 65535), besides the above.
    std::optional<double> invalid_value{};
    // Decoded depths beyond this are invalid (a sensor's range); +inf: none.
    double max_depth = std::numeric_limits<double>::infinity();
    // Disparity: the stereo baseline (scene units) and the focal length in
    // pixels it multiplies (set from the camera by resolve_depth_decode).
    double baseline = std::numeric_limits<double>::quiet_NaN();
    double focal_px = std::numeric_limits<double>::quiet_NaN();

    Status validate() const;
};

// The decode with what it needs from the camera filled in (Disparity with a
// baseline: the camera's horizontal focal length in pixels).
GDOF_API Result<DepthDecode> resolve_depth_decode(const DepthDecode& d, const Camera& camera);

// One stored value -> depth (scene units). Invalid values -> `invalid`; a
// Disparity decode must be resolved (resolve_depth_decode) or carry its
// f_px x baseline in `scale`.
GDOF_API double decode_depth(double v, const DepthDecode& d);
// In place over a whole plane.
GDOF_API void decode_depth(std::span<float> values, const DepthDecode& d);

// Depth map channel + camera -> world positions: an image with float channels
// P.x, P.y, P.z over the depth image's data window (display window kept).
// Pixel (i, j) is taken at its centre (i + 0.5, j + 0.5). A non-finite depth
// (invalid, or +inf sky) gives P = (NaN, NaN, NaN): there is no finite point.
GDOF_API Result<Image> depth_to_positions(const Image& depth_image, int channel, const Camera& camera,
                                          const DepthDecode& decode = {});

}  // namespace gdof
