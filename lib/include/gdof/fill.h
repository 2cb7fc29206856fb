// Smooth fill of missing pixels by push-pull (a weighted image pyramid):
// used to extend a layer's blur beyond its silhouette (the paper's Figure 7)
// and to extend a background layer's colour behind the foreground.
#pragma once

#include <span>

#include "gdof/exec.h"
#include "gdof/export.h"
#include "gdof/image.h"

namespace gdof {

// The pyramid's grid. Single: one pyramid (classic push-pull), whose cell
// boundaries decide where the fill puts an edge it continues: a step hidden
// by a 26 px strip lands up to 5 px off the strip's middle, and moves as the
// picture moves by a pixel. Spun: the average of 4 pyramids on grids offset
// by up to 31 px (cycle spinning): within 1.5 px, so the fill follows a pan.
// About 2.5x the cost of Single (the first coarse level is pushed once for
// two of the four).
enum class FillGrids { Single, Spun };

// `planes` (any number of channels) hold values where `weight` (one channel
// over the same window) > 0. Every pixel whose weight is 0 gets a smooth,
// weighted extrapolation of the known pixels (nearer known pixels count
// more: a pixel beside known ones takes nearly their values, whatever lies
// a pyramid cell away); pixels with weight > 0 keep their values bit for
// bit. Weights are
// clamped to [0, 1]. Returns false (and changes nothing) when no pixel has
// weight, when there are no planes or pixels, and when `weight` is not one
// channel over the planes' window. Deterministic (the same bits for any
// thread count of `exec`); cost O(pixels * planes).
GDOF_API bool push_pull_fill(const ImageView& planes, const ConstImageView& weight, const Exec& exec = {},
                             FillGrids grids = FillGrids::Single);

// The same, filling only the unknown pixels that `wanted` marks (row-major
// over the planes' window; empty: all): each gets the bits the whole fill
// would give it, the other unknown pixels keep their values. A layer's
// extension needs its fill in a band around the layer (5% of the unknown
// pixels of a 4K frame's layers), and level 0 is most of the fill's cost.
// Returns false also when `wanted` is not one value per pixel.
GDOF_API bool push_pull_fill(const ImageView& planes, const ConstImageView& weight,
                             std::span<const unsigned char> wanted, const Exec& exec = {},
                             FillGrids grids = FillGrids::Single);

}  // namespace gdof
