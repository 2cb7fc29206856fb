// Photographed focus sweeps: a stack shot by turning the focus ring, as method
// 2 needs it. A handheld sweep is not aligned (the camera drifts, and every
// lens changes magnification with focus: "breathing", 1-2% over a phone's
// sweep), and its frames carry no depth. This capability:
//   1. aligns every frame to the middle one with a similarity (scale,
//      rotation, shift) and a gain and offset of brightness, estimated
//      frame to neighbour frame (neighbours differ little in blur) and
//      chained; frames are resampled onto the middle frame's pixels;
//   2. finds, per pixel, the frame in which it is sharpest (depth from
//      focus: the energy of the Laplacian over a small window, its peak
//      over the frames refined between frames by a parabola through the
//      logarithms); where no frame stands out (no texture), the peak is
//      small beside strong texture nearby (an edge's blur reaching into a
//      flat area peaks in the blurriest frame), or a pixel's frame is far
//      from its neighbours' (a lone peak in a flat area), the pixel is a
//      hole, which the plate's hole fill (plate.h) fills guided by colour;
//   3. returns the all-in-focus plate (each pixel from the frames at its
//      depth) with a Z channel: a plate + depth for method 3, and the depth
//      that drives method 2 on the aligned stack itself.
// Depth is in the stack's depth units: the frames' focus distances,
// interpolated in inverse depth (a sweep moves evenly in dioptres), or the
// frame's index from 1 when no focus distance is known.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "gdof/exec.h"
#include "gdof/export.h"
#include "gdof/image.h"
#include "gdof/status.h"

namespace gdof {

// Maps a pixel position (x, y) of one frame to another, both measured from
// the data window's corner (pixel i's centre at i + 0.5): x' = a x - b y + tx, y' = b x + a y + ty (scale sqrt(a^2 + b^2),
// rotation atan2(b, a)).
struct GDOF_API Similarity {
    double a = 1, b = 0, tx = 0, ty = 0;
    void apply(double x, double y, double& xo, double& yo) const {
        xo = a * x - b * y + tx;
        yo = b * x + a * y + ty;
    }
    double scale() const;
    double rotation_degrees() const;
    // this after `first`: p -> this(first(p)).
    Similarity after(const Similarity& first) const;
    // The largest displacement over the corners of a width x height frame, px.
    double largest_shift(int width, int height) const;
};

struct AlignOptions {
    // Refused as a failure to align (a different shot, a frame with no
    // detail): a scale beyond [1/max_scale, max_scale] or a shift of more
    // than max_shift of the frame's width between neighbours.
    double max_scale = 1.15;
    double max_shift = 0.15;
    int iterations = 40;  // Gauss-Newton steps per pyramid level at most
};

// The similarity that maps `fixed`'s pixels onto `moving`'s (so `moving`
// resampled through it matches `fixed`), with a brightness gain and offset
// estimated alongside; both on the luminance of R, G, B (or the first
// channel). `initial` seeds the coarsest level.
struct GDOF_API SimilarityFit {
    Similarity map;
    double gain = 1, offset = 0;
    double residual_before = 0;  // RMS difference of the luminance (its square root) before and after, over the
    double residual_after = 0;   // pixels both frames see
};
GDOF_API Result<SimilarityFit> estimate_similarity(const Image& moving, const Image& fixed, const AlignOptions& options = {},
                                                   const Similarity& initial = {}, const Exec& exec = {});

// `source` resampled (bilinear) onto its own window through `map` (output
// pixel p takes source at map(p)); positions outside the source take its
// nearest edge pixel. Float channels only.
GDOF_API Image warp_similarity(const Image& source, const Similarity& map, const Exec& exec = {});

struct GDOF_API SweepAlignment {
    std::size_t reference = 0;           // the frame the others are aligned to (the middle one)
    std::vector<Similarity> maps;        // per frame: reference pixel -> that frame's pixel
    std::vector<double> residual_before;  // per frame: against its neighbour towards the reference (0 for it)
    std::vector<double> residual_after;
    Roi common;  // the pixels every frame sees (aligned frames are clamped outside it)
    std::string report() const;  // for --stats
};

// Aligns the frames in place (all of one size, float R, G, B or one channel,
// finite). Errors name the frame (from 1) and what failed.
GDOF_API Result<SweepAlignment> align_sweep(std::vector<Image>& frames, const AlignOptions& options = {},
                                            const Exec& exec = {});

struct DepthFromFocusOptions {
    int window_radius = 4;  // the focus measure's window: (2 r + 1)^2 pixels
    // A pixel whose sharpest frame's measure is less than this times the
    // median over the frames has no depth of its own (no texture): a hole,
    // filled from its surroundings.
    double min_peak_ratio = 3.0;
};

struct GDOF_API DepthFromFocusStats {
    std::size_t pixels = 0;
    std::size_t holes = 0;     // pixels given a depth by the fill: no frame stood out (or not beside texture), or an outlier
    std::size_t outliers = 0;  // of them, a peak more than 2 frames from the median of its 7x7 neighbours'
    std::string report() const;
};

struct GDOF_API DepthFromFocus {
    // R, G, B (the frames at each pixel's depth, blended between the two
    // nearest), A = 1, Z (depth), focus.index (the fractional frame index
    // from 1) and focus.confidence (the peak's ratio to the median, 0 for a
    // filled hole).
    Image plate;
    DepthFromFocusStats stats;
};

// `frames` aligned (align_sweep), in sweep order; `focus_depths` one per
// frame (the distance each is focused at, strictly monotonic) or empty (the
// index from 1 is the depth).
GDOF_API Result<DepthFromFocus> depth_from_focus(const std::vector<Image>& frames, const std::vector<double>& focus_depths,
                                                 const DepthFromFocusOptions& options = {}, const Exec& exec = {});

}  // namespace gdof
