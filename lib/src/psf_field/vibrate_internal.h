// Pieces of vibrate_layers (vibrate.cpp): a layer prepared as splat sources,
// and the pyramid a sample's splats land in. Internal to psf_field.
#pragma once

#include <vector>

#include "gdof/psf_field.h"

namespace gdof::vibrate_detail {

// One layer's sources: every pixel of `region` (beyond `output` the edge
// repeats), transparent ones too, so that the splatted weight normalises
// coverage. Row-major over region.
struct Sources {
    Roi region;
    std::vector<float> r, g, b, a, z;  // premultiplied colour, coverage, depth (+inf -> 1e30)
    std::vector<float> blur;           // B, px
    std::vector<float> weights;        // the field's blend weights, weight_count per pixel
    std::vector<float> lipschitz;      // |d displacement / d u| (px per aperture unit)
    std::vector<float> stretch;        // largest change of displacement to a neighbour (px)
    std::vector<float> level;          // footprint as a continuous pyramid level (after set_levels)
    double max_displacement = 0.0;
    bool empty = true;
    // No source moves with the aperture sample (an in-focus layer, a constant
    // depth offset): every sample sees the same moved layer, made once.
    bool still = false;
};

// Prepares layer `layer` for `field` (its blend weights filled beyond the
// coverage by push-pull, like the radii).
Result<Sources> prepare_sources(const VibrateLayer& layer, const PsfField& field, const Camera& camera,
                                const Roi& frame, const Roi& output, const Exec& exec);

// The footprint of each source for sample spacing `spacing_px_per_unit`
// (aperture units): sigma = max(prefilter * spacing * lipschitz, stretch / 2),
// as the pyramid level whose splat-and-upsample kernel has that sigma (-1
// for a source that does not move: splatted exactly onto itself).
void set_levels(Sources& s, double spacing, double prefilter);
int levels_needed(const std::vector<Sources>& layers);

// A pyramid of mass buffers over `window` (level k: cells of 2^k px, one
// border cell each side); each cell holds R, G, B, A, A * Z and the weight.
class SplatPyramid {
public:
    static constexpr int kChannels = 6;
    SplatPyramid(const Roi& window, int levels);
    void clear();
    // Mass `m` (kChannels values) at continuous position (px, py), absolute
    // pixel coordinates, spread on level `level` (fractional: two levels; < 0:
    // bilinear on level 0, for sources that do not move).
    void splat(double px, double py, float level, const float* m);
    // Upsamples every level into level 0 and returns it: per pixel of the
    // window, kChannels values (row-major, interleaved), valid inside `box`
    // (window-relative pixels: where anything landed; nothing outside).
    const float* resolve(Roi& box);
    const Roi& window() const { return window_; }

private:
    void splat_level(int k, double px, double py, float w, const float* m, bool quadratic);
    Roi window_;
    std::vector<int> nx_, ny_;                // cells per level, without the border
    std::vector<std::vector<float>> cells_;  // (ny + 2) x (nx + 2) x kChannels
    std::vector<Roi> box_;                   // per level: the cells written (stored indices)
    std::vector<float> out_;
    int top_used_ = 0;  // the coarsest level splatted since clear()
};

}  // namespace gdof::vibrate_detail
