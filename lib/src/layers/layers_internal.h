// Shared pieces of the layer builders (layers_*.cpp): choosing depth slices
// and small helpers. Not installed.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "image/frame_buffer.h"
#include "gdof/layers.h"

namespace gdof::layers_detail {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// Depth slices: slice k holds the depths d with bounds[k-1] <= d < bounds[k]
// (bounds ascending, one fewer than the slices). Depths <= 0 fall into slice
// 0 and +inf into the last slice.
struct DepthSlices {
    std::vector<double> bounds;
    // Nominal interval of each slice (Count: the equal 1/depth extents;
    // Auto: the clusters' sample ranges).
    std::vector<double> lo, hi;
    int count() const { return int(bounds.size()) + 1; }
    // The number of bounds <= depth (NaN: the last slice). Inline and, for
    // the usual few bounds, a branchless count: it runs for every pixel.
    int slice_of(double depth) const {
        if (std::isnan(depth)) return count() - 1;
        if (bounds.size() > 16) return int(std::upper_bound(bounds.begin(), bounds.end(), depth) - bounds.begin());
        int k = 0;
        for (double b : bounds) k += b <= depth ? 1 : 0;
        return k;
    }
};

// Auto clustering: gaps in log depth.
//  - Histogram of log(depth) over the positive finite depths, bins of
//    kAutoMinGap / 4; a gap is a run of bins holding at most
//    n * kAutoNoiseFraction samples (stray samples, antialiased depth edges)
//    that does not touch either end and is at least kAutoMinGap wide
//    (depth ratio e^0.05 ~ 5 %).
//  - At most max_layers - 1 gaps are kept (the widest; ties: nearest first).
constexpr double kAutoMinGap = 0.05;
constexpr double kAutoNoiseFraction = 2e-5;
// Auto blur cuts (LayerSplit::blur_step = 0): step = max(kAutoBlurStepPx,
// largest bin-mean radius / kAutoBlurLayers), times 1.25 until the layers fit.
// At silhouettes (plates) the largest radius is divided by
// kAutoBlurLayersAtSilhouettes: since a bound across a continuous surface
// is continued from the surface's own pixels (defocus_seams.cpp) a cut
// costs less, and the finer step measured better (docs/diffusion.md).
constexpr double kAutoBlurStepPx = 2.0;
constexpr double kAutoBlurLayers = 4.0;
constexpr double kAutoBlurLayersAtSilhouettes = 4.5;
// Cuts at silhouettes (SilhouetteGrid): a sharper front over a more blurred
// background needs a bound only when the background's radius exceeds the
// front's by kReverseNeed steps (a more blurred front: by one step).
constexpr double kReverseNeed = 3.0;

// Two finite depths on one surface: within `continuity` of each other.
inline bool same_surface(float a, float b, double continuity) {
    if (!std::isfinite(a) || !std::isfinite(b)) return false;
    return double(std::max(a, b)) <= double(std::min(a, b)) * continuity;
}

// A plate's pixels, for Auto's blur cuts at silhouettes (choose_slices).
// Where two 4-neighbours' depths differ by more than `continuity` and the
// nearer one's blur radius exceeds the farther's by more than the blur step
// (or the farther's the nearer's by kReverseNeed steps), a slice bound must
// lie between them: a blurred foreground then spreads over a sharper
// background instead of being insulated by it. A continuous surface needs no
// bound (diffusion varies its blur within a layer), and a bound through one
// hides, under the nearer strip, the blurred light of the farther one (a lamp
// just behind a bound on a ceiling loses the glow that falls on the nearer
// strip). So the bounds are as few as the silhouettes allow, each at the
// depth that puts the least light behind a nearer part of the picture within
// a blur radius.
struct SilhouetteGrid {
    int width = 0, height = 0;
    const float* depth = nullptr;  // row-major; finite or +inf (sky)
    const unsigned char* present = nullptr;
    const float* radius = nullptr;
    const float* rgb[3] = {nullptr, nullptr, nullptr};  // the light a bound may hide
    double continuity = 1.05;
    // Mixed pixels: the foreground's depth and radius in front of the
    // pixel's own (its background's).
    struct Front {
        float fg_depth, fg_radius, depth, radius;
    };
    std::vector<Front> fronts;
};

// Log-depth histogram (choose_slices) shared by the gap search and the blur cuts.
struct LogHistogram {
    double vmin = 0, binw = 1;
    long nbins = 0;
    std::vector<std::size_t> count;
    std::vector<double> rsum;         // sum of finite radii per bin
    std::vector<std::size_t> rcount;  // number of finite radii per bin
    long bin_of(double v) const { return std::clamp(long((v - vmin) / binw), 0L, nbins - 1); }
    double edge_depth(long b) const { return std::exp(vmin + double(b) * binw); }
};

// Blur cuts at a plate's silhouettes (SilhouetteGrid). A bound at histogram
// edge e (1..nbins-1: edge_depth(e); nbins: beyond every finite depth, before
// the sky) puts bins >= e in the farther slice.
struct CutNeed {
    long a = 0, f = 0;  // a bound at an edge e with a < e <= f separates the pair
    float dr = 0;       // the largest need (need_weight) of the pairs that have it
};
struct SilhouetteScan {
    // Per edge 0..nbins: the light (R + G + B) that a bound there puts behind
    // a nearer part of the picture within `reach` (whose glow the nearer
    // layer then hides: a lamp just behind a bound loses the half of its
    // glow that falls on the nearer side; just in front of it, none).
    std::vector<double> cost;
    std::vector<CutNeed> needs;  // sorted by (a, f), one per pair of bins
};

// The needs of a plate's silhouettes whose weight exceeds min_step, and
// the cost of a bound at each edge of `h` (light within `reach` px behind a
// nearer part of the picture). The same for any thread count.
SilhouetteScan scan_silhouettes(const LogHistogram& h, const SilhouetteGrid& grid, double min_step, double reach,
                                const Exec& exec = {});
// The bounds (depths, ascending) for the needs of `scan` above `step` that
// the `gaps` (depths) leave unseparated; zmax: the largest finite depth.
std::vector<double> silhouette_cuts(const LogHistogram& h, const SilhouetteScan& scan, const std::vector<double>& gaps,
                                    double step, double zmax);

// Slices for Auto / Count from the sample depths (NaN must be filtered out
// by the caller; +inf and <= 0 are allowed and ignored when choosing).
// `radius`: empty, or one blur radius per depth (Auto's blur cuts). With a
// `grid` (plates), Auto cuts by blur only at its silhouettes; without (deep
// samples, which have no neighbours), wherever the slice's blur span would
// exceed the step.
DepthSlices choose_slices(std::span<const float> depths, const LayerSplit& split, std::span<const float> radius = {},
                          const Exec& exec = {}, const SilhouetteGrid* grid = nullptr);

// The pixels of nearer slices (slice[j] < s, owner[j] == s) that continue
// slice s's surface (layers_from_depth_map): cont[j] = 1 for each, sized like
// depth; returns their bounding box (absolute coordinates, `win` the
// image's window).
Roi continue_surface(const std::vector<float>& depth, const std::vector<unsigned char>& present,
                     std::span<const int> slice, std::span<const int> owner, int s, int width, int height,
                     const Roi& win, double continuity, int reach, std::vector<unsigned char>& cont);

// Slice s's surface onward (surface_onward.cpp): the pixels of farther
// slices that continue its surface past its own pixels (`own`: their box),
// at most `reach` steps from them and nearer to where the surface goes on
// than to any silhouette of the slice. Coordinates from the plate window's
// origin; `box` bounds the onward pixels, `mask` (1: onward) covers it,
// row-major (both empty: none).
struct SurfaceOnwardInput {
    int width = 0, height = 0;
    std::span<const float> depth;             // per pixel; +inf sky
    std::span<const unsigned char> present;   // per pixel: has a sample
    std::span<const int> slice, fg_slice;     // per pixel; -1: none
    std::span<const int> mixed;               // per pixel, >= 0: a mixed pixel (empty: none)
    double continuity = 1.05;
};
struct SurfaceOnward {
    Roi box;
    std::vector<unsigned char> mask;
};
SurfaceOnward surface_onward(const SurfaceOnwardInput& in, int s, const Roi& own, int reach, const Exec& exec);
// Layer L's surface onward (L.onward, marked) written as uncovered pixels
// (blank colour) that carry the surface's depth and positions there:
// `depth` and `p` (null: no positions) row-major over `frame`.
void write_onward(Layer& L, const Roi& frame, const float* depth, const std::array<const float*, 3>& p);

// Which slice continues or extends behind each pixel: among the slices behind
// the pixel's nearest (the nearer of slice[i] and fg_slice[i]; slice -1: no
// sample), the one whose own pixels (where slice or fg_slice is k) are
// nearest, -1 where emptiness (no sample) is nearer or nothing is behind;
// and the distance to it (+inf where none).
// With a finite `bound` and no emptiness (a plate), distances beyond it are
// not computed (each slice's distances only over its box grown by the
// bound): a pixel no slice behind it reaches within the bound gets the
// farthest non-empty slice behind it and distance +inf. So the owners and
// distances are those of the unbounded call wherever the distance is within
// the bound, and the owner is >= 0 exactly where it is. At most 65534
// slices (as ExtensionPlan).
struct BackgroundOwners {
    FrameBuffer<int> owner;
    FrameBuffer<float> distance;
};
BackgroundOwners background_owners(std::span<const int> slice, std::span<const int> fg_slice, int nslices,
                                   int width, int height, const Exec& exec = {},
                                   double bound = std::numeric_limits<double>::infinity());

// A layer pixel's own coverage: alpha > 0 or any colour != 0.
inline bool covers(float r, float g, float b, float a) { return a > 0.0f || r != 0.0f || g != 0.0f || b != 0.0f; }

// What extending one layer needs to know of the others (extend_layer):
// where each pixel is hidden by the nearer layers' own coverage. Layers
// s >= hidden_from[i] are hidden at frame pixel i (ExtendOptions::
// occluder_alpha); the nearer layers' coverage only grows with s, so one
// index per pixel says it for every layer.
struct ExtensionPlan {
    static constexpr std::uint16_t kNeverHidden = 0xffff;
    Roi frame;
    int nearest = -1, farthest = -1;  // non-empty layers
    FrameBuffer<std::uint16_t> hidden_from;  // per frame pixel, row-major
};
// The plan of a list of layers (their own coverage, before any extension).
Result<ExtensionPlan> plan_extension(const std::vector<Layer>& front_to_back, const Roi& frame,
                                     const ExtendOptions& options, const Exec& exec);
// Layer s extended behind the nearer ones (extend_layers_behind, for one layer).
Status extend_layer(Layer& layer, int s, const ExtensionPlan& plan, const ExtendOptions& options, const Exec& exec);
// Past extend_px, layer s's extension goes on behind a nearer part of its
// own surface as far as surface_reach_px (surface_ring.cpp); called by
// extend_layer once the layer is extended.
Status extend_ring(Layer& layer, int s, const ExtensionPlan& plan, const ExtendOptions& options, const Exec& exec);
// Layer L's image over `box` (which holds its data window): its pixels
// copied, blank (blank_layer_value) beyond them.
void rewindow_layer(Layer& L, const Roi& box, const Exec& exec);
Status check_extendable(const Layer& layer);
Status check_extend_options(const ExtendOptions& options, const Roi& frame);

// Layer L's seams (Layer::seam, seam_box) once it is extended: its
// extension pixels (covered, not its own: own(i, x, y), i the frame index)
// that a nearer part of its own surface hides, where the frame's front
// surface (`depth`, and `present`, null: everywhere, row-major over
// `frame`) lies within `continuity` of the extension's depth. Rows in
// parallel, each with its own span; the union taken after, in row order.
template <class Own>
void mark_seams(Layer& L, const Roi& frame, const float* depth, const unsigned char* present, double continuity,
                const Own& own, const Exec& exec) {
    L.seam.clear();
    L.seam_box = Roi{};
    const Roi lw = L.image.data_window();
    const int zc = L.image.channel_index("Z");
    const Roi inside = intersect(lw, frame);  // the layer within the frame
    if (inside.empty() || zc < 0) return;
    std::vector<unsigned char> seam(lw.npixels(), 0);
    std::vector<Roi> row_box(std::size_t(lw.height()));
    parallel_for(exec, inside.height(), [&](long r0, long r1) {
        // Locals: a byte store may alias anything reached through a reference.
        const float* A = L.image.plane(3);
        const float* Z = L.image.plane(zc);
        unsigned char* out = seam.data();
        for (int y = inside.y0 + int(r0); y < inside.y0 + int(r1); ++y) {
            int xmin = inside.x1, xmax = inside.x0 - 1;
            const std::size_t orow = std::size_t(y - lw.y0) * std::size_t(lw.width());
            const std::size_t frow = std::size_t(y - frame.y0) * std::size_t(frame.width());
            for (int x = inside.x0; x < inside.x1; ++x) {
                const std::size_t o = orow + std::size_t(x - lw.x0), i = frow + std::size_t(x - frame.x0);
                if (!(A[o] > 0.0f) || own(i, x, y)) continue;
                if ((present && !present[i]) || !same_surface(depth[i], Z[o], continuity)) continue;
                out[o] = 1;
                xmin = std::min(xmin, x);
                xmax = x;
            }
            if (xmax >= xmin) row_box[std::size_t(y - lw.y0)] = Roi{xmin, y, xmax + 1, y + 1};
        }
    }, 16);
    for (const Roi& r : row_box)
        if (!r.empty()) L.seam_box = unite(L.seam_box, r);
    if (!L.seam_box.empty()) L.seam = std::move(seam);
}

// Every layer of a source, made in order (the list builders).
Result<std::vector<Layer>> make_all(const LayerSource& source, const Exec& exec);

// A layer's image over `box`: float R, G, B, A, Z (and P.x, P.y, P.z with
// positions), with the source's display window, metadata and view, named
// `name`. Left unset: its maker writes every pixel, in parallel (a frame-
// sized layer zeroed first is a serial pass over fresh memory), the pixels
// that hold nothing with blank_layer_value (blank_layer_pixel).
Image layer_image(bool with_positions, const Roi& box, const Roi& display, const Metadata& metadata,
                  const std::string& name, const std::string& view);
// What channel c of a layer pixel that holds nothing is: RGBA 0, Z and P NaN.
inline float blank_layer_value(int c) { return c < 4 ? 0.0f : kNaN; }
inline void blank_layer_pixel(Image& img, std::size_t offset) {
    for (int c = 0; c < img.nchannels(); ++c) img.plane(c)[offset] = blank_layer_value(c);
}
// The planes of a layer image (R, G, B, A, Z, P.x, P.y, P.z; null beyond its
// channels), for loops that keep them in locals: a store may alias anything
// of its type reached through a reference, so plane() would be looked up
// again per pixel.
template <class Img>
auto layer_planes(Img& img) {
    std::array<decltype(img.plane(0)), 8> p{};
    for (int c = 0; c < std::min(8, img.nchannels()); ++c) p[std::size_t(c)] = img.plane(c);
    return p;
}

// "depth 2.1-3.4"
std::string depth_range_name(double near, double far);

// Median of the finite values (sorted copy); NaN if none.
double median_finite(std::vector<float> values);

// Exact Euclidean distance transform: out[i] = distance from pixel i to the
// nearest pixel with mask != 0 (+inf if none). Row-major width x height.
// With a finite `bound`, distances above it are +inf (and cost less).
void distance_transform(std::span<const unsigned char> mask, int width, int height, FrameBuffer<float>& out,
                        const Exec& exec = {}, double bound = std::numeric_limits<double>::infinity());

}  // namespace gdof::layers_detail
