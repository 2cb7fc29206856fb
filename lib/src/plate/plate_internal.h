// The steps of plate depth preparation (plate.h), each on a row-major depth
// plane over the plate's data window (NaN: a hole, +inf: sky). Internal.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
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

// Two depths on one surface: within `ratio` of each other, or both sky
// (holes continue nothing).
inline bool continuous(float a, float b, double ratio) {
    if (std::isnan(a) || std::isnan(b)) return false;
    if (std::isinf(a) || std::isinf(b)) return std::isinf(a) && std::isinf(b);
    return double(std::max(a, b)) <= double(std::min(a, b)) * ratio;
}

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

// The relative noise of a depth map (a standard deviation as a fraction of
// the depth), from the second differences of inverse depth within surfaces
// (depth_noise.cpp); 0 when too few pixels continue a surface.
double estimate_depth_noise(const std::vector<float>& depth, int width, int height, double continuity,
                            const Exec& exec = {});

// Each finite pixel (not keep[i]) takes the inverse-depth plane fitted
// through the pixels of its (2 radius + 1)^2 window within `continuity` of
// it (not keep[j]), at its centre. `keep` may be empty.
void smooth_depth_noise(std::vector<float>& depth, int width, int height, double continuity, int radius,
                        const std::vector<unsigned char>& keep, const Exec& exec = {});

// Fills every NaN from its surroundings (see plate.h); returns how many. Needs
// at least one non-NaN pixel.
Status fill_holes(std::vector<float>& depth, int width, int height, const Guide& guide, const Exec& exec,
                  std::size_t& filled);

// Mixed silhouette pixels (plate.h step 4) take the nearer surface's depth:
// a pixel whose 3x3 neighbourhood spans a step of at least `mixed_step` and
// whose depth lies between its nearest and farthest neighbours (measurably:
// 2% from each), unless the 5x5 window says it is a ramp. Returns how many.
// `steps` (optional): each moved pixel with the two depths it lay between,
// in index order.
struct MixedStep {
    std::size_t index;
    float near, far;
};
std::size_t mixed_to_nearer(std::vector<float>& depth, int width, int height, double mixed_step, const Exec& exec = {},
                            std::vector<MixedStep>* steps = nullptr);

// A mixed pixel's parts from its colour (colour_parts.cpp). The two
// surfaces' colours must differ by kDistinctColours of the larger channel
// value to be told apart; the pixel may lie kResidual off the line between
// them (in units of their difference) and its share kShareSlack outside
// [0, 1]; a share within kPureShare of 0 or 1 is all one surface.
inline constexpr double kDistinctColours = 0.1;
inline constexpr double kResidual = 0.35;
inline constexpr double kShareSlack = 0.25;
inline constexpr double kPureShare = 0.1;
// A front's part never below this share: a pixel next to the front whose
// colour says none of it (its background's colour varies) keeps a trace.
inline constexpr double kMinFrontShare = 0.02;

// The colour, depth and count of one surface's pixels nearest to a mixed
// pixel (all at the least squared distance seen).
struct SideColour {
    int dist2 = std::numeric_limits<int>::max();
    int n = 0;
    double sum[3] = {0, 0, 0};
    double depth = 0;
    void add(int d2, const float* const rgb[3], std::size_t j, float q);
    void mean(double out[3]) const;
};
// The foreground's share s of `pixel` (s * fg + (1 - s) * bg nearest to
// it), or NaN where the colours cannot tell: too alike, the pixel off their
// line (texture, a third surface), s far outside [0, 1].
double colour_share(const double fg[3], const double bg[3], const float pixel[3]);
// The parts' colours for m.fg_share: each surface's colour, both moved by
// the residual so that the parts composite back exactly:
// share * fg + (1 - share) * bg = pixel.
void unmix(MixedPixel& m, const float pixel[3], const double fg[3], const double bg[3]);

// Step 4's moved pixels as parts (sharp_fronts.cpp): each one's foreground
// and background colour from the nearest measured (not was_hole; may be
// empty: none), opaque, unmoved pixels of each side in its 5x5 window, its
// share from its colour; none where the colours cannot tell, the pixel is
// nearly all foreground (as moved) or not opaque (`alpha`, may be null: all
// opaque). Its depth stays the foreground's; bg_depth is the background
// side's mean.
inline constexpr float kOpaque = 0.999f;
std::vector<MixedPixel> front_parts(const std::vector<float>& depth, const std::vector<MixedStep>& steps,
                                    const std::vector<unsigned char>& was_hole, int width, int height,
                                    double continuity, const float* const rgb[3], const float* alpha);

// Holes at silhouettes: a sensor loses the pixels next to a depth step (the
// projector's shadow on the far side, flying pixels filtered out), and those
// are the silhouette's mixed pixels. The fill gives each a depth from its
// surroundings, so it turns all foreground or all background by whichever
// neighbours its colour matched: the silhouette moves and a mixed colour is
// blurred as one surface. Here a filled hole whose 7x7 window holds both
// sides of a step (measured, non-candidate pixels at least mixed_step apart)
// is decided by its colour between the nearest measured pixels of each side:
// the share s of the foreground that best explains it; near 1 or 0 it takes
// that side's depth, between it is split as a mixed pixel (returned, in
// index order; its depth set to the background's). Surfaces too alike in
// colour, or a pixel their mix does not explain (texture, a third
// surface), keep the fill. `recoloured`: holes decided by colour.
std::vector<MixedPixel> split_silhouette_holes(std::vector<float>& depth, const std::vector<unsigned char>& was_hole,
                                               const std::vector<unsigned char>& candidate, int width, int height,
                                               double continuity, double mixed_step, const float* const rgb[3],
                                               std::size_t& recoloured);

// The camera's focal length in scene units; NaN when it is unknown (a camera
// from matrices alone). No depth within it can be focused on.
inline double focal_length_scene_units(const Camera& camera) {
    const LensInfo& li = camera.lens();
    return li.focal_length_mm / li.scene_unit_mm;
}

// What a depth within the focal length almost always is, said by both checks
// of it (the whole plate's, and the pixel --focus-at picks).
inline constexpr const char* kDepthScaleHint =
    "check the depth's encoding and scale (8- and 16-bit files are read as 0..1, so millimetres in a 16-bit file "
    "are scaled by 65.535)";

}  // namespace gdof::plate_detail
