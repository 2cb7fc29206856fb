// Method 2 (Kosloff & Barsky, section 3): each output pixel is pulled from
// the reference of a focus/aperture stack whose depth of field [near, far]
// best matches the desired one at that pixel (focus_surfaces.h), by the
// paper's deviation
//     |near_desired - near_ref| + |far_desired - far_ref|.
// docs/compositing.md has the rules, the soft mode and the AOVs.
//
// Three steps, so that a reference no pixel selects is never read:
//   1. StackIndex::build: the references' (near, far) pairs indexed once.
//   2. select_references: the choice for every pixel, and which references
//      are needed at all (no pixel is read).
//   3. composite_stack: tile by tile, each tile reads only the references its
//      pixels chose, through a StackPixels source (files through an image
//      cache in gdof::io::StackReader, or images in memory).
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
#include <vector>

#include "gdof/blur_field.h"
#include "gdof/exec.h"
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
Deviation stack_deviation(double near_desired, double far_desired, double near_ref, double far_ref);

// The references' (near, far) pairs, indexed once: sorted by near in two
// groups (finite far, infinite far); a query walks outward from the desired
// near and stops when |near_desired - near_ref| alone exceeds the k-th best
// deviation found, so it usually looks at a handful of references whatever
// the stack size. Exact: equal to a brute-force search, ties included.
class StackIndex {
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
struct StackSelection {
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
Result<StackSelection> select_references(const StackIndex& index, const DesiredFocus& desired,
                                         const CompositeOptions& settings = {}, const Exec& exec = {});

// Where reference pixels come from. read_tile is called concurrently from
// several threads (for different tiles) and must be thread-safe.
class StackPixels {
public:
    virtual ~StackPixels() = default;
    virtual int size() const = 0;  // number of references
    // R, G, B, A (premultiplied, scene-linear) of reference `ref` over `tile`
    // (local coordinates, inside the stack's window), interleaved, row-major,
    // tile.npixels() * 4 floats. A missing alpha reads 1, missing colour 0.
    virtual Status read_tile(int ref, const Roi& tile, float* rgba) = 0;
};

// References held in memory (tests, OFX hosts). All images must have the
// same data window size; pixel (x, y) of the stack is pixel
// (x0 + x, y0 + y) of each image's data window. Counts reads per reference.
class MemoryStackPixels : public StackPixels {
public:
    explicit MemoryStackPixels(std::vector<const Image*> images);
    int size() const override { return int(images_.size()); }
    Status read_tile(int ref, const Roi& tile, float* rgba) override;
    long reads(int ref) const;  // read_tile calls for that reference

private:
    std::vector<const Image*> images_;
    std::vector<std::atomic<long>> reads_;
};

struct CompositeStats {
    int references = 0, references_used = 0;
    long tiles = 0;       // tiles of the output
    long tile_reads = 0;  // read_tile calls (reference tiles read)
    double select_seconds = 0, composite_seconds = 0;
};

// Step 3: an image with float channels R, G, B, A (+ the AOVs) over the
// selection's window moved to `origin` (the references' data window origin).
// Display window = data window (callers set the references' one).
Result<Image> composite_stack(const StackSelection& selection, StackPixels& pixels, const CompositeOptions& settings = {},
                              int origin_x = 0, int origin_y = 0, CompositeStats* stats = nullptr,
                              const Exec& exec = {});

}  // namespace gdof
