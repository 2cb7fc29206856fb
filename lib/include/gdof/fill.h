// Smooth fill of missing pixels by push-pull (a weighted image pyramid):
// used to extend a layer's blur beyond its silhouette (the paper's Figure 7)
// and to extend a background layer's colour behind the foreground.
#pragma once

#include "gdof/exec.h"
#include "gdof/export.h"
#include "gdof/image.h"

namespace gdof {

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
GDOF_API bool push_pull_fill(const ImageView& planes, const ConstImageView& weight, const Exec& exec = {});

}  // namespace gdof
