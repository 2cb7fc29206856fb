// Shared pieces of the layer builders (layers_*.cpp): choosing depth slices
// and small helpers. Not installed.
#pragma once

#include <limits>
#include <span>
#include <string>
#include <vector>

#include "gdof/layers.h"

namespace gdof::layers_detail {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// Depth slices: slice k holds the depths d with bounds[k-1] <= d < bounds[k]
// (bounds ascending, one fewer than the slices). Depths <= 0 fall into slice
// 0 and +inf into the last slice.
struct DepthSlices {
    std::vector<double> bounds;
    // Nominal interval of each slice (Count: the equal 1/depth extents;
    // Auto: the clusters' sample ranges).
    std::vector<double> lo, hi;
    int count() const { return int(bounds.size()) + 1; }
    int slice_of(double depth) const;
};

// Auto clustering: gaps in log depth.
//  - Histogram of log(depth) over the positive finite depths, bins of
//    kAutoMinGap / 4; a gap is a run of bins holding at most
//    n * kAutoNoiseFraction samples (stray samples, antialiased depth edges)
//    that does not touch either end and is at least kAutoMinGap wide
//    (depth ratio e^0.05 ~ 5 %).
//  - At most max_layers - 1 gaps are kept (the widest; ties: nearest first).
constexpr double kAutoMinGap = 0.05;
constexpr double kAutoNoiseFraction = 2e-5;
// Auto blur cuts (LayerSplit::blur_step = 0): step = max(kAutoBlurStepPx,
// largest bin-mean radius / kAutoBlurLayers), times 1.25 until the layers fit.
constexpr double kAutoBlurStepPx = 2.0;
constexpr double kAutoBlurLayers = 4.0;

// Slices for Auto / Count from the sample depths (NaN must be filtered out
// by the caller; +inf and <= 0 are allowed and ignored when choosing).
// `radius`: empty, or one blur radius per depth (Auto's blur cuts).
DepthSlices choose_slices(std::span<const float> depths, const LayerSplit& split, std::span<const float> radius = {});

// The pixels of nearer slices (slice[j] < s, owner[j] == s) that continue
// slice s's surface (layers_from_depth_map): cont[j] = 1 for each, sized like
// depth; returns their bounding box (absolute coordinates, `win` the
// image's window).
Roi continue_surface(const std::vector<float>& depth, const std::vector<unsigned char>& present,
                     const std::vector<int>& slice, const std::vector<int>& owner, int s, int width, int height,
                     const Roi& win, double continuity, int reach, std::vector<unsigned char>& cont);

// Which slice continues or extends behind each pixel: among the slices behind
// the pixel's nearest (front[i], -1: not present), the one whose own pixels
// (own[k]: the pixels where slice k has a sample) are nearest; -1 where none.
std::vector<int> background_owners(const std::vector<int>& front, const std::vector<std::vector<unsigned char>>& own,
                                   int width, int height, const Exec& exec = {});

// "depth 2.1-3.4"
std::string depth_range_name(double near, double far);

// Median of the finite values (sorted copy); NaN if none.
double median_finite(std::vector<float> values);

// Exact Euclidean distance transform: out[i] = distance from pixel i to the
// nearest pixel with mask != 0 (+inf if none). Row-major width x height.
void distance_transform(const std::vector<unsigned char>& mask, int width, int height, std::vector<float>& out,
                        const Exec& exec = {});

}  // namespace gdof::layers_detail
