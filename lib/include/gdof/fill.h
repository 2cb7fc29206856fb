// Smooth fill of missing pixels by push-pull (a weighted image pyramid):
// used to extend a layer's blur beyond its silhouette (the paper's Figure 7)
// and to extend a background layer's colour behind the foreground.
#pragma once

#include <span>

namespace gdof {

// `planes` (each width*height floats, row-major) hold values where
// weight > 0. Every pixel whose weight is 0 gets a smooth, weighted
// extrapolation of the known pixels (nearer known pixels count more); pixels
// with weight > 0 keep their values bit for bit. Weights are clamped to
// [0, 1]. Returns false (and changes nothing) when no pixel has weight.
// Deterministic; cost O(width * height * planes).
bool push_pull_fill(std::span<float* const> planes, const float* weight, int width, int height);

}  // namespace gdof
