// 4D light fields as a grid of sub-aperture views, refocused by shift-and-add
// into focus/aperture stacks for method 2 (Kosloff & Barsky, section 3).
//
// Grid and sign convention
// - The views form a rows x cols grid, row-major; view (row, col) sits
//   (du, dv) = (col - center_col, row - center_row) view steps from the
//   central view. Rows go down the grid, columns to the right, as the file
//   indices do ("2067_RR_CC.png": RR is the row, CC the column).
// - A scene point at *disparity* d (pixels per view step) seen at image
//   position (x, y) in the central view appears at (x - d * du, y - d * dv) in
//   view (row, col): a view one step to the right and one down, (row+1,
//   col+1), shows the point moved by (-d, -d) pixels (up and to the left).
//   This is the stereo convention: for a camera array whose columns move
//   right (rows down), near points have the larger disparity.
// - Depth and disparity: d(z) = focal_baseline / z + disparity_at_infinity,
//   focal_baseline = focal length (px) x baseline (scene units per view
//   step), positive for such an array. The real Lytro views in
//   ../shared/data/lightfield/lytro_2067 follow the same convention (near
//   points have the larger disparity: the dinosaur is sharp at d = +1.0, the
//   wall behind it at d = 0; measured, see docs/lightfield.md), so
//   focal_baseline > 0 there too. A negative focal_baseline describes a grid
//   ordered the other way. focal_baseline = 1 when unknown: depths are then
//   pseudo-depths 1 / (d - disparity_at_infinity).
//
// Refocusing (shift-and-add)
// - For a focus disparity d_f and an aperture radius r (view steps), the
//   synthetic aperture is the set of views with du^2 + dv^2 <= r^2 (+1e-9);
//   each is sampled at (x - d_f * du, y - d_f * dv) (its content moved by
//   +d_f * (du, dv), undoing the parallax of disparity d_f) and the samples
//   are averaged. Points at disparity d_f line up (sharp), others spread over
//   a disc of radius r * |d - d_f| pixels.
// - Sub-pixel samples: Catmull-Rom bicubic (default) or bilinear; edges are
//   clamped. A shift whose fractional part is zero along an axis is an exact
//   copy along that axis (no interpolation). Radius 0 returns the central
//   view exactly. Every float channel is averaged (colour is expected
//   premultiplied by alpha when there is alpha, as everywhere in gdof).
// - Summation: per output pixel, views in row-major order, float accumulation,
//   divided by the number of views (independent of threads and tiling).
#pragma once

#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "gdof/exec.h"
#include "gdof/export.h"
#include "gdof/focal_stack.h"
#include "gdof/image.h"
#include "gdof/status.h"

namespace gdof {

struct GDOF_API LightFieldGeometry {
    double disparity_at_infinity = 0.0;  // px per view step of points at infinite depth
    double focal_baseline = 1.0;         // focal length (px) x baseline (scene units per step); sign per the convention
    bool depth_known = false;            // false: focal_baseline is the default 1 (pseudo-depths)

    // d(z) = focal_baseline / z + disparity_at_infinity; z = +inf gives d_inf.
    double disparity_of_depth(double z) const;
    // Inverse of disparity_of_depth: +inf at (or beyond) infinity, NaN when
    // the disparity lies on the far side of infinity (no depth > 0 has it).
    double depth_of_disparity(double d) const;
};

// The depth interval [near, far] whose points have a disparity in [d_lo, d_hi]
// (far may be +inf; near = 0 when d_hi is unbounded). Both NaN when no
// positive depth has such a disparity.
struct DepthRange {
    double near = std::numeric_limits<double>::quiet_NaN();
    double far = std::numeric_limits<double>::quiet_NaN();
};
GDOF_API DepthRange depth_interval(const LightFieldGeometry& g, double d_lo, double d_hi);

// Depth of field of a refocused image: the points whose circle of confusion
// r * |d - d_f| is at most coc_px pixels. r = 0: every depth ([0, inf]).
GDOF_API DepthRange refocus_depth_of_field(const LightFieldGeometry& g, double focus_disparity, double aperture_radius,
                                              double coc_px);

struct GDOF_API LightField {
    int rows = 0, cols = 0;
    int center_row = 0, center_col = 0;  // grid indices of the central view
    std::vector<Image> views;            // rows * cols, row-major, linear float, same channels and windows
    std::vector<std::string> sources;    // file of each view (may be empty for generated fields)
    LightFieldGeometry geometry;

    const Image& view(int row, int col) const { return views[std::size_t(row) * std::size_t(cols) + std::size_t(col)]; }
    Image& view(int row, int col) { return views[std::size_t(row) * std::size_t(cols) + std::size_t(col)]; }
    const Image& central() const { return view(center_row, center_col); }
    // Checks the grid: sizes, a central view inside it, views with equal
    // channel names and data windows (errors name the view's file).
    Status validate() const;
    // Number of views inside the synthetic aperture of radius r.
    int aperture_views(double aperture_radius) const;
};

enum class LightFieldFilter { Bicubic, Bilinear };
GDOF_API const char* to_string(LightFieldFilter f);
GDOF_API Result<LightFieldFilter> parse_lightfield_filter(const std::string& name);

struct RefocusOptions {
    double focus_disparity = 0.0;  // d_f, px per view step
    double aperture_radius = 0.0;  // r, view steps (0: the central view)
    LightFieldFilter filter = LightFieldFilter::Bicubic;
};

// Shift-and-add refocus; the result has the central view's channels (float),
// windows and metadata.
GDOF_API Result<Image> refocus(const LightField& lf, const RefocusOptions& settings, const Exec& exec = {});

// One reference of a stack: focus as a disparity, or a depth (converted with
// the geometry; +inf = disparity_at_infinity), and an aperture radius.
struct StackRequest {
    double focus_disparity = std::numeric_limits<double>::quiet_NaN();
    double focus_depth = std::numeric_limits<double>::quiet_NaN();  // used when focus_disparity is NaN
    double aperture_radius = 0.0;
};

struct ExtractStackOptions {
    std::vector<StackRequest> references;
    double coc_px = 1.0;  // acceptable CoC radius (px) for near/far
    LightFieldFilter filter = LightFieldFilter::Bicubic;
    double scene_unit_mm = 1000.0;  // recorded in the manifest
};

struct ExtractedStack {
    std::vector<Image> images;  // one per reference, in order
    FocalStack stack;           // near/far, focus_disparity, aperture_radius_views filled; file names empty
};

// (StackSink, focal_stack.h: when given, `images` is left empty.)

// Resolves each request's focus disparity and depth of field; errors name the
// reference ("references[2].aperture_radius: ..."), duplicates are errors.
GDOF_API Result<FocalStack> plan_stack(const LightField& lf, const ExtractStackOptions& spec);
// Plans and refocuses every reference. Progress is reported over the whole stack.
GDOF_API Result<ExtractedStack> extract_stack(const LightField& lf, const ExtractStackOptions& spec, const StackSink& sink = {},
                                              const Exec& exec = {});

}  // namespace gdof
