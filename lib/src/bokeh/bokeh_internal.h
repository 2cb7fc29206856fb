// What BokehFilter prepares, shared by the bokeh sources. Not installed.
#pragma once

#include <optional>
#include <vector>

#include "gdof/bokeh.h"

namespace gdof {

struct BokehFilter::Prepared {
    Aperture aperture;
    bool spans = true;  // disc / polygon: one span per row; image: cell by cell
    // Pyramid: level 0 spreads radii [0, 2T), level k >= 1 radii [T 2^k, 2T 2^k)
    // as radii [T, 2T) on a grid 2^k coarser.
    int level_radius = 12;
    std::optional<ApertureProfile> profile;
    // Image kernels at r = q / kKernelSteps (q = 0 .. 2T kKernelSteps).
    static constexpr int kKernelSteps = 8;
    std::vector<ApertureKernel> kernels;
    int kernel_reach = 0;  // largest kernel half width (cells)
};

namespace bokeh_detail {

// Level of a radius in the pyramid above.
inline int level_of(float r, int level_radius) {
    int k = 0;
    float t = 2.0f * float(level_radius);
    while (r >= t) {
        ++k;
        t *= 2.0f;
    }
    return k;
}

}  // namespace bokeh_detail

}  // namespace gdof
