// Row-major planes of an ImageView, for kernels that address a channel as
// plane[y * width + x]: the view's own memory when it is already laid out so
// (Image planes, planar buffers), else a packed copy that store() writes back
// (interleaved host buffers, cropped views). Copies are exact, so a kernel
// gives the same bits either way.
#pragma once

#include <cstddef>
#include <span>
#include <type_traits>
#include <vector>

#include "gdof/image.h"

namespace gdof::image_detail {

template <class T>  // float, or const float for inputs
class RowMajorPlanes {
public:
    explicit RowMajorPlanes(const BasicImageView<T>& view) : view_(view) {
        const int nc = view.window.empty() ? 0 : view.nchannels;
        planes_.resize(std::size_t(nc));
        if (view.row_major()) {
            for (int c = 0; c < nc; ++c) planes_[std::size_t(c)] = view.plane(c);
            return;
        }
        const std::size_t n = view.npixels();
        copy_.resize(std::size_t(nc) * n);
        for (int c = 0; c < nc; ++c) {
            std::remove_const_t<T>* dst = copy_.data() + std::size_t(c) * n;
            planes_[std::size_t(c)] = dst;
            for (int y = view.window.y0; y < view.window.y1; ++y)
                for (int x = view.window.x0; x < view.window.x1; ++x) *dst++ = view.at(c, x, y);
        }
    }

    std::span<T* const> planes() const { return planes_; }
    T* plane(int c) const { return planes_[std::size_t(c)]; }

    // Writes a packed copy back into the view (nothing to do without one).
    void store() const
        requires(!std::is_const_v<T>)
    {
        if (copy_.empty()) return;
        for (std::size_t c = 0; c < planes_.size(); ++c) {
            const T* src = planes_[c];
            for (int y = view_.window.y0; y < view_.window.y1; ++y)
                for (int x = view_.window.x0; x < view_.window.x1; ++x) view_.at(int(c), x, y) = *src++;
        }
    }

private:
    BasicImageView<T> view_;
    std::vector<std::remove_const_t<T>> copy_;
    std::vector<T*> planes_;
};

}  // namespace gdof::image_detail
