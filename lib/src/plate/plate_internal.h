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
Guide make_guide(const Image& plate, const Exec& exec = {});

// Pixels sandwiched between a nearer and a farther neighbour on one line
// (steps larger than `continuity`) whose outer neighbours on that line are
// much flatter than the jump (a silhouette, not a steep ramp): the
// candidates for mixed silhouette pixels (1), which speckle removal leaves
// alone.
std::vector<unsigned char> mixed_candidates(const std::vector<float>& depth, int width, int height, double continuity,
                                            const Exec& exec = {});

// Islands of at most `max_px` pixels that no neighbour continues become NaN
// (pixels with keep[i] != 0 never); returns how many pixels.
std::size_t remove_speckles(std::vector<float>& depth, int width, int height, double continuity, int max_px,
                            const std::vector<unsigned char>& keep, const Exec& exec = {});

// Fills every NaN from its surroundings (see plate.h); returns how many. Needs
// at least one non-NaN pixel.
Status fill_holes(std::vector<float>& depth, int width, int height, const Guide& guide, const Exec& exec,
                  std::size_t& filled);

// Splits the mixed silhouette pixels among the candidates (plate.h step 4):
// `depth` takes the background's depth there. `rgb`: the plate's
// premultiplied R, G, B planes (null: the parts keep the pixel's colour).
std::vector<MixedPixel> split_mixed(std::vector<float>& depth, const std::vector<unsigned char>& candidate, int width,
                                    int height, double continuity, double mixed_step, const float* const rgb[3]);

}  // namespace gdof::plate_detail
