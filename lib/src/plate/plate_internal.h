// The steps of plate depth preparation (plate.h), each on a row-major depth
// plane over the plate's data window (NaN: a hole, +inf: sky). Internal.
#pragma once

#include <cstddef>
#include <vector>

#include "gdof/exec.h"
#include "gdof/plate.h"

namespace gdof::plate_detail {

// The plate's colour as a fill guide: three planes of sqrt(max(colour, 0))
// (brightness steps weigh alike in shadows and highlights); empty when the
// plate has no R, G, B.
struct Guide {
    std::vector<float> c[3];
    bool empty() const { return c[0].empty(); }
};
Guide make_guide(const Image& plate);

// Islands of at most `max_px` pixels that no neighbour continues become NaN;
// returns how many pixels.
std::size_t remove_speckles(std::vector<float>& depth, int width, int height, double continuity, int max_px);

// Fills every NaN from its surroundings (see plate.h); returns how many. Needs
// at least one non-NaN pixel.
Status fill_holes(std::vector<float>& depth, int width, int height, const Guide& guide, const Exec& exec,
                  std::size_t& filled);

// Splits mixed silhouette pixels (plate.h step 4): `depth` keeps the
// background's depth there; fg_depth / fg_coverage are filled (sized on the
// first mixed pixel). Returns how many.
std::size_t split_mixed(std::vector<float>& depth, int width, int height, double continuity, double mixed_step,
                        std::vector<float>& fg_depth, std::vector<float>& fg_coverage);

}  // namespace gdof::plate_detail
