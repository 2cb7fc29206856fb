#include "stack_pixels.h"

#include <string>

namespace gdof::ofx {

namespace {

// A straight-alpha RGBA view premultiplied into `store` (interleaved RGBA).
ConstImageView premultiplied_copy(const ConstImageView& v, std::vector<float>& store) {
    const Roi& w = v.window;
    store.assign(w.npixels() * 4, 0.0f);
    float* p = store.data();
    for (int y = w.y0; y < w.y1; ++y)
        for (int x = w.x0; x < w.x1; ++x, p += 4) {
            const float a = v.at(3, x, y);
            for (int c = 0; c < 3; ++c) p[c] = v.at(c, x, y) * a;
            p[3] = a;
        }
    return ConstImageView::interleaved(store.data(), 4, w, std::ptrdiff_t(w.width()) * 4);
}

}  // namespace

SourceFramePixels::SourceFramePixels(const Clip& source, std::vector<int> frames, const PixelFrame& frame,
                                     const Roi& grid)
    : ViewStackPixels(std::vector<ConstImageView>(frames.size()), grid),
      source_(source),
      frames_(std::move(frames)),
      frame_(frame),
      grid_(grid) {}

Status SourceFramePixels::prepare(const std::vector<int>& refs, const Roi& region) {
    const Roi abs{grid_.x0 + region.x0, grid_.y0 + region.y0, grid_.x0 + region.x1, grid_.y0 + region.y1};
    const OfxRectI pixels = frame_.to_ofx(abs);
    const OfxRectD canonical = frame_.to_canonical(pixels);
    try {
        for (int i : refs) {
            const int frame = frames_[std::size_t(i)];
            auto img = std::make_unique<ClipImage>(source_, double(frame), &canonical);
            if (!img->valid())
                fail("clip 'Source' has no image at frame " + std::to_string(frame) + " (reference " + std::to_string(i) +
                     ")");
            img->require({kOfxImageComponentRGBA, kOfxImageComponentRGB});
            const ImageView host = img->view(frame_, pixels);
            ConstImageView v{host.base, host.nchannels, host.window, host.cstride, host.xstride, host.ystride};
            if (img->ncomponents() == 4 && img->premultiplication() == kOfxImageUnPreMultiplied)
                v = premultiplied_copy(v, premultiplied_.emplace_back());
            set_view(i, v);
            images_.push_back(std::move(img));
        }
    } catch (const std::exception& e) {
        fetch_error_ = std::current_exception();
        return Status::error(e.what());
    }
    return Status::ok();
}

}  // namespace gdof::ofx
