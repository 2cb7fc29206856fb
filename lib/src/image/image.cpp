#include "gdof/image.h"

#include <algorithm>
#include <cassert>
#include <cstdio>

namespace gdof {

Roi intersect(const Roi& a, const Roi& b) {
    Roi r{std::max(a.x0, b.x0), std::max(a.y0, b.y0), std::min(a.x1, b.x1), std::min(a.y1, b.y1)};
    if (r.empty()) return {r.x0, r.y0, r.x0, r.y0};
    return r;
}

Roi unite(const Roi& a, const Roi& b) {
    if (a.empty()) return b;
    if (b.empty()) return a;
    return {std::min(a.x0, b.x0), std::min(a.y0, b.y0), std::max(a.x1, b.x1), std::max(a.y1, b.y1)};
}

TileGrid::TileGrid(const Roi& w, int tile_size)
    : window(w), size(tile_size), nx((w.width() + tile_size - 1) / tile_size), ny((w.height() + tile_size - 1) / tile_size) {}

Roi TileGrid::tile(long index) const {
    const int x0 = window.x0 + int(index % nx) * size, y0 = window.y0 + int(index / nx) * size;
    return {x0, y0, std::min(x0 + size, window.x1), std::min(y0 + size, window.y1)};
}

std::string to_string(const Roi& r) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "[%d,%d)x[%d,%d)", r.x0, r.x1, r.y0, r.y1);
    return buf;
}

const char* to_string(PixelType t) {
    switch (t) {
        case PixelType::Half: return "half";
        case PixelType::Float: return "float";
        case PixelType::UInt: return "uint";
    }
    return "?";
}

Image::Image(std::vector<ChannelSpec> channels, Roi data_window)
    : Image(std::move(channels), data_window, data_window) {}

Image::Image(std::vector<ChannelSpec> channels, Roi data_window, Roi display_window)
    : channels_(std::move(channels)), data_(data_window), display_(display_window) {
    allocate_planes(true);
}

void Image::allocate_planes(bool zero_floats) {
    // Keep a degenerate (x1 < x0) window representable but allocate nothing for it.
    number_float_planes();
    const std::size_t n = std::size_t(float_channel_count()) * npixels();
    if (zero_floats) fdata_.assign(n, 0.0f);
    else fdata_.resize(n);
    uplanes_.resize(channels_.size());
    for (std::size_t c = 0; c < channels_.size(); ++c)
        if (channels_[c].type == PixelType::UInt) uplanes_[c].assign(npixels(), 0u);
}

Image Image::uninitialized(std::vector<ChannelSpec> channels, Roi data_window, Roi display_window) {
    Image img;
    img.channels_ = std::move(channels);
    img.data_ = data_window;
    img.display_ = display_window;
    img.allocate_planes(false);
    return img;
}

Image Image::with_channels(const std::vector<std::string>& names, Roi data_window) {
    std::vector<ChannelSpec> specs;
    for (const auto& n : names) specs.push_back({n, PixelType::Float});
    return Image(std::move(specs), data_window);
}

int Image::float_channel_count() const {
    int n = 0;
    for (const ChannelSpec& c : channels_) n += c.type == PixelType::UInt ? 0 : 1;
    return n;
}

void Image::number_float_planes() {
    fplane_of_.assign(channels_.size(), -1);
    int k = 0;
    for (std::size_t c = 0; c < channels_.size(); ++c)
        if (channels_[c].type != PixelType::UInt) fplane_of_[c] = k++;
}

Status Image::set_channel_type(int c, PixelType t) {
    auto& ch = channels_[std::size_t(c)];
    if ((ch.type == PixelType::UInt) != (t == PixelType::UInt))
        return Status::error("channel '" + ch.name + "' is " + to_string(ch.type) + " and cannot become " + to_string(t) +
                                 " (uint and float channels keep their storage)",
                             StatusCode::InvalidArgument);
    ch.type = t;
    return Status::ok();
}

int Image::channel_index(std::string_view name) const {
    for (std::size_t c = 0; c < channels_.size(); ++c)
        if (channels_[c].name == name) return int(c);
    return -1;
}

int Image::add_channel(ChannelSpec spec) {
    const bool is_uint = spec.type == PixelType::UInt;
    channels_.push_back(std::move(spec));
    number_float_planes();
    uplanes_.emplace_back();
    if (is_uint) {
        uplanes_.back().assign(npixels(), 0u);
    } else {
        // Exactly one plane more (resize alone may double the capacity).
        fdata_.reserve(fdata_.size() + npixels());
        fdata_.resize(fdata_.size() + npixels(), 0.0f);
    }
    return nchannels() - 1;
}

void Image::remove_channel(int c) {
    if (channels_[std::size_t(c)].type != PixelType::UInt && npixels() > 0) {
        const auto first = fdata_.begin() + std::ptrdiff_t(plane_offset(c));
        fdata_.erase(first, first + std::ptrdiff_t(npixels()));
    }
    channels_.erase(channels_.begin() + c);
    uplanes_.erase(uplanes_.begin() + c);
    number_float_planes();
}

float Image::sample(int c, int x, int y) const {
    if (!data_.contains(x, y)) return 0.0f;
    if (channels_[std::size_t(c)].type == PixelType::UInt) return float(uplanes_[std::size_t(c)][offset(x, y)]);
    return at(c, x, y);
}

ConstImageView Image::channel_view(int c) const {
    return {plane(c), 1, data_, 0, 1, std::ptrdiff_t(width())};
}

ImageView Image::channel_view(int c) {
    return {plane(c), 1, data_, 0, 1, std::ptrdiff_t(width())};
}

ConstImageView Image::channels_view() const {
    if (float_channel_count() != nchannels()) return {nullptr, 0, data_, 0, 0, 0};
    return ConstImageView::planar(npixels() ? fdata_.data() : nullptr, nchannels(), data_);
}

ImageView Image::channels_view() {
    if (float_channel_count() != nchannels()) return {nullptr, 0, data_, 0, 0, 0};
    return ImageView::planar(npixels() ? fdata_.data() : nullptr, nchannels(), data_);
}

RgbaIndices find_rgba(const Image& img, std::string_view layer) {
    std::string prefix = layer.empty() ? std::string() : std::string(layer) + ".";
    auto find = [&](std::initializer_list<const char*> names) {
        for (const char* n : names) {
            int i = img.channel_index(prefix + n);
            if (i >= 0) return i;
        }
        return -1;
    };
    return {find({"R", "r", "red"}), find({"G", "g", "green"}), find({"B", "b", "blue"}),
            find({"A", "a", "alpha"})};
}

}  // namespace gdof
