// The aperture: one description of the iris for every method. The ray
// tracer samples it (lens_rays.h: aperture_shape), the bokeh filter spreads
// each pixel over it (bokeh.h). Coordinates (u, v): u along the camera's
// right, v along up, radius 1 = the blur radius B of the blur field, so a
// point blurred by B becomes the shape scaled by B (in image pixels: x = u B,
// y = -v B).
//
//   disc     the unit disc.
//   polygon  a regular N-gon inscribed in the unit circle, `rotation_deg`
//            turning it counter-clockwise (0: a vertex on +u, as the ray
//            tracer's polygon), `roundness` bending the blades between
//            straight (0) and the circle (1).
//   image    any image as the kernel (greyscale or colour: colour fringes,
//            stars, cut-outs), fitted into [-1, 1]^2 (longer side 2, centred,
//            image rows down = -v), turned by `rotation_deg`.
// For every kind:
//   squeeze   anamorphic: the shape's width is divided by it (2 = the oval
//             bokeh of a 2x anamorphic lens, twice as tall as wide).
//   cats_eye  0..1, mechanical vignetting: towards the frame corners the
//             shape is cut by a second unit disc displaced outward by
//             cats_eye * (distance from the frame centre / half diagonal),
//             so bokeh turns into the cat's eyes of a real lens's corners.
#pragma once

#include <cmath>
#include <string>
#include <vector>

#include "gdof/export.h"
#include "gdof/image.h"
#include "gdof/status.h"

namespace gdof {

struct Aperture {
    enum class Kind { Disc, Polygon, Image };
    Kind kind = Kind::Disc;
    int blades = 6;
    double rotation_deg = 0.0;
    double roundness = 0.0;
    double squeeze = 1.0;
    double cats_eye = 0.0;
    // Kind::Image: the kernel (its data window; non-negative finite values;
    // one channel, or R, G, B for a colour kernel) and the file it came
    // from, for messages. The front ends read the file.
    Image image;
    std::string image_path;

    bool position_dependent() const { return cats_eye > 0.0; }
    // An image kernel with R, G, B: each colour channel spreads by its own.
    bool colour() const { return kind == Kind::Image && image.nchannels() >= 3; }
};

GDOF_API const char* to_string(Aperture::Kind kind);  // "disc", "polygon", "image"

// Checks the values (blades >= 3, roundness and cats_eye in [0, 1],
// squeeze > 0, finite rotation; an image kernel that is non-empty, finite,
// non-negative and not all zero): errors name the key.
GDOF_API Status validate(const Aperture& aperture);

// The CLI form: "disc" | "polygon:BLADES[:ROTATION_DEG]" | "image:FILE",
// followed by ",key=value" for roundness, squeeze, cats_eye (and rotation for
// image). The image is not read: `image_path` is set, the caller loads it.
// Errors name the unknown shape, key or malformed number.
GDOF_API Result<Aperture> parse_aperture(const std::string& spec);
// The same form back ("polygon:6:15,roundness=0.2").
GDOF_API std::string format_aperture(const Aperture& aperture);

// Whether unit-shape point (u, v) lies inside disc / polygon (roundness,
// squeeze and rotation applied; not the cat's eye). For Image, the kernel's
// luminance > 0.
GDOF_API bool aperture_contains(const Aperture& aperture, double u, double v);

// The cat's eye over a frame: at pixel (x, y) the shape is cut by a unit
// disc whose centre is offset by d = cats_eye x (distance from the frame's
// centre / half its diagonal), outward, in (u, v) with v up. One definition
// for every filter that draws it (--bokeh's spans, --vibrate's samples).
struct CatsEyeCut {
    double d = 0.0;              // the offset, in aperture radii (0: no cut)
    double ex = 0.0, ey = 0.0;   // the outward unit direction in (u, v)
};
class CatsEyeVignette {
public:
    CatsEyeVignette(double cats_eye, const Roi& frame)
        : amount_(cats_eye), cx_(0.5 * (frame.x0 + frame.x1)), cy_(0.5 * (frame.y0 + frame.y1)) {
        const double half_diag = 0.5 * std::hypot(double(frame.width()), double(frame.height()));
        inv_half_diag_ = half_diag > 0.0 ? 1.0 / half_diag : 0.0;
    }
    // (x, y) in the frame's absolute pixel coordinates (y down).
    CatsEyeCut at(double x, double y) const {
        const double dx = x - cx_, dy = y - cy_, rho = std::hypot(dx, dy);
        if (!(amount_ > 0.0) || !(rho > 0.0)) return {};
        return {amount_ * rho * inv_half_diag_, dx / rho, -dy / rho};
    }

private:
    double amount_, cx_, cy_, inv_half_diag_ = 0.0;
};

// The shape's extent row by row, for filters that spread spans: the unit
// shape (squeeze included, cat's eye not) tabulated over v in [-1, 1] with
// its left and right edges and their integrals, so the average edges over
// any horizontal strip come from two look-ups. Disc and polygon only (an
// image kernel is no span per row).
class GDOF_API ApertureProfile {
public:
    static Result<ApertureProfile> create(const Aperture& aperture);

    // Over the strip v in [v0, v1] (v0 < v1): the part of its height the
    // shape covers (`height`, in v units) and the average left / right
    // edges there. False when the shape does not reach the strip.
    bool strip(double v0, double v1, double& height, double& left, double& right) const;
    // The edges of the row at v (no averaging); false outside the shape.
    bool row(double v, double& left, double& right) const;
    // Area in (u, v) units (pi for the disc).
    double area() const { return area_; }

private:
    int n_ = 0;                 // rows over [-1, 1]
    std::vector<float> left_, right_;             // per row, NaN outside
    std::vector<double> c_height_, c_left_, c_right_;  // integrals up to row boundaries (n + 1)
    double area_ = 0.0;
    double integral(const std::vector<double>& c, double v) const;
};

// The kernel of an image aperture rasterised at blur radius `radius_px`:
// (2K + 1)^2 cells, K = ceil(radius), each the kernel's average over the
// cell (supersampled), every channel normalised to sum 1. Channels: 1 (grey)
// or 3 (colour) plus, last, the mean of the colour channels (for coverage).
struct ApertureKernel {
    int half = 0;  // K
    int channels = 0;
    std::vector<float> weights;  // [channel][row][column], rows down
    const float* plane(int c) const { return weights.data() + std::size_t(c) * std::size_t(2 * half + 1) * std::size_t(2 * half + 1); }
};
GDOF_API Result<ApertureKernel> rasterize_aperture(const Aperture& aperture, double radius_px);

// The aperture as a mask image (size x size, channel "A", coverage
// supersampled), for samplers that take masks: polygons with roundness or
// squeeze, squeezed or turned images. Not the cat's eye.
GDOF_API Image aperture_mask_image(const Aperture& aperture, int size = 256);

}  // namespace gdof
