// What the alignment keeps of a frame, built once per frame (align_sweep
// matches each frame twice: to its neighbour, and its neighbour to it), and
// the fit on two of them. Internal to focus_sweep.
#pragma once

#include <string>
#include <vector>

#include "focus_sweep/sweep_planes.h"
#include "gdof/focus_sweep.h"

namespace gdof::sweep_detail {

struct AlignPyramid {
    Plane raw;                  // level 0 unblurred: the residuals reported
    std::vector<Plane> level;   // finest first, down to about 32 px, each binomial-blurred
    std::vector<Plane> gx, gy;  // their central differences (used when the frame is the moving one)
};

Result<AlignPyramid> make_align_pyramid(const Image& frame, const std::string& what, const Exec& exec = {});

// estimate_similarity on pyramids of frames of one size.
Result<SimilarityFit> fit_similarity(const AlignPyramid& moving, const AlignPyramid& fixed, int width, int height,
                                     const AlignOptions& options, const Similarity& initial, const Exec& exec = {});

Status check_align_options(const AlignOptions& options);

}  // namespace gdof::sweep_detail
