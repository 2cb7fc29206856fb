// Region maths of the defocus pipeline: how far a blur spreads, the input
// region an output region needs, the output domain of an input.
#include <algorithm>
#include <cmath>

#include "gdof/defocus.h"

namespace gdof {

int defocus_margin(double max_radius_px) {
    if (!(max_radius_px > 0.0)) return 0;
    // 3 sigma with sigma = R / 2, plus one pixel for the discrete stencil.
    // Capped so that the Roi arithmetic cannot overflow (radii this large are
    // rejected by the pipeline anyway).
    const double m = std::ceil(1.5 * std::min(max_radius_px, 1.0e6)) + 1.0;
    return int(m);
}

Roi defocus_input_region(const Roi& output, double max_radius_px) {
    if (output.empty()) return {};
    return output.grown(defocus_margin(max_radius_px));
}

Roi defocus_output_region(const Roi& input_data_window, const Roi& display_window, double max_radius_px) {
    if (input_data_window.empty()) return {};
    const int m = defocus_margin(max_radius_px);
    // Blur never spreads past the frame (display window ∪ data window): the
    // frame edge insulates, so a full-frame plate keeps its edges opaque.
    return intersect(input_data_window.grown(m), unite(display_window, input_data_window));
}

}  // namespace gdof
