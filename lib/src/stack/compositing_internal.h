// Shared by the compositing steps (compositing_tiles.cpp) and composite()
// (compositing_pipeline.cpp): step 3 writing into any strided memory, so the
// result lands in an Image's planes or straight in a caller's buffer.
#pragma once

#include "gdof/compositing.h"

namespace gdof::detail {

// Where step 3 writes: one single-channel view per output channel, in order
// R, G, B[, A[, stack.index, stack.deviation]], each over the selection's
// window in its local coordinates ([0, w) x [0, h)), all zero on entry.
struct CompositePlanes {
    ImageView channel[6];
    int count = 0;
};

// Planes of an image's float channels (at most 6).
CompositePlanes image_planes(Image& img);
// The channels of a strided view (interleaved host memory) over `region`
// (absolute, inside view.window), as planes in region-local coordinates.
CompositePlanes view_planes(const ImageView& view, const Roi& region);

// Step 3 into `out` (composite_stack without the allocation): calls
// pixels.prepare, then reads and writes tile by tile. stats: references,
// references_used, tiles, tile_reads, composite_seconds.
Status composite_tiles(const StackSelection& selection, StackPixels& pixels, const CompositeOptions& settings,
                       const CompositePlanes& out, CompositeStats* stats, const Exec& exec);

}  // namespace gdof::detail
