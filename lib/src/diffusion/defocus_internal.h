// Internal pieces of the defocus pipeline (defocus.h), shared by the
// defocus_*.cpp files only.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <vector>

#include "gdof/bokeh.h"
#include "gdof/defocus.h"
#include "image/frame_buffer.h"

namespace gdof::defocus_detail {

// What one layer holds, found once over the whole layer.
struct LayerAnalysis {
    RgbaIndices rgba;
    bool empty = true;         // no pixel with any of R, G, B, A != 0
    Roi content;               // bounding box of those pixels
    // Radii are known at pixels with A > 0 (weight min(A, 1)); a layer with
    // colour but no alpha anywhere (pure emission) takes them from its content
    // pixels where the field is finite.
    bool radius_from_alpha = true;
    double max_radius = 0.0;   // largest known radius (0: the layer is sharp)
    FrameBuffer<float> radius; // over the layer's data window (every pixel evaluated), valid where known
};

// Blur map of a layer at its pixels' world positions (P, else Z + camera) and
// the checks on it: non-finite radii at covered pixels and radii above
// settings.max_radius are errors naming the layer, the pixel and the value.
Result<LayerAnalysis> analyse_layer(const Layer& layer, int index, const BlurField& field, const Camera& camera,
                                    const DiffusionOptions& settings, const Exec& exec);

// "WHERE: channel 'R' is nan at pixel (x, y) (colour must be finite)".
Status non_finite_colour(const std::string& where, int channel, float value, int x, int y);
// The first non-finite R, G, B or A of an image in row order (channel order
// within a pixel) as non_finite_colour; absent channels (index < 0) skipped.
Status check_finite_colour(const Image& img, const RgbaIndices& rgba, const std::string& where, const Exec& exec);

// Weight of a layer pixel as a known radius for the extrapolation (0:
// unknown): min(A, 1) where A > 0; for a layer without alpha, 1 where it has
// colour and a finite radius. Made once per layer, inline per pixel.
struct KnownWeight {
    KnownWeight(const LayerAnalysis& a, const Layer& layer)
        : from_alpha(a.radius_from_alpha), r(layer.image.plane(a.rgba.r)), g(layer.image.plane(a.rgba.g)),
          b(layer.image.plane(a.rgba.b)), alpha(layer.image.plane(a.rgba.a)), radius(a.radius.data()) {}
    float operator()(std::size_t i) const {
        if (from_alpha) return alpha[i] > 0.0f ? std::min(alpha[i], 1.0f) : 0.0f;
        const bool content = r[i] != 0.0f || g[i] != 0.0f || b[i] != 0.0f;
        return content && std::isfinite(radius[i]) ? 1.0f : 0.0f;
    }
    bool from_alpha;
    const float *r, *g, *b, *alpha, *radius;
};

// Name used in messages: "layer 2 'depth 2.10-3.40'".
std::string layer_label(const Layer& layer, int index);

// A layer's premultiplied R, G, B, A diffused over its work region.
struct DiffusedLayer {
    Roi work;
    Image rgba;  // float R, G, B, A over `work`
};

// A layer's per-pixel radius map (row-major over its work region): frame-
// sized at 4K and always written whole, so it is not zeroed first.
using RadiusMap = FrameBuffer<float>;

// The solver settings used for a layer: the step count (ADI) or iteration
// count (explicit) follows the layer's largest radius over the *whole* layer,
// not over the (possibly cropped) radius map, so a sub-region render runs the
// same operator as the full render.
DiffusionOptions layer_solver_settings(const DiffusionOptions& base, double layer_max_radius,
                                        const RadiusMap& radius_map, const Exec& exec);

// The largest blur radius of layers in memory, as the pipeline's analysis
// measures it (LayerSource::largest_blur_radius: they are then served with
// it); 0 unless the filter is diffusion, whose pyramid alone uses it. Bad
// settings or a layer's bad blur give the pipeline's own errors.
Result<double> largest_layer_radius(const std::vector<Layer>& layers, const BlurField& field, const Camera& camera,
                                    const DefocusOptions& settings, const Exec& exec);

// What diffuse_pyramid ran, for the --stats counts.
struct PyramidSolve {
    bool on_pyramid = false;  // coarse levels were used
    DiffusionSolver solver = DiffusionSolver::Explicit;  // the solver that ran (on every level)
};

// Diffuses a layer's four row-major planes over their window with `radius`
// (same window): on the pyramid when settings.pyramid and the layer's
// largest radius (above 6 px) call for it, else at full resolution. Step
// counts follow the whole layer's largest radius (layer_solver_settings);
// the level count follows the larger of it and `frame_radius` (the largest
// radius of all the layers, 0 if not known), and the layer's whole region:
// every layer on the pyramid then blends the same levels for a given
// radius, and sub-regions run the same operator.
// Every pyramid level's radii are at most 6 px, so under `auto` each level
// runs explicit: the default path solves nothing implicitly.
Status diffuse_pyramid(const ImageView& planes, const RadiusMap& radius, double layer_max_radius,
                       double frame_radius, const Roi& layer_region, const DiffusionOptions& settings,
                       const Exec& exec, PyramidSolve& how);

// Extrapolates the layer's radii over `extrapolation` (push-pull beyond the
// known pixels; the whole render's work region, so a cropped render gets the
// very same radii: push-pull depends on its domain), crops them to `work`,
// copies the layer's RGBA into zero-padded planes over `work` and diffuses
// them, or spreads them with `bokeh` when it is given (the cat's eye grows
// towards the corners of `frame`). Times go to stats.t_extrapolate / t_diffuse.
// `frame_radius`: as for diffuse_pyramid.
Status diffuse_layer(const Layer& layer, int index, const LayerAnalysis& analysis, double frame_radius,
                     const Roi& work, const Roi& extrapolation, const DiffusionOptions& settings,
                     const BokehFilter* bokeh, const Roi& frame, const Exec& exec, DiffusedLayer& out,
                     DefocusStats& stats);

// The layer's radii over `work`: its known radii, extrapolated by push-pull
// over `extrapolation` (∪ work) beyond its coverage (for a plate's layer
// then radius_past_coverage), clamped to [0, largest].
RadiusMap extrapolated_radius(const Layer& layer, const LayerAnalysis& analysis, const Roi& extrapolation,
                              const Roi& work, const Exec& exec);

// Over `full` (the push-pull fill over `ext`), for a layer whose surface
// onward was marked (Layer::onward_marked; otherwise nothing): its surface
// onward takes its own radii, and past its silhouettes a pixel takes the
// largest radius among the layer's points whose circle reaches it, where
// one does (radius_past_coverage.cpp).
void radius_past_coverage(const Layer& layer, const LayerAnalysis& analysis, const Roi& ext, RadiusMap& full,
                          const Exec& exec);

// Method 4 for defocus_layers: every layer made and analysed, its radii
// extrapolated over the frame, then vibrate_layers (psf_field.h) over the
// frame, cropped to settings.roi when one is given.
Result<Image> defocus_vibrate(const LayerSource& source, const BlurField& field, const Camera& camera,
                              const DefocusOptions& settings, DefocusStats& stats, const Exec& exec);

// Margin of a layer's work region around its content. The bokeh filter
// takes 2R + 2 (more than the aperture's reach R + 1) so that the spread
// weight it normalises by is complete wherever the layer's light lands.
int work_margin(const DefocusOptions& settings, double max_radius_px);
// The same for a layer spread with the bokeh filter or diffused.
int spread_margin(bool bokeh, double max_radius_px);

// Spreads four planes over their window with radii over the same window,
// as a layer's own diffusion or bokeh spread did (continue_across_seams).
using SpreadSeams = std::function<Status(const ImageView& planes, const RadiusMap& radius, const Exec& exec)>;

// A layer's colour behind a nearer part of its own surface, after `out`
// was spread (defocus_seams.cpp): where the layer has seam pixels
// (Layer::seam), they are spread alone over their box grown by `margin`
// (within `work`; pieces of seam more than 2 `margin` apart each over its
// own) and the layer's colour there becomes its other pixels' normalised
// spread, so the two parts of a surface cut by a slice bound add up to the
// surface blurred whole.
Status continue_across_seams(const Layer& layer, const RadiusMap& radius, const Roi& work, int margin,
                             const SpreadSeams& spread, DiffusedLayer& out, const Exec& exec);

// dst (float R, G, B, A at channels 0..3) = src over dst, where src is four
// row-major planes over src_window (row stride = its width). A destination
// pixel that is still all zero receives src bit for bit.
Status composite_over(Image& dst, const std::array<const float*, 4>& src, const Roi& src_window, const Exec& exec);

}  // namespace gdof::defocus_detail
