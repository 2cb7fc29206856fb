// The deep render reduced to what a perfect plate holds: one sample per
// pixel, its colour and alpha the pixel's samples composited front to back,
// every other channel (Z, P, id ...) the front sample's. Defocused through
// the deep path, it separates what a plate lacks (the second fragment of a
// silhouette pixel, each with its own depth) from how the plate path layers.
#pragma once

#include "gdof/deep.h"

namespace gdof::bench {

DeepImage one_sample_deep(const DeepImage& deep);

}  // namespace gdof::bench
