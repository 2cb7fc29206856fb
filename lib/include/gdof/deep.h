// Deep images: each pixel holds a list of samples, each sample a value for
// every channel (Z and, for volumetric samples, ZBack). Storage is planar per
// channel with a prefix-sum offset table, which is how OpenEXR lays out deep
// data and lets a pixel's samples be reached in O(1).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "gdof/export.h"
#include "gdof/image.h"
#include "gdof/status.h"

namespace gdof {

class GDOF_API DeepImage {
public:
    DeepImage() = default;
    DeepImage(std::vector<ChannelSpec> channels, Roi data_window, Roi display_window);

    int nchannels() const { return int(channels_.size()); }
    const std::vector<ChannelSpec>& channels() const { return channels_; }
    const ChannelSpec& channel(int c) const { return channels_[std::size_t(c)]; }
    int channel_index(std::string_view name) const;
    int z_channel() const;       // "Z" (or "*.Z"), -1 if absent
    int zback_channel() const;   // "ZBack", -1 if absent
    // Half <-> Float only (an error naming the channel otherwise; nothing changes).
    Status set_channel_type(int c, PixelType t);
    // Adds a zero-filled sample channel and returns its index.
    int add_channel(ChannelSpec spec);

    const Roi& data_window() const { return data_; }
    const Roi& display_window() const { return display_; }
    void set_display_window(const Roi& r) { display_ = r; }
    std::size_t npixels() const { return data_.npixels(); }
    std::size_t pixel_index(int x, int y) const {
        return std::size_t(y - data_.y0) * std::size_t(data_.width()) + std::size_t(x - data_.x0);
    }

    // Sets every pixel's sample count and allocates zeroed samples. An error
    // (nothing changes) unless there is one count per pixel (npixels()).
    Status set_sample_counts(const std::vector<std::uint32_t>& counts);
    std::uint32_t sample_count(std::size_t pixel) const { return counts_[pixel]; }
    std::size_t first_sample(std::size_t pixel) const { return offsets_[pixel]; }
    std::size_t total_samples() const { return offsets_.empty() ? 0 : offsets_.back(); }
    const std::vector<std::uint32_t>& sample_counts() const { return counts_; }

    // All samples of a channel, pixel after pixel (float channels / UInt channels).
    float* samples(int c) { return fsamples_[std::size_t(c)].data(); }
    const float* samples(int c) const { return fsamples_[std::size_t(c)].data(); }
    std::uint32_t* usamples(int c) { return usamples_[std::size_t(c)].data(); }
    const std::uint32_t* usamples(int c) const { return usamples_[std::size_t(c)].data(); }

    Metadata metadata;
    std::string name;
    std::string view;
    StorageHints storage;

private:
    void allocate_samples(const std::vector<std::uint32_t>& counts);

    std::vector<ChannelSpec> channels_;
    Roi data_, display_;
    std::vector<std::uint32_t> counts_;
    std::vector<std::size_t> offsets_;  // npixels()+1 prefix sums
    std::vector<std::vector<float>> fsamples_;
    std::vector<std::vector<std::uint32_t>> usamples_;
};

}  // namespace gdof
