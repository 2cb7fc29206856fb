// Method 3 end to end: generalized defocus by simulated heat diffusion of
// layers (Kosloff & Barsky, section 4).
//
//   input (deep / multipart / RGBA + depth) -> layers (layers.h)
//   -> per layer: blur radius per pixel from the blur field at the pixel's
//      world position, smoothly extrapolated beyond the layer's coverage
//      (push-pull, fill.h) so a blurred object grows past its silhouette
//   -> diffusion of premultiplied RGBA (diffusion.h) on the layer's window
//      grown by its largest blur; zero-blur and empty layers pass through
//   -> composite back to front with `over`.
#pragma once

#include <string>
#include <vector>

#include "gdof/aperture.h"
#include "gdof/blur_field.h"
#include "gdof/camera.h"
#include "gdof/diffusion.h"
#include "gdof/exec.h"
#include "gdof/export.h"
#include "gdof/image_set.h"
#include "gdof/layers.h"
#include "gdof/plate.h"
#include "gdof/psf_field.h"
#include "gdof/status.h"

namespace gdof {

// What blurs each layer: the heat equation (Gaussian point-spread function,
// diffusion.h) or the bokeh filter (the aperture's shape, bokeh.h). Both run
// in the same pipeline: layers, extrapolated radii, back-to-front `over`.
// Or, with Vibrate, not a filter per layer but method 4, the generalized PSF
// field (psf_field.h): the layers moved per aperture sample and composited
// with visibility, the samples averaged.
enum class DefocusFilter { Diffusion, Bokeh, Vibrate };
GDOF_API const char* to_string(DefocusFilter f);  // "diffusion", "bokeh", "vibrate"

struct DefocusOptions {
    DefocusFilter filter = DefocusFilter::Diffusion;
    Aperture aperture;       // the bokeh filter's point-spread function, vibrate's sample domain (disc by default)
    PsfField psf_field;      // Vibrate: the displacement field (default: defocus, B(x) * u)
    VibrateOptions vibrate;  // Vibrate: sample count, seed, prefilter
    DiffusionOptions diffusion;
    LayerSplit split;        // deep and RGBA + depth inputs
    PositionSource source;   // position / depth channels and depth encoding
    DepthCleanupOptions cleanup;  // RGBA + depth (plates): speckles, holes, mixed pixels (plate.h)
    // Output region in absolute pixels; empty = the whole result: the union
    // of the layers' data windows and their work regions (each layer's
    // content grown by defocus_margin of its own largest blur), clipped to
    // the frame (display window ∪ the layers' data windows). The frame edge
    // insulates: blur does not leak out of it, so a full-frame plate keeps
    // opaque edges (as an edge-clamped blur would). (So the result lies within
    // defocus_output_region(input data window, display, largest blur).)
    // A sub-region equals the crop of the whole result to within 1e-4 of the
    // image's peak value; the one difference is the insulated boundary of the
    // cropped work regions (docs/diffusion.md, "Sub-regions", has the figure).
    Roi roi;
};

struct GDOF_API DefocusStats {
    int layers = 0;
    int layers_empty = 0;      // no coverage: cost nothing
    int layers_sharp = 0;      // largest blur 0: passed through untouched
    int layers_explicit = 0, layers_adi = 0;  // diffused layers by the solver that ran
    int layers_bokeh = 0;      // layers spread by the bokeh filter
    int layers_pyramid = 0;
    int layers_vibrated = 0;   // non-empty layers moved by the PSF field (Vibrate)
    VibrateStats vibrate;      // Vibrate: samples, largest displacement, splats    // diffused layers solved on pyramid levels (DiffusionOptions::pyramid)
    std::size_t pixels_diffused = 0;  // summed over layers (work-region pixels)
    std::size_t pixels_skipped = 0;   // layer pixels outside any work region / in sharp layers
    double max_radius_px = 0.0;
    DepthCleanupStats depth;   // plates: what the depth preparation did
    // Seconds per stage.
    double t_layers = 0, t_blur = 0, t_extrapolate = 0, t_diffuse = 0, t_composite = 0;
    std::string report() const;  // multi-line, for --stats
};

// Region maths (one place, shared by the pipeline, the CLI and the OFX
// RoI / RoD actions). A blur of CoC radius R is a Gaussian of sigma = R / 2;
// its spread is 3 sigma (+1 px for the discrete stencil):
//   defocus_margin(R) = ceil(1.5 R) + 1 for R > 0, 0 for R <= 0 (or NaN).
GDOF_API int defocus_margin(double max_radius_px);
// The input region needed to compute `output`: output grown by the margin of
// the largest blur radius. (Pixels of a layer outside it cannot reach the
// output by more than the Gaussian's 3-sigma tail.)
GDOF_API Roi defocus_input_region(const Roi& output, double max_radius_px);
// The output domain (RoD) of an input data window: the window grown by the
// margin, clipped to the frame (display window ∪ input data window). Empty
// in, empty out.
GDOF_API Roi defocus_output_region(const Roi& input_data_window, const Roi& display_window, double max_radius_px);

// Defocuses prepared layers (front = index 0). Output: float R, G, B, A
// (premultiplied) over settings.roi or the whole result. From a source, the
// whole result is made one layer at a time, back to front (each layer made,
// diffused, composited and dropped: one layer's pixels in memory at once); a
// sub-region makes every layer first (all their blurs set the region needed).
GDOF_API Result<Image> defocus_layers(const std::vector<Layer>& layers, const BlurField& field, const Camera& camera,
                                      const DefocusOptions& settings, DefocusStats* stats = nullptr, const Exec& exec = {});
GDOF_API Result<Image> defocus_layers(const LayerSource& layers, const BlurField& field, const Camera& camera,
                                      const DefocusOptions& settings, DefocusStats* stats = nullptr, const Exec& exec = {});

// The part of a defocus() input whose camera, display window and metadata
// the result takes: the first deep part, else the first part. Front ends
// resolve the camera from it.
GDOF_API std::size_t defocus_reference_part(const ImageSet& input);

// Defocuses a whole file's contents: a deep part -> layers_from_deep; several
// RGBA layers/parts with P or Z -> layers_from_parts; a single flat RGBA with
// depth -> layers_from_depth_map. The result is one flat part: R, G, B, A
// (with each colour channel's input type), the input's display window and
// metadata; other channels of a flat input (Z, P, N, ids) are carried over
// unchanged on the new data window (zero where the input had no data).
GDOF_API Result<ImageSet> defocus(const ImageSet& input, const BlurField& field, const Camera& camera,
                                  const DefocusOptions& settings, DefocusStats* stats = nullptr, const Exec& exec = {});

}  // namespace gdof
