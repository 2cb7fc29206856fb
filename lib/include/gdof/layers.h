// Depth layers for method 3 (heat diffusion): every input users have becomes
// a list of layers, front (index 0) to back, each a flat image of
// premultiplied colour, coverage and depth that can be diffused on its own
// and composited back with `over`.
#pragma once

#include <memory>
#include <span>
#include <string>
#include <vector>

#include "gdof/blur_map.h"
#include "gdof/camera.h"
#include "gdof/deep.h"
#include "gdof/exec.h"
#include "gdof/export.h"
#include "gdof/image.h"
#include "gdof/image_set.h"
#include "gdof/plate.h"
#include "gdof/status.h"

namespace gdof {

// One layer. `image` has float channels R, G, B, A (premultiplied) and Z
// (metric depth along the view axis, already decoded: evaluate it with a
// default PositionSource), and P.x, P.y, P.z when the source had world
// positions. Its data window is the bounding box of the layer's pixels (it
// may be smaller than the input's, and is empty for an empty layer); its
// display window and metadata are the input's. Where the layer has no
// coverage, R = G = B = A = 0 and Z (and P) are NaN, unless the layer was
// extended (see layers_from_depth_map). Covered pixels may have Z = +inf
// (sky, or invalid depth in a depth map): blur fields must accept it.
struct Layer {
    Image image;
    std::string name;          // "depth 2.10-3.40", "id 12", a part or layer name
    double depth_near = 0.0;   // smallest covered depth (NaN for an empty layer)
    double depth_far = 0.0;    // largest covered depth (+inf if it holds invalid / sky depths)
    // The depth interval the split gave this layer: Count: the equal 1/depth
    // extent; Auto: the cluster's range; id and part layers: the covered range.
    double slice_near = 0.0;
    double slice_far = 0.0;
    // Plates: the extension pixels that continue this layer's own surface
    // behind a nearer slice of it (a bound across a floor or a wall: the
    // pixel's own depth in the plate within `continuity` of the extension's),
    // 1 per pixel of image's data window, all inside seam_box; empty: none.
    // The defocus continues the surface there from the layer's own pixels
    // (docs/diffusion.md, "A bound across a surface"), not from the fill.
    std::vector<unsigned char> seam;
    Roi seam_box;
    // Plates (SliceOptions::mark_onward): the pixels past this layer's
    // coverage where its surface goes on in a farther slice (a bound across
    // a ceiling: the far part's pixels beside the near part, up to
    // `extend_px` away, nearer to it than to any silhouette of the layer).
    // They stay uncovered (R = G = B = A = 0) but hold the plate's Z (and
    // P), and the diffusion blurs the layer there with their own radii, so
    // its edge spreads over the far part as the whole surface would
    // (docs/diffusion.md, "Past a plate layer's coverage"). 1 per pixel of
    // onward_box (row-major; inside image's data window); empty: none.
    std::vector<unsigned char> onward;
    Roi onward_box;
    // The surface onward was looked for (even if none was found): then
    // every other uncovered pixel lies past a silhouette, where the
    // diffusion spreads the layer as a lens spreads a blurred object: with
    // the largest radius among its points whose circle reaches there.
    bool onward_marked = false;
};

// Layers made one at a time, front (index 0) to back: what defocus streams
// back to front, so that only one layer's pixels are in memory at once.
// make(i) gives the same pixels as element i of the list the corresponding
// builder below returns (layers_from_depth_map, layers_from_deep with
// extend_layers_behind); the source keeps references to its input, which
// must outlive it.
class GDOF_API LayerSource {
public:
    virtual ~LayerSource() = default;
    virtual int size() const = 0;
    // The union of the layers' data windows (known before any is made), and
    // the display window they carry.
    virtual Roi frame() const = 0;
    virtual Roi display_window() const = 0;
    // Layer i, in `storage` or held by the source itself: the pointer is
    // valid until the next call and while the source lives.
    virtual Result<const Layer*> make(int index, Layer& storage, const Exec& exec = {}) const = 0;
    // The largest blur radius (px) of all the layers' pixels, when it was
    // known before any layer is made (defocus() on a plate or a deep image
    // computes every pixel's or sample's radius first); 0: not known. It
    // sets how many pyramid levels each layer's diffusion has, so that a
    // pixel's blur is the same whichever layer holds it.
    virtual double largest_blur_radius() const { return 0.0; }
};
// A source over layers already made (front to back): borrowed (they must
// outlive the source) or taken over. frame(): the union of their data
// windows; display_window(): the union of their display windows.
GDOF_API std::unique_ptr<LayerSource> source_of(const std::vector<Layer>& front_to_back);
GDOF_API std::unique_ptr<LayerSource> source_of(std::vector<Layer>&& front_to_back);
// `source` (taken over) with its layers' largest blur radius made known
// (LayerSource::largest_blur_radius).
GDOF_API std::unique_ptr<LayerSource> with_largest_blur_radius(std::unique_ptr<LayerSource> source, double radius);

struct LayerSplit {
    enum class Mode {
        // Split where the sample depths have gaps (clusters), at most
        // max_layers: a histogram of log(depth) (bins of 0.0125); a gap is a
        // run of bins holding at most 2e-5 of the samples (strays, mixed edge
        // depths), not touching either end, at least 0.05 wide in log depth
        // (a 5 % depth ratio); the widest max_layers - 1 gaps are kept, each
        // split at its middle. Then, when the caller gives each sample's
        // blur radius (defocus does), layers are also cut by blur, so that a
        // blurred object in front of a sharper part of the same continuous
        // depth range (a ground plane) spreads over it:
        //  - by blur span (deep samples by default, plates with
        //    SliceOptions::cut_at_silhouettes off): walking the histogram
        //    bins front to back, a new layer starts when the bins' mean
        //    radii since the last cut span more than blur_step px;
        //  - at silhouettes (plates, and deep images sliced by their front
        //    surface: what defocus does for diffusion, a deep pixel's
        //    surface being the sample at which its coverage reaches one
        //    half; layers_from_deep): only where a pixel's neighbour is farther by more
        //    than `continuity` and the nearer one's radius exceeds the
        //    farther's by more than blur_step px (or the farther's the
        //    nearer's by 3 steps). The
        //    fewest bounds that separate every such pair, each at the depth
        //    that puts the least light behind a nearer part of the picture
        //    within a blur radius (a continuous surface is cut only where a
        //    silhouette needs it, and not just in front of a highlight).
        // Without radii, continuous depths give one layer. See
        // docs/diffusion.md for the measurements.
        Auto,
        // `count` layers of equal extent in 1/depth between the smallest and
        // largest positive finite depth (+inf counts as 1/depth = 0): even in
        // defocus for a thin lens. Empty slices are kept (empty windows).
        Count,
        // One layer per value of the uint channel `id_channel` (deep inputs),
        // ordered by the median depth of its samples; named "<channel> <id>".
        ById,
    };
    Mode mode = Mode::Auto;
    int count = 8;
    int max_layers = 32;
    // Auto: whether defocus cuts by blur. Default: yes, for deep inputs and
    // depth maps alike (for diffusion at silhouettes, for bokeh and vibrate
    // by span); Off: gaps only.
    enum class BlurCuts { Default, On, Off };
    BlurCuts blur_cuts = BlurCuts::Default;
    // Auto: the blur step, px: by span, the most a layer's (per-bin mean)
    // radius may vary; at silhouettes, the radius difference across a
    // silhouette that needs a bound. 0 = automatic: max(2 px, largest
    // radius / 4), at silhouettes largest radius / 4.5; raised until the
    // layers fit in max_layers.
    double blur_step = 0.0;
    std::string id_channel = "id";
};
// Parses "auto" with optional ':'-separated options (MAX = max_layers,
// "blur" = cut by blur, "blur=STEP" = cut by blur with that step in px,
// "gaps" = no blur cuts; e.g. "auto:8:blur=3"), "N" (count, 1..1024), "id" /
// "id:CHANNEL"; errors name the value.
GDOF_API Result<LayerSplit> parse_layer_split(const std::string& text);

// Deep image -> layers: samples grouped by depth (or id); within a layer a
// pixel's samples are sorted by Z (stored order may be anything; ties keep
// file order) and composited front to back with `over`; Z of a layer pixel
// is the mean depth of its samples weighted by their contributions
// (alpha * transmittance; the nearest sample's if none contributes). P, when
// the deep image has positions, is averaged the same way.
// Needs R, G, B and Z (no A: opaque samples). ZBack is ignored (a sample
// counts at Z). Z NaN or -inf, or a non-finite A, is an error naming the
// pixel and sample; Z = +inf goes to the farthest layer, Z <= 0 to the
// nearest. For depth splits, compositing all layers with composite_layers
// equals flatten_deep up to float rounding (the layers partition the sorted
// samples); for ById only when ids do not interleave in depth.
// `sample_radius` (optional, like SliceOptions::radius: empty, or one blur
// radius per deep sample in sample order) drives Auto's blur cuts: by blur
// span, or with `by_front_surface` only at the silhouettes of the image's
// front surface (per pixel, the sample at which the coverage reaches one
// half), as a plate's for diffusion. `by_front_surface` (what defocus does
// for diffusion; depth splits) also marks each layer's surface onward and
// seams from the front surface (Layer::onward, Layer::seam), as a plate
// layer's.
GDOF_API Result<std::vector<Layer>> layers_from_deep(const DeepImage& deep, const LayerSplit& split,
                                                     std::span<const float> sample_radius = {}, const Exec& exec = {},
                                                     bool by_front_surface = false);

// Multilayer / multipart EXR -> layers: every flat part, and every layer
// prefix inside a part ("fg.R", "fg.A", "fg.P.x" or "fg.Z" ...), that has
// R, G, B, A and a position pass or depth becomes a layer, ordered front to
// back by the median depth of its covered pixels (stable; no finite depth:
// last). Positions are found as blur_map.h describes, under the prefix;
// depth: "<prefix>.Z", ".depth.Z", ".Depth.Z", ".depth", ".Depth" or
// source.depth_channel under the prefix, decoded with source.depth_decode.
// A part's unprefixed layer may lack A (opaque). With positions but no
// depth, Z is the depth in the part's camera (worldToCamera / worldToNDC),
// or P.z without camera attributes (camera at the origin looking down +z).
// Covered: A > 0 or any colour != 0; colour is taken as premultiplied.
// Deep parts become layers through layers_from_deep (Auto split). Names:
// part name, "part.prefix", or the prefix for unnamed parts. No layer at
// all is an error that says what was looked for.
GDOF_API Result<std::vector<Layer>> layers_from_parts(const ImageSet& set, const PositionSource& source, const Exec& exec = {});

// Flat RGBA + depth (live action) -> depth slices (split Auto or Count; ById
// is an error). Each present pixel (A > 0 or colour != 0; no A channel:
// opaque) goes to the slice of its depth, with its colour and alpha. The
// depth is `options.depth` (a plate's prepared depth, plate.h: holes filled,
// mixed silhouette pixels at the nearer depth, lost ones split), or else the depth channel
// (source.depth_channel or Z, depth.Z, Depth.Z, depth, Depth) decoded with
// source.depth_decode, where a depth that is not finite (a hole, sky) is
// +inf. A mixed pixel goes to its background's slice with the background's
// colour, and to its foreground's slice with the foreground's colour and
// share of its alpha (so `over` gives the pixel back exactly). A pixel at a
// silhouette (a neighbour farther by more than `continuity`) that continues
// the surface of a 4-neighbour in a nearer slice (its anti-aliased edge, a
// little deeper) goes to that slice: alone in its own, it would be the
// nearest background to the pixels the surface hides, and continue it there
// with the surface's colour. Position channels are carried (without a
// prepared depth).
//
// Continued surfaces (continue_surfaces, off by default): every slice also holds, with their own colour, alpha and depth,
// the pixels of nearer slices that continue its own surface: reached from
// its own pixels through neighbours whose depths lie within
// `continuity` of each other, up to `extend_px` pixels away. When a nearer
// slice's edge is blurred away, the very surface shows through, not a fill;
// a silhouette (a depth step larger than `continuity`) stops the
// continuation, so a foreground never shows behind itself. Off by default:
// a copy of the nearer slice's content blurs out of the cut a second time
// where that content is bright (a lamp on a ceiling cut by blur: +7% energy
// around it on the benchmark's Cornell box, relative L1 away from edges
// 0.085 against 0.059 for the extension alone). The extension below,
// from the slice's own pixels, is what the layered sum needs behind a cut.
//
// What lies behind a hidden pixel is the background seen nearest to it:
// among the slices behind the pixel's own, only the one whose own pixels are
// nearest (Euclidean) continues or extends there, and none where emptiness
// (pixels without any sample) is nearer still. So the back of a wall's near
// strip is its next strip where they meet, but nothing where the strip meets
// a transparent sky (a copy of the strip's silhouette would otherwise blur
// out over the sky a second time).
//
// Extension: for every slice but the nearest non-empty one, its hidden
// pixels (present in nearer slices) within `extend_px` pixels (Euclidean)
// of the slice's own pixels -- for the farthest non-empty slice all hidden
// pixels of the image -- that are not continued get alpha 1 and a push-pull
// fill (fill.h) of the slice's unpremultiplied colour (weights = its alpha)
// and of its depth and positions (weights = its alpha where finite), fed by
// the rim of its coverage (own pixels within 4 px of pixels it does not
// cover: the fill continues the slice's edge, not a highlight deeper
// inside), so blurring a foreground away reveals plausible background, not
// black. The extension pixels behind a nearer part of the slice's own
// surface (the plate's depth there within `continuity` of the fill's) are
// marked in Layer::seam: there the defocus continues the surface from the
// slice's own pixels instead of the fill. Behind a nearer part of its own
// surface the extension goes on to surface_reach_px (its edge continued
// ring by ring), where a near part's blurred edge still lets it show.
struct SliceOptions {
    LayerSplit split;
    PositionSource source;   // depth channel and its encoding (when `depth` is null)
    double extend_px = 0.0;  // typically the largest blur radius of the image
    // Behind a nearer part of its own surface a slice reaches this far
    // (ExtendOptions::surface_reach_px; 0: extend_px), the plate's depth
    // there being the surface seen.
    double surface_reach_px = 0.0;
    // Optional: the blur radius of every pixel (row-major over the image's
    // data window), for Auto's blur cuts; empty: gaps only. With a prepared
    // depth that has mixed pixels, `fg_radius` gives their foregrounds'
    // radii (one per entry of depth->mixed). Not owned.
    std::span<const float> radius, fg_radius;
    // The plate's prepared depth over the image's data window; not owned.
    const PlateDepth* depth = nullptr;
    bool continue_surfaces = false;
    double continuity = 1.05;  // neighbouring depth ratio within which a surface continues
    // Auto's blur cuts (with `radius`): only at the silhouettes that need a
    // bound (true: diffusion, which varies the blur within a layer and whose
    // sharp pixels insulate), or wherever a slice's blur span would exceed
    // the step, as for deep samples (false: the bokeh and PSF-field filters,
    // whose spread is normalised within a layer and so mixes a layer's
    // blurs).
    bool cut_at_silhouettes = true;
    // Mark each layer's surface onward (Layer::onward): for diffusion, whose
    // radii vary within a layer; the bokeh and vibrate filters do not read
    // it.
    bool mark_onward = false;
};
GDOF_API Result<std::vector<Layer>> layers_from_depth_map(const Image& rgba_depth, const SliceOptions& options,
                                                          const Exec& exec = {});

// Extends layers behind the nearer layers that hide them: every layer but
// the nearest gets, at its hidden pixels within `extend_px` of its own
// coverage, a push-pull fill of its unpremultiplied colour, depth and
// positions from the rim of that coverage (its pixels within 4 px of pixels
// it does not cover), with alpha 1 (or its continued coverage, continue_coverage);
// so blurring a nearer layer away reveals a plausible continuation instead
// of black or a hole.
struct ExtendOptions {
    double extend_px = 0.0;
    // The farthest non-empty layer fills every hidden pixel of the frame
    // (live-action plates: the background is everywhere).
    bool farthest_fills_frame = false;
    // A pixel is hidden when the nearer layers' accumulated alpha reaches
    // this (deep renders: 0.999, fully occluded); 0 = any nearer coverage.
    float occluder_alpha = 0.0f;
    // Optional, per frame pixel (row-major over `frame`): the one layer that
    // may extend there (-1: emptiness is nearer, none may; the farthest
    // still fills where another owner's reach ends).
    // Empty: every layer may. Not owned.
    std::span<const int> owner;
    // The extension's alpha continues the layer's coverage instead of being
    // 1: its own pixels count with their alpha, the pixels where it is seen
    // to be empty (not hidden, no coverage: in a deep render the ray passed
    // the layer's depths without a hit) with 0. So a small isolated object
    // (a highlight) does not grow an opaque patch behind an occluder that
    // the occluder's blurred edge would reveal. Deep inputs and plates; with
    // farthest_fills_frame the farthest layer's backing fades likewise.
    bool continue_coverage = false;
    // With continue_coverage: only the pixels where no layer has a sample (a
    // render's transparent background) count as seen empty (plates). Where a
    // farther layer is seen, a plate's extension stays opaque: an opaque
    // plate's layers are extended as without continue_coverage (the layer's
    // presence continues, 1 on its own pixels, not their alpha).
    bool coverage_fades_at_emptiness_only = false;
    // Optional, with `owner`: per frame pixel, the distance to the owner's own
    // coverage (what the owners were chosen by), so that a layer's reach
    // needs no distance transform of its own. Not owned.
    std::span<const float> owner_distance;
    // The fill is fed only by the layer's edge that faces the pixels it
    // fills (plates): an edge that meets a farther layer or emptiness feeds
    // nothing. Off: every edge of the layer's coverage feeds it (deep
    // inputs, where that measured better on some frames of a focus pull and
    // worse on others).
    bool fill_from_hidden_edge = false;
    // Colours above a knee k enter the fill as k (1 + log(v / k)) and come
    // back out as k exp(v / k - 1); at or below k they are unchanged (the
    // map is smooth at k). A highlight on the rim (a lamp at 17 beside a
    // ceiling at 0.01) then no longer rules every average it enters, so it
    // does not glow sideways into the hidden part.
    //   One: k = 1 (deep inputs, whose every edge feeds the fill).
    //   RimMedian: k = 8 times the median of the layer's rim colours
    //     (the mean of R, G, B; black ones left out), at most 1 (plates).
    //     Fed by the facing edge only, a plate's fill met a highlight where
    //     a slice bound crosses a light on a receding surface; a ceiling at
    //     0.002 lies far below 1, so a knee at 1 barely helps there.
    enum class HighlightKnee { None, One, RimMedian };
    HighlightKnee fill_highlight_knee = HighlightKnee::None;
    // Behind a nearer part of its own surface (a slice bound across a wall,
    // where the depth seen, `front_depth`, lies within `continuity` of the
    // extension's filled depth), a layer reaches this far instead of
    // extend_px (0: no farther). A near part blurred by R lets its far part
    // show up to the kernel's reach (defocus_margin(R), about 1.5 R); the far
    // part extended by R alone leaves the two parts' coverages summing below
    // one a few pixels inside the near part: a dark band along the bound.
    // That ring (past extend_px) is continued from the extension's edge, a
    // ring of pixels at a time (the mean of the neighbours of that surface),
    // so the extension within extend_px is unchanged. Not for a layer that
    // fills the frame.
    double surface_reach_px = 0.0;
    // Per frame pixel (row-major over `frame`), with surface_reach_px: the
    // depth seen there (NaN, 0 or inf: nothing). Deep inputs set their own
    // front surface's. Not owned.
    std::span<const float> front_depth;
    double continuity = 1.05;
};
GDOF_API Status extend_layers_behind(std::vector<Layer>& front_to_back, const Roi& frame, const ExtendOptions& options,
                                     const Exec& exec = {});

// The sources behind the builders (LayerSource): the preparation that
// concerns every layer (depth slices, which sample or pixel goes where,
// owners, where each pixel is hidden) is done here, each layer's pixels
// and extension in make(). layers_from_depth_map(img, o) makes every layer
// of depth_map_layer_source(img, o); layers_from_deep followed by
// extend_layers_behind(layers, deep.data_window(), *extend) every layer of
// deep_layer_source(deep, split, radius, extend, exec, by_front_surface)
// (extend null: none).
GDOF_API Result<std::unique_ptr<LayerSource>> depth_map_layer_source(const Image& rgba_depth, const SliceOptions& options,
                                                            const Exec& exec = {});
GDOF_API Result<std::unique_ptr<LayerSource>> deep_layer_source(const DeepImage& deep, const LayerSplit& split,
                                                       std::span<const float> sample_radius,
                                                       const ExtendOptions* extend, const Exec& exec = {},
                                                       bool by_front_surface = false);

// Deep image flattened front to back with `over` (premultiplied): R, G, B, A
// (float) and Z = depth of the nearest sample (NaN where there is none), over
// the deep data window (display window, metadata, name and view kept).
// Samples are sorted by Z first; same sample rules and errors as
// layers_from_deep. RGBA equals OIIO's ImageBufAlgo::flatten on sorted
// files (OIIO's Z is an alpha-composited depth instead, 1e30 where empty).
GDOF_API Result<Image> flatten_deep(const DeepImage& deep, const Exec& exec = {});

// Composites layers (front = index 0) back to front with `over` into an
// image of float R, G, B, A over `window` (absolute pixels; display window:
// the first layer's, else `window`); layers may have any data windows,
// inside or outside it. Null entries are skipped; a layer without A is
// opaque. Parallel over rows; the only error is cancellation.
GDOF_API Result<Image> composite_layers(const std::vector<const Image*>& front_to_back, const Roi& window, const Exec& exec = {});

}  // namespace gdof
