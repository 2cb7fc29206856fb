// A depth map as a sensor delivers it, made from a render's exact Z for the
// benchmark's live-action row: holes, noise, quantisation.
#pragma once

#include <cstdint>

#include "gdof/image.h"

namespace gdof::bench {

struct DegradedDepthStats {
    double hole_fraction = 0;  // pixels without a measurement (0)
};

// RGBA + Z of `plate` with Z replaced by uint16 millimetre counts (stored as
// float; decode with DepthEncoding::Scaled, scale 1/1000): random holes
// (discs of 2..8 px at 640 wide covering about 12% of the frame), a
// structured-light shadow band (holes on the far side of depth steps, half
// the pixels within 2 px), no return from the sky (+inf -> 0), relative
// noise of 0.5% (Gaussian), and the render's anti-aliased (mean) depth at
// silhouettes as it is. Deterministic for a seed.
Image degraded_depth(const Image& plate, double scale, std::uint64_t seed, DegradedDepthStats* stats = nullptr);

}  // namespace gdof::bench
