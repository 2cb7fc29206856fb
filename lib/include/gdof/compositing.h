// Method 2 (Kosloff & Barsky, section 3): each output pixel is pulled from
// the reference of a focus/aperture stack whose depth of field [near, far]
// best matches the desired one at that pixel (focus_surfaces.h), by the
// paper's deviation
//     |near_desired - near_ref| + |far_desired - far_ref|.
// docs/compositing.md has the rules, the soft mode and the AOVs.
//
// composite() runs the whole method (the CLI's --composite and the OFX Focal
// Stack effect call it): desired focus from its source, then three steps, so
// that a reference no pixel selects is never read:
//   1. StackIndex::build: the references' (near, far) pairs indexed once.
//   2. select_references: the choice for every pixel, and which references
//      are needed at all (no pixel is read).
//   3. composite_stack: tile by tile, each tile reads only the references its
//      pixels chose, through a StackPixels source (files through an image
//      cache in gdof::io::StackReader, images in memory, or views of host
//      memory).
//
// Infinite depths: a term is 0 when both sides are equal (also both +inf) and
// infinite when exactly one side is infinite. Deviations compare first by how
// many infinite terms they have, then by the sum of the finite terms; so a
// desired far of +inf prefers references whose far is +inf, and among the
// others the near term decides. Ties go to the lower manifest index.
// Output is independent of the thread count and of the tile size.
#pragma once

#include <atomic>
#include <cstdint>
#include <limits>
#include <memory>
#include <variant>
#include <vector>

#include "gdof/blur_field.h"
#include "gdof/exec.h"
#include "gdof/export.h"
#include "gdof/focal_stack.h"
#include "gdof/focus_surfaces.h"
#include "gdof/image.h"
#include "gdof/status.h"

namespace gdof {

struct Deviation {
    int infinite_terms = 0;  // 0, 1 or 2
    double value = 0;        // sum of the finite terms
    bool operator<(const Deviation& o) const {
        return infinite_terms != o.infinite_terms ? infinite_terms < o.infinite_terms : value < o.value;
    }
    bool operator==(const Deviation&) const = default;
    // As one number: value, or +inf when a term is infinite.
    double as_double() const { return infinite_terms ? std::numeric_limits<double>::infinity() : value; }
};
// The paper's deviation between a desired and a reference interval (NaN in
// the desired interval: 2 infinite terms, never chosen over a real match).
GDOF_API Deviation stack_deviation(double near_desired, double far_desired, double near_ref, double far_ref);

// The references' (near, far) pairs, indexed once: sorted by near in two
// groups (finite far, infinite far); a query walks outward from the desired
// near and stops when |near_desired - near_ref| alone exceeds the k-th best
// deviation found, so it usually looks at a handful of references whatever
// the stack size. Exact: equal to a brute-force search, ties included.
class GDOF_API StackIndex {
public:
    StackIndex() = default;
    // refs[i] = (near, far) of reference i; near finite and >= 0, far >= near (may be +inf).
    static Result<StackIndex> build(const std::vector<DepthInterval>& refs);

    int size() const { return n_; }
    // The best k references for a desired interval, best first (deviation,
    // then lower index): writes up to k entries and returns how many (0 for a
    // NaN desired interval or an empty index).
    int nearest(double near_desired, double far_desired, int k, int* index, Deviation* deviation) const;

private:
    struct Entry {
        double near, far;
        int index;
    };
    std::vector<Entry> finite_far_, infinite_far_;
    std::vector<DepthInterval> refs_;
    int n_ = 0;
};

struct CompositeOptions {
    // 1: the paper's hard pick (default). K in 2..16: soft mode, blending the best K
    // references with modified Shepard weights w_i = ((R - d_i) / (R d_i))^2,
    // R = deviation of the (K+1)-th best (w_i = 1 / d_i^2 when there is none),
    // so weights fade to 0 as a reference leaves the best K (no seams); a
    // reference with deviation 0 is taken alone; only references with as
    // many infinite terms as the best one take part. K = 1 is exactly the hard pick.
    int soft_k = 1;
    // Add the AOVs "stack.index" (float: manifest index of the best
    // reference, -1 where nothing was selected) and "stack.deviation" (float:
    // its deviation, +inf if a term is infinite).
    bool aovs = false;
    int tile_size = 64;  // square tiles of the output (pixels)
};

// The choice of every pixel of a window (local coordinates [0, w) x [0, h)).
struct GDOF_API StackSelection {
    Roi window;
    int k = 1;                       // candidates stored per pixel
    std::vector<std::int32_t> index; // npixels * k, best first; -1 = none
    std::vector<float> weight;       // npixels * k (soft mode only; empty for the hard pick)
    std::vector<float> deviation;    // npixels: the best deviation (as_double)
    std::vector<char> used;          // per reference: some pixel needs it
    int references_used() const;
    std::vector<int> used_references() const;  // manifest indices, ascending
};

// Step 2: no pixel data is touched.
GDOF_API Result<StackSelection> select_references(const StackIndex& index, const DesiredFocus& desired,
                                                  const CompositeOptions& settings = {}, const Exec& exec = {});

// What a reference is: its pixel grid (the stack's local pixel (x, y) is
// (data_window.x0 + x, data_window.y0 + y)) and header.
struct ReferenceInfo {
    Roi data_window, display_window;
    Metadata metadata;  // header attributes (camera, lens, ...)
};

// Where reference pixels come from. read_tile is called concurrently from
// several threads (for different tiles) and must be thread-safe; info and
// prepare are called from the caller's thread only.
class GDOF_API StackPixels {
public:
    virtual ~StackPixels() = default;
    virtual int size() const = 0;  // number of references
    // Describes reference `ref` (a file source may open it to know).
    virtual Result<ReferenceInfo> info(int ref) = 0;
    // Called once before the first read_tile of a composite (step 3): the
    // references that will be read (ascending) and the part of the stack
    // (local coordinates) that the tiles cover. A source that must fetch its
    // pixels on the caller's thread (an OFX host's images) does it here.
    virtual Status prepare(const std::vector<int>& refs, const Roi& region) {
        (void)refs, (void)region;
        return Status::ok();
    }
    // R, G, B, A (premultiplied, scene-linear) of reference `ref` over `tile`
    // (local coordinates, inside the stack's window), interleaved, row-major,
    // tile.npixels() * 4 floats. A missing alpha reads 1, missing colour 0.
    virtual Status read_tile(int ref, const Roi& tile, float* rgba) = 0;
};

// References held in memory (tests). All images must have the same data
// window size; pixel (x, y) of the stack is pixel (x0 + x, y0 + y) of each
// image's data window. Counts reads per reference.
class GDOF_API MemoryStackPixels : public StackPixels {
public:
    explicit MemoryStackPixels(std::vector<const Image*> images);
    int size() const override { return int(images_.size()); }
    Result<ReferenceInfo> info(int ref) override;
    Status read_tile(int ref, const Roi& tile, float* rgba) override;
    long reads(int ref) const;  // read_tile calls for that reference

private:
    std::vector<const Image*> images_;
    std::vector<std::atomic<long>> reads_;
};

// References as views of memory someone else owns (an OFX host's images: no
// copy). Each view has 3 (R, G, B: alpha 1) or 4 (R, G, B, A) channels,
// premultiplied, in absolute coordinates; pixel (x, y) of the stack is
// (grid.x0 + x, grid.y0 + y), and where a view has no pixel every channel
// (alpha too) reads 0. info() is the grid for every reference.
class GDOF_API ViewStackPixels : public StackPixels {
public:
    ViewStackPixels(std::vector<ConstImageView> views, const Roi& grid);
    int size() const override { return int(views_.size()); }
    Result<ReferenceInfo> info(int ref) override;
    Status read_tile(int ref, const Roi& tile, float* rgba) override;
    // Replaces a reference's view (before reading: from prepare()).
    void set_view(int ref, const ConstImageView& view) { views_[std::size_t(ref)] = view; }

private:
    std::vector<ConstImageView> views_;
    Roi grid_;
};

struct CompositeStats {
    int references = 0, references_used = 0;
    std::vector<int> used_references;  // manifest indices, ascending (composite() only)
    long tiles = 0;       // tiles of the output
    long tile_reads = 0;  // read_tile calls (reference tiles read)
    double desired_seconds = 0, select_seconds = 0, composite_seconds = 0;
};

// Step 3: an image with float channels R, G, B, A (+ the AOVs) over the
// selection's window moved to `origin` (the references' data window origin).
// Display window = data window (callers set the references' one).
GDOF_API Result<Image> composite_stack(const StackSelection& selection, StackPixels& pixels, const CompositeOptions& settings = {},
                                       int origin_x = 0, int origin_y = 0, CompositeStats* stats = nullptr,
                                       const Exec& exec = {});

// ---- The whole method ----

// Desired near/far from images (desired_from_maps): channel near_channel of
// *near and far_channel of *far.
struct FocusMaps {
    const Image* near = nullptr;
    int near_channel = 0;
    const Image* far = nullptr;
    int far_channel = 0;
};
// Desired near/far along the rays of a depth / position image through a blur
// field (desired_from_blur_field). options.coc_px is normally the stack's.
struct FocusFromBlurField {
    const BlurField* field = nullptr;
    const Camera* camera = nullptr;
    const Image* depth_image = nullptr;
    BlurFocusOptions options;
};
// Where the desired near/far come from (focus_surfaces.h). Surfaces are
// evaluated over the stack's size: the manifest's width x height, else the
// size of reference 0 (pixels.info(0)).
using FocusSource = std::variant<FocusSurfaces, FocusMaps, FocusFromBlurField>;

// composite() writing a region into memory the caller owns (an OFX host's
// output image).
struct CompositeTarget {
    // Channels R, G, B[, A[, stack.index, stack.deviation]] (3, 4, or 6 with
    // the AOVs); `view.window` is the region, in absolute pixels at the render
    // scale. Every pixel of it is written (0 where the stack has none).
    ImageView view;
    // A proxy render: pixel (x, y) at scale s is the mean of the full
    // resolution result over [x / s, (x + 1) / s) x [y / s, (y + 1) / s) (the
    // references and the desired focus stay at full resolution). 1: none.
    double render_scale_x = 1.0, render_scale_y = 1.0;
};

// Method 2 end to end, the counterpart of defocus(): the desired focus from
// `focus`, checked against the stack's size (the manifest's, when it gives
// one) and the references' (pixels.info); the references' (near, far) from
// `stack`; selection, then the tiles, reading `pixels`.
// Errors name the culprit, and their subject is the argument at fault:
// "focus" (its source failed, or its size is not the stack's), "stack" (the
// references' near/far) or "pixels" (reading reference pixels); other errors
// (selection, reference headers) have none.
//
// The whole result: float R, G, B, A (+ the AOVs) over the references' data
// window, with the display window and header metadata of the first used
// reference, less the lens focus attributes (focusDistance, focus, fNumber,
// aperture: no single lens describes the result). An error if no pixel
// selects a reference (the desired near/far are all NaN).
GDOF_API Result<Image> composite(const FocalStack& stack, const FocusSource& focus, StackPixels& pixels,
                                 const CompositeOptions& options = {}, CompositeStats* stats = nullptr, const Exec& exec = {});
// A region of the result into target.view, equal to the crop of the whole
// (at a render scale: to its reduction); the references' grid is reference
// 0's data window. Where nothing is selected the region is 0 (no error).
GDOF_API Status composite(const FocalStack& stack, const FocusSource& focus, StackPixels& pixels, const CompositeTarget& target,
                          const CompositeOptions& options = {}, CompositeStats* stats = nullptr, const Exec& exec = {});

}  // namespace gdof
