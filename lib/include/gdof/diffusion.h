// Simulated heat diffusion (Kosloff & Barsky, section 4): blur that varies
// per pixel, computed as the heat equation du/dt = div(D grad u) run to t = 1.
//
// - A pixel whose blur is a CoC radius R (output pixels) gets diffusivity
//   D = sigma^2 / 2 with sigma = R / 2 (the Gaussian with the disc's second
//   moment), so a constant field gives exactly a Gaussian of sigma = R / 2.
// - Neighbours p, q exchange heat through the conductance min(D_p, D_q). It is
//   symmetric, so the total of every channel is conserved, and a sharp pixel
//   (D = 0) is an insulator: sharp pixels neither bleed into blurred ones nor
//   receive from them (which also keeps blurred interiors opaque: no holes).
// - Image borders are insulating (no heat leaves the image).
// - Channels are diffused independently with the same operator: pass
//   premultiplied colour and alpha together so colour follows coverage.
#pragma once

#include <cmath>

#include "gdof/exec.h"
#include "gdof/export.h"
#include "gdof/image.h"
#include "gdof/status.h"

namespace gdof {

enum class DiffusionSolver {
    Explicit,  // the paper's repeated 3x3 averaging: reference, cost grows with R^2
    Adi,       // implicit alternating-direction sweeps (Thomas): cost independent of R
    Auto,      // the cheaper of the two for the largest radius (choose_solver)
};
GDOF_API const char* to_string(DiffusionSolver s);
GDOF_API Result<DiffusionSolver> parse_diffusion_solver(const char* name);  // "auto" | "explicit" | "adi"

struct DiffusionOptions {
             DiffusionSolver solver = DiffusionSolver::Auto;
    // ADI: implicit sub-steps, each an x sweep then a y sweep. One step already
    // has the exact variance; more steps bring the kernel's shape closer to a
    // Gaussian (excess kurtosis of the 1D kernel is about 3 / steps for large
    // R). 0 = automatic: clamp(ceil(8 * R_max), 4, 64), which keeps a constant
    // blur within 1% relative L2 of the analytic Gaussian.
    int adi_steps = 0;
    // Explicit: iterations = ceil(safety * 10/3 * D_max); 1 is the stability limit.
    double explicit_safety = 1.0;
    // Radii above this are an error (naming the value); radii are clamped to >= 0.
    double max_radius = 4096.0;
    // defocus(): solve each pixel's blur on the pyramid level where it is
    // 3 .. 6 cells and blend levels per pixel (docs/diffusion.md, "pyramid"),
    // so a layer's cost stops growing with its largest blur. false: every
    // layer at full resolution (the reference). diffuse_planes ignores it.
    bool pyramid = true;
};

// Diffusivity of a CoC radius in output pixels: D = (R / 2)^2 / 2.
inline double diffusivity_from_radius(double radius_px) { return radius_px * radius_px / 8.0; }
// Its inverse: the radius the solvers size their work by, from the largest
// (float) diffusivity of a map.
inline double radius_from_diffusivity(double d) { return std::sqrt(8.0 * d); }
// Number of explicit iterations needed for a largest radius.
GDOF_API int explicit_iterations(double max_radius_px, const DiffusionOptions& settings);
// Number of ADI sub-steps used for a largest radius.
GDOF_API int adi_steps_for(double max_radius_px, const DiffusionOptions& settings);
// The run time of one ADI sub-step (an x and a y sweep) in explicit
// iterations; both scale with the pixel count, so the ratio holds at any
// size. Measured by tests/bench/bench_solvers (docs/diffusion.md, "auto").
inline constexpr double kAdiStepCost = 12.0;
// The solver that runs for a largest radius: settings.solver unless it is
// Auto; then explicit when explicit_iterations <= kAdiStepCost * adi steps
// (with the default settings: R <= 42.9 px), else ADI. Both give the same
// Gaussian within 1% relative L2, so the choice only changes the run time.
GDOF_API DiffusionSolver choose_solver(double max_radius_px, const DiffusionOptions& settings);

// Diffuses the channels of `planes` in place over its window, with the
// per-pixel blur radius map `radius` (one channel over the same window; an
// error naming both shapes otherwise). Any strides: planar buffers and
// Image::channels_view() are used as they are, other layouts through an exact copy.
// NaN or negative radii are errors naming the first bad pixel (relative to
// the window's origin); Inf is an error too. Radius 0 everywhere leaves the
// planes bit-identical. Results do not depend on exec.nthreads. Auto is
// resolved by the map's largest radius.
GDOF_API Status diffuse_planes(const ImageView& planes, const ConstImageView& radius, const DiffusionOptions& settings,
                               const Exec& exec = {});

// The two solvers, on diffusivities (D per pixel, one channel over the
// planes' window, already validated: finite and >= 0).
GDOF_API Status diffuse_explicit(const ImageView& planes, const ConstImageView& diffusivity, const DiffusionOptions& settings,
                                 const Exec& exec = {});
GDOF_API Status diffuse_adi(const ImageView& planes, const ConstImageView& diffusivity, const DiffusionOptions& settings,
                            const Exec& exec = {});

}  // namespace gdof
