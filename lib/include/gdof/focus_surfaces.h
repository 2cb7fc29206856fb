// Desired focus per pixel for method 2 (Kosloff & Barsky, section 3): the
// depth interval [near, far] each output pixel should be sharp in. Three
// sources (docs/compositing.md):
//
// 1. Near and far focal *surfaces*: uniform bicubic B-spline surfaces over the
//    image, each from a grid of control depths in JSON (the paper's interface).
// 2. Per-pixel near/far maps (images).
// 3. A blur field and a depth/position image: the interval along each
//    pixel's central ray where B <= the acceptable CoC.
//
// Coordinates: a DesiredFocus covers `window` (the stack's pixel grid, local
// coordinates [0, width) x [0, height)); planes are row-major over it.
//
// B-spline surfaces APPROXIMATE their control grids by default: a control grid
// of nx x ny depths is spread uniformly over the image (control point (i, j)
// sits at u = i / (nx - 1), v = j / (ny - 1); u runs left to right over the
// image width, v top to bottom over its height, u = x / width for a continuous
// pixel position x, so pixel centres are at (i + 0.5) / width), and the
// surface is the uniform cubic B-spline of those points, extended past the
// border by linear extrapolation (phantom P[-1] = 2 P[0] - P[1], P[n] =
// 2 P[n-1] - P[n-2]; replication when a neighbour is infinite). Consequences:
//   - the four corners and the border curves pass through the border control
//     points' values at the border (exactly at the corners);
//   - at an interior control point the surface is (P[i-1] + 4 P[i] + P[i+1]) / 6
//     per direction (tensor product), so bumps are smoothed, not hit;
//   - constant and bilinear grids are reproduced exactly (up to rounding);
//   - a point depends on the 4 x 4 control points around it (local control).
// With "interpolate": true the control values are first prefiltered (one
// tridiagonal solve per row and per column) so the surface passes through
// every control value at its grid position; infinite values cannot be
// interpolated (error).
// Infinite depths ("inf", for far) propagate: a pixel whose B-spline support
// includes an infinite control point with a non-zero weight is infinite.
#pragma once

#include <limits>
#include <string>
#include <vector>

#include "gdof/blur_field.h"
#include "gdof/blur_map.h"
#include "gdof/camera.h"
#include "gdof/exec.h"
#include "gdof/export.h"
#include "gdof/image.h"
#include "gdof/status.h"

namespace gdof {

// Desired near/far per pixel. near/far are npixels floats each (far may be +inf).
struct DesiredFocus {
    Roi window;
    std::vector<float> near, far;
    std::size_t npixels() const { return window.npixels(); }
    std::size_t offset(int x, int y) const {
        return std::size_t(y - window.y0) * std::size_t(window.width()) + std::size_t(x - window.x0);
    }
};

// A uniform bicubic B-spline surface over the unit square (see the top of this file).
class GDOF_API BSplineSurface {
public:
    BSplineSurface() = default;  // 0 everywhere
    static BSplineSurface constant(double value);
    // nx x ny control values, row-major with the top row first. interpolate:
    // prefilter so that the surface passes through them. Errors: sizes < 1,
    // wrong count, NaN, -inf, or infinite values with interpolate.
    static Result<BSplineSurface> create(int nx, int ny, std::vector<double> values, bool interpolate = false);

    // Surface value at (u, v); u, v are clamped to [0, 1].
    double evaluate(double u, double v) const;
    // The surface at every pixel centre ((x + 0.5) / width, (y + 0.5) / height)
    // of a width x height image, row-major into `out` (width * height values):
    // bit for bit evaluate()'s values, computed separably (each control row
    // combined once per column, then four rows per pixel). False if cancelled.
    bool evaluate_pixels(int width, int height, float* out, const Exec& exec = {}) const;
    int nx() const { return nx_; }
    int ny() const { return ny_; }
    // The B-spline control points actually used (after any prefilter).
    const std::vector<double>& control_points() const { return cp_; }
    bool interpolating() const { return interpolate_; }

private:
    int nx_ = 1, ny_ = 1;
    bool interpolate_ = false;
    std::vector<double> cp_{0.0};
    // Control point with the phantom border (i in [-1, nx], j in [-1, ny]).
    double cp(int i, int j) const;
    double phantom_x(int i, int j) const;
};

struct FocusSurfaces {
    BSplineSurface near, far;
};

// Parses a surfaces file (docs/compositing.md):
//   {"gdof_surfaces": 1, "interpolate": false,
//    "near": {"grid": [[2, 2, 3], [2, 2.5, 3]]},     // rows top to bottom, depth units
//    "far": {"grid": [[4, 4, "inf"], [4, 5, "inf"]]}} // or a single number / "inf"
// Errors name the key path ("far.grid[1][2]: ...").
GDOF_API Result<FocusSurfaces> parse_focus_surfaces(const std::string& json_text);

// Evaluates the surfaces at every pixel centre of a width x height grid.
GDOF_API Result<DesiredFocus> desired_from_surfaces(const FocusSurfaces& s, int width, int height, const Exec& exec = {});

// From per-pixel maps: channel near_channel of near_img and far_channel of
// far_img (float channels), over their data windows, which must have the same
// size (an error naming both sizes otherwise). The result's window is
// [0, width) x [0, height). NaN stays NaN (such pixels select nothing).
GDOF_API Result<DesiredFocus> desired_from_maps(const Image& near_img, int near_channel, const Image& far_img, int far_channel);
// The channel of a near/far map: `name` ("near" / "far") if present, else
// "Z", else "Y", else the first float channel; -1 if none.
GDOF_API int find_focus_map_channel(const Image& img, const std::string& name);

struct BlurFocusOptions {
    double coc_px = 1.0;     // acceptable CoC radius (output px): B <= coc_px is "in focus"
    double depth_min = 0.0;  // search range along each ray (scene units)
    double depth_max = std::numeric_limits<double>::infinity();
    // Spacing of the grid of rays that are searched when B is not a function of
    // depth alone (0: automatic = 8 px; 1: every pixel, exact). Pixels between
    // grid rays bilinearly interpolate near/far of their 4 neighbours' chosen
    // intervals. Depth-only fields (thin_lens, focal_planes, ...) search one ray.
    int grid_step = 0;
    PositionSource source;   // where the depth of each pixel comes from
};

// Desired near/far from a blur field and a depth/position image (its data
// window; the result's window is [0, w) x [0, h) over it). For each pixel the
// in-focus intervals along its central ray are found (BlurField::in_focus_interval);
// the one containing the pixel's depth is chosen, else the nearest in inverse
// depth (so sky at +inf picks the farthest), else (no depth) the primary one;
// if B never gets down to coc_px the interval is [d, d] at the sharpest depth d.
GDOF_API Result<DesiredFocus> desired_from_blur_field(const BlurField& field, const Camera& camera, const Image& depth_image,
                                                      const BlurFocusOptions& settings, const Exec& exec = {});

// The interval of `iv` chosen for a pixel at depth z (NaN: unknown), as above.
GDOF_API DepthInterval choose_interval(const InFocusIntervals& iv, double z);

}  // namespace gdof
