#include "gdof/deep.h"

namespace gdof {

DeepImage::DeepImage(std::vector<ChannelSpec> channels, Roi data_window, Roi display_window)
    : channels_(std::move(channels)), data_(data_window), display_(display_window) {
    fsamples_.resize(channels_.size());
    usamples_.resize(channels_.size());
    allocate_samples(std::vector<std::uint32_t>(npixels(), 0u));
}

int DeepImage::channel_index(std::string_view name) const {
    for (std::size_t c = 0; c < channels_.size(); ++c)
        if (channels_[c].name == name) return int(c);
    return -1;
}

static bool ends_with_channel(const std::string& name, std::string_view base) {
    if (name == base) return true;
    return name.size() > base.size() && name.compare(name.size() - base.size(), base.size(), base) == 0 &&
           name[name.size() - base.size() - 1] == '.';
}

// The channel `base` ("Z"), else the first "<layer>.<base>"; -1 if neither.
static int base_channel(const DeepImage& d, std::string_view base) {
    const int i = d.channel_index(base);
    if (i >= 0) return i;
    for (int c = 0; c < d.nchannels(); ++c)
        if (ends_with_channel(d.channel(c).name, base)) return c;
    return -1;
}

int DeepImage::z_channel() const { return base_channel(*this, "Z"); }

int DeepImage::zback_channel() const { return base_channel(*this, "ZBack"); }

Status DeepImage::set_channel_type(int c, PixelType t) {
    auto& ch = channels_[std::size_t(c)];
    if ((ch.type == PixelType::UInt) != (t == PixelType::UInt))
        return Status::error("deep channel '" + ch.name + "' is " + to_string(ch.type) + " and cannot become " +
                                 to_string(t) + " (uint and float channels keep their storage)",
                             StatusCode::InvalidArgument);
    ch.type = t;
    return Status::ok();
}

int DeepImage::add_channel(ChannelSpec spec) {
    const bool is_uint = spec.type == PixelType::UInt;
    channels_.push_back(std::move(spec));
    fsamples_.emplace_back();
    usamples_.emplace_back();
    if (is_uint)
        usamples_.back().assign(total_samples(), 0u);
    else
        fsamples_.back().assign(total_samples(), 0.0f);
    return nchannels() - 1;
}

Status DeepImage::set_sample_counts(const std::vector<std::uint32_t>& counts) {
    if (counts.size() != npixels())
        return Status::error("deep image: " + std::to_string(counts.size()) + " sample counts for the " +
                                 std::to_string(npixels()) + " pixels of its data window " + to_string(data_),
                             StatusCode::InvalidArgument);
    allocate_samples(counts);
    return Status::ok();
}

void DeepImage::allocate_samples(const std::vector<std::uint32_t>& counts) {
    counts_ = counts;
    offsets_.assign(counts_.size() + 1, 0);
    for (std::size_t i = 0; i < counts_.size(); ++i) offsets_[i + 1] = offsets_[i] + counts_[i];
    for (std::size_t c = 0; c < channels_.size(); ++c) {
        if (channels_[c].type == PixelType::UInt) {
            usamples_[c].assign(total_samples(), 0u);
            fsamples_[c].clear();
        } else {
            fsamples_[c].assign(total_samples(), 0.0f);
            usamples_[c].clear();
        }
    }
}

}  // namespace gdof
