// The flat image model: planar float channels with names, a data window and a
// display window (both in absolute pixel coordinates, either may have negative
// origins, the data window may lie partly or wholly outside the display
// window, and may be empty), plus metadata. ImageView is a non-owning strided
// view so host memory (OFX) is processed without copies.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <new>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include "gdof/export.h"
#include "gdof/metadata.h"
#include "gdof/status.h"

namespace gdof {

// Half-open pixel rectangle [x0, x1) x [y0, y1), absolute coordinates.
// (EXR stores inclusive max; the I/O layer converts.)
struct Roi {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;

    constexpr int width() const { return x1 > x0 ? x1 - x0 : 0; }
    constexpr int height() const { return y1 > y0 ? y1 - y0 : 0; }
    constexpr bool empty() const { return width() == 0 || height() == 0; }
    constexpr std::size_t npixels() const { return std::size_t(width()) * std::size_t(height()); }
    constexpr bool contains(int x, int y) const { return x >= x0 && x < x1 && y >= y0 && y < y1; }
    constexpr bool operator==(const Roi&) const = default;
    // Grown by r pixels on every side (r may be negative).
    constexpr Roi grown(int r) const { return {x0 - r, y0 - r, x1 + r, y1 + r}; }
};
GDOF_API Roi intersect(const Roi& a, const Roi& b);  // empty Roi if disjoint
GDOF_API Roi unite(const Roi& a, const Roi& b);      // bounding box; an empty side is ignored
GDOF_API std::string to_string(const Roi& r);        // "[x0,x1)x[y0,y1)"

// A window cut into square tiles of `size` pixels (size >= 1), numbered
// row-major from the window's top-left; the last column and row are clipped
// to the window. The renderer and the compositor share it, so a tile index
// means the same pixels in both.
struct GDOF_API TileGrid {
             Roi window;
    int size = 1;
    int nx = 0, ny = 0;  // tiles per row, per column (0 for an empty window)

    TileGrid(const Roi& window, int size);
    long count() const { return long(nx) * long(ny); }
    Roi tile(long index) const;  // 0 <= index < count()
};

// Storage type of a channel in its file. Half and Float are processed as
// float; UInt (ids) is kept exactly as uint32 and never blurred.
enum class PixelType : std::uint8_t { Half, Float, UInt };
GDOF_API const char* to_string(PixelType t);

struct ChannelSpec {
    std::string name;  // full name, "layer.channel" for multilayer EXR
    PixelType type = PixelType::Float;
    bool operator==(const ChannelSpec&) const = default;
};

// How the file was laid out, so a round trip writes it back the same way.
struct StorageHints {
    int tile_width = 0, tile_height = 0;  // 0: scanline
    std::string compression;              // OIIO name ("zip", "piz", "dwaa:45"); empty: default
    std::string format;                   // source format name ("openexr", "png")
};

// Strided non-owning view: the value of channel c at absolute pixel (x, y) is
// base[c * cstride + (x - window.x0) * xstride + (y - window.y0) * ystride].
// Planar images and interleaved host buffers (negative ystride for bottom-up
// rows) are both expressible. The library's pixel arguments and output
// buffers are views; a function taking one checks its shape (channels,
// window) and fails with an error naming both when it is not the expected one.
template <class T>
struct BasicImageView {
    T* base = nullptr;
    int nchannels = 0;
    Roi window;
    std::ptrdiff_t cstride = 0, xstride = 0, ystride = 0;  // in elements

    // A view of mutable pixels is also a read-only view of them.
    operator BasicImageView<const T>() const
        requires(!std::is_const_v<T>)
    {
        return {base, nchannels, window, cstride, xstride, ystride};
    }

    T& at(int c, int x, int y) const {
        return base[c * cstride + std::ptrdiff_t(x - window.x0) * xstride +
                    std::ptrdiff_t(y - window.y0) * ystride];
    }
    bool valid() const { return base != nullptr || window.empty(); }
    int width() const { return window.width(); }
    int height() const { return window.height(); }
    std::size_t npixels() const { return window.npixels(); }
    // Whether every channel is a row-major plane over the window (x stride 1,
    // row stride = width): the layout kernels address as plane(c)[y * width + x].
    bool row_major() const { return window.empty() || (xstride == 1 && ystride == window.width()); }
    // Channel c's value at the window's origin (its plane, when row_major()).
    T* plane(int c) const { return base + c * cstride; }

    // Channels [first, first + count) of this view.
    BasicImageView channels(int first, int count) const {
        return {base + first * cstride, count, window, cstride, xstride, ystride};
    }
    // The part of this view over `sub`, clipped to the window.
    BasicImageView cropped(const Roi& sub) const {
        const Roi r = intersect(window, sub);
        if (r.empty()) return {base, nchannels, r, cstride, xstride, ystride};
        return {&at(0, r.x0, r.y0), nchannels, r, cstride, xstride, ystride};
    }

    // `nchannels` row-major planes over `window`, back to back from `base`
    // (a std::vector of nchannels * window.npixels() values, say).
    static BasicImageView planar(T* base, int nchannels, Roi window) {
        return {base, nchannels, window, std::ptrdiff_t(window.npixels()), 1, std::ptrdiff_t(window.width())};
    }
    // Interleaved buffer (e.g. OFX RGBA float): rowbytes may be negative.
    static BasicImageView interleaved(T* base, int nchannels, Roi window, std::ptrdiff_t row_stride_elems) {
        return {base, nchannels, window, 1, nchannels, row_stride_elems};
    }
};
using ImageView = BasicImageView<float>;
using ConstImageView = BasicImageView<const float>;

// An allocator that default-initialises: vector<T, DefaultInitAllocator<T>>::
// resize(n) leaves new elements of a trivial T unset (for buffers every element
// of which is written next, often in parallel: no serial zeroing first);
// assign() and resize(n, v) set them as usual.
template <class T>
struct DefaultInitAllocator : std::allocator<T> {
    template <class U>
    struct rebind {
        using other = DefaultInitAllocator<U>;
    };
    DefaultInitAllocator() = default;
    template <class U>
    DefaultInitAllocator(const DefaultInitAllocator<U>&) noexcept {}
    template <class U>
    void construct(U* p) noexcept(std::is_nothrow_default_constructible_v<U>) {
        ::new (static_cast<void*>(p)) U;
    }
    template <class U, class... A>
    void construct(U* p, A&&... a) {
        std::allocator_traits<std::allocator<T>>::construct(static_cast<std::allocator<T>&>(*this), p,
                                                            std::forward<A>(a)...);
    }
};

class GDOF_API Image {
public:
    Image() = default;
    // Zero-filled image. The display window defaults to the data window.
    Image(std::vector<ChannelSpec> channels, Roi data_window);
    Image(std::vector<ChannelSpec> channels, Roi data_window, Roi display_window);
    // Convenience: float channels by name.
    static Image with_channels(const std::vector<std::string>& names, Roi data_window);
    // Float planes left unset (UInt planes zero), for a caller that writes
    // every float pixel itself: a frame-sized image is then not zeroed on
    // one thread first (at 4K, 33 MB per plane).
    static Image uninitialized(std::vector<ChannelSpec> channels, Roi data_window, Roi display_window);

    int nchannels() const { return int(channels_.size()); }
    const std::vector<ChannelSpec>& channels() const { return channels_; }
    const ChannelSpec& channel(int c) const { return channels_[std::size_t(c)]; }
    // Half <-> Float only: a UInt channel stays UInt and a float one float
    // (an error naming the channel otherwise; nothing changes).
    Status set_channel_type(int c, PixelType t);
    void rename_channel(int c, std::string name) { channels_[std::size_t(c)].name = std::move(name); }
    int channel_index(std::string_view name) const;  // -1 if absent
    // Adds a channel (zero-filled) and returns its index.
    int add_channel(ChannelSpec spec);
    void remove_channel(int c);

    const Roi& data_window() const { return data_; }
    const Roi& display_window() const { return display_; }
    void set_display_window(const Roi& r) { display_ = r; }
    int width() const { return data_.width(); }
    int height() const { return data_.height(); }
    std::size_t npixels() const { return data_.npixels(); }

    // Planes are row-major over the data window, row stride = width(); the
    // float planes lie back to back in channel order, so channels_view() spans them.
    // plane() is for Half/Float channels (nullptr for UInt, and for an empty
    // window); uplane() for UInt. add_channel / remove_channel move the float
    // planes: take plane pointers after them.
    float* plane(int c) { return float_plane(c) < 0 ? nullptr : fdata_.data() + plane_offset(c); }
    const float* plane(int c) const { return float_plane(c) < 0 ? nullptr : fdata_.data() + plane_offset(c); }
    std::uint32_t* uplane(int c) { return uplanes_[std::size_t(c)].empty() ? nullptr : uplanes_[std::size_t(c)].data(); }
    const std::uint32_t* uplane(int c) const { return uplanes_[std::size_t(c)].empty() ? nullptr : uplanes_[std::size_t(c)].data(); }

    std::size_t offset(int x, int y) const {
        return std::size_t(y - data_.y0) * std::size_t(width()) + std::size_t(x - data_.x0);
    }
    // Absolute coordinates; must lie in the data window. Float channels only.
    float& at(int c, int x, int y) { return fdata_[plane_offset(c) + offset(x, y)]; }
    float at(int c, int x, int y) const { return fdata_[plane_offset(c) + offset(x, y)]; }
    // Value as float for any channel type (UInt converted), 0 outside the data window.
    float sample(int c, int x, int y) const;

    // Strided view of one float channel over the data window.
    ConstImageView channel_view(int c) const;
    ImageView channel_view(int c);
    // All channels as one view over the data window (channel c of the view
    // is channel c of the image). Needs every channel to be Half/Float: with
    // a UInt channel the view has no pixels (base nullptr, !valid() unless
    // the window is empty).
    ConstImageView channels_view() const;
    ImageView channels_view();

    Metadata metadata;
    std::string name;  // EXR part name, kept on write
    std::string view;  // EXR multi-view name ("left"), kept on write
    StorageHints storage;

private:
    // Index of channel c's plane among the float planes, -1 for UInt or an
    // empty window (nothing allocated).
    int float_plane(int c) const { return npixels() == 0 ? -1 : fplane_of_[std::size_t(c)]; }
    std::size_t plane_offset(int c) const { return std::size_t(fplane_of_[std::size_t(c)]) * npixels(); }
    int float_channel_count() const;
    void number_float_planes();
    // Numbers the planes and allocates them: float planes zero or unset, UInt planes zero.
    void allocate_planes(bool zero_floats);

    std::vector<ChannelSpec> channels_;
    Roi data_, display_;
    std::vector<float, DefaultInitAllocator<float>> fdata_;  // the float planes, back to back
    std::vector<int> fplane_of_;                       // per channel: its float plane, -1 for UInt
    std::vector<std::vector<std::uint32_t>> uplanes_;  // per channel: its UInt plane (empty for float)
};

// Helpers for the usual channel sets.
// Indices of R,G,B,A (or layer.R ...) for the given layer prefix ("" for none).
struct RgbaIndices {
    int r = -1, g = -1, b = -1, a = -1;
};
GDOF_API RgbaIndices find_rgba(const Image& img, std::string_view layer = "");

}  // namespace gdof
