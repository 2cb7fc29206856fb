// The Source clip's frames as the references of "gdof Focal Stack"
// (stack_source = frames), read in place from the host's images.
#pragma once

#include <exception>
#include <memory>
#include <vector>

#include "gdof/compositing.h"
#include "ofx_clips.h"

namespace gdof::ofx {

// prepare() (called by composite() on the render thread, once the selection
// is known) fetches only the frames some pixel chose, over the region the
// tiles cover, and presents each host image to the library as a view, without
// a copy; only a straight-alpha (unpremultiplied) RGBA image is copied, to be
// premultiplied. Images are released when this is destroyed.
class SourceFramePixels final : public ViewStackPixels {
public:
    // frames[i]: the Source frame of reference i; grid: the stack's pixels
    // (gdof coordinates at the render scale).
    SourceFramePixels(const Clip& source, std::vector<int> frames, const PixelFrame& frame, const Roi& grid);
    Status prepare(const std::vector<int>& refs, const Roi& region) override;
    // A fetch that failed in prepare() threw an Error (a missing frame, an
    // unsupported image): thrown again here, so the plugin reports it as it was.
    void rethrow_fetch_error() const {
        if (fetch_error_) std::rethrow_exception(fetch_error_);
    }

private:
    const Clip& source_;
    std::vector<int> frames_;
    PixelFrame frame_;
    Roi grid_;
    std::vector<std::unique_ptr<ClipImage>> images_;
    std::vector<std::vector<float>> premultiplied_;  // copies of straight-alpha images
    std::exception_ptr fetch_error_;
};

}  // namespace gdof::ofx
