// How the solvers link two neighbouring pixels' diffusivities (the
// conductance of the link between them), and the solvers' entry points that
// take the rule (docs/diffusion.md, "pyramid"). The public diffuse_planes,
// diffuse_explicit and diffuse_adi use Min.
#pragma once

#include <algorithm>

#include "gdof/diffusion.h"

namespace gdof::diffusion_detail {

enum class Conductance {
    // min(D_p, D_q): the paper's, so the sharper side of a link insulates.
    Min,
    // 2 D_p D_q / (D_p + D_q), 0 when either end is 0 (an insulator still
    // conducts nothing): two half-cells in series. For a pyramid's coarse
    // levels, where one link spans 2^j pixels: across a smooth change of blur
    // it is the blur at the link (min() took the blur a whole cell away, and
    // a ramp of blur came out 2-4% too narrow); across a jump of blur it is
    // at most twice the smaller, so the sharper cell still nearly insulates
    // (the arithmetic mean let blur cross silhouettes: +3.5% edge error on
    // the benchmark's 1080p Cornell box, deep, sphere of focus).
    Harmonic,
};

inline float link(float a, float b, Conductance c) {
    if (c == Conductance::Min) return std::min(a, b);
    return a > 0.0f && b > 0.0f ? 2.0f * a * b / (a + b) : 0.0f;
}

Status diffuse_planes(const ImageView& planes, const ConstImageView& radius, const DiffusionOptions& settings,
                      const Exec& exec, Conductance conductance);
Status diffuse_explicit(const ImageView& planes, const ConstImageView& diffusivity, const DiffusionOptions& settings,
                        const Exec& exec, Conductance conductance);
Status diffuse_adi(const ImageView& planes, const ConstImageView& diffusivity, const DiffusionOptions& settings,
                   const Exec& exec, Conductance conductance);

}  // namespace gdof::diffusion_detail
