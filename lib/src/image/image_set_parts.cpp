// Choosing the parts of a file: by view (stereo), by name or index, and a
// depth map given as its own file or part attached to its plate.
#include <algorithm>
#include <cstring>

#include "gdof/image_set.h"

namespace gdof {

namespace {

std::string quoted_list(const std::vector<std::string>& names) {
    std::string s;
    for (const std::string& n : names) s += (s.empty() ? "'" : ", '") + n + "'";
    return s.empty() ? std::string("none") : s;
}

std::string part_list(const ImageSet& set) {
    std::string s;
    for (std::size_t i = 0; i < set.size(); ++i)
        s += (i ? ", " : "") + std::to_string(i) + (set.part_name(i).empty() ? "" : " '" + set.part_name(i) + "'");
    return s;
}

// "12" -> 12; anything else (sign, letters, empty) -> -1.
long index_of(const std::string& s) {
    if (s.empty() || s.size() > 9) return -1;
    for (char c : s)
        if (c < '0' || c > '9') return -1;
    return std::stol(s);
}

}  // namespace

const std::string& ImageSet::part_view(std::size_t i) const {
    return std::visit([](const auto& p) -> const std::string& { return p.view; }, parts[i]);
}

std::vector<std::string> part_views(const ImageSet& set) {
    std::vector<std::string> views;
    for (std::size_t i = 0; i < set.size(); ++i) {
        const std::string& v = set.part_view(i);
        if (!v.empty() && std::find(views.begin(), views.end(), v) == views.end()) views.push_back(v);
    }
    return views;
}

Result<ImageSet> select_view(const ImageSet& set, const std::string& view) {
    const std::vector<std::string> views = part_views(set);
    if (std::find(views.begin(), views.end(), view) == views.end())
        return Status::error("no view '" + view + "' (the views are " + quoted_list(views) + ")", StatusCode::NotFound,
                             "view");
    ImageSet out;
    for (std::size_t i = 0; i < set.size(); ++i)
        if (set.part_view(i).empty() || set.part_view(i) == view) out.parts.push_back(set.parts[i]);
    return out;
}

Result<ImageSet> select_parts(const ImageSet& set, const std::string& list) {
    ImageSet out;
    std::size_t pos = 0;
    while (pos <= list.size()) {
        const std::size_t comma = std::min(list.find(',', pos), list.size());
        const std::string item = list.substr(pos, comma - pos);
        pos = comma + 1;
        long k = -1;
        for (std::size_t i = 0; i < set.size() && k < 0; ++i)
            if (!item.empty() && set.part_name(i) == item) k = long(i);
        if (k < 0) k = index_of(item);
        if (k < 0 || std::size_t(k) >= set.size())
            return Status::error("no part '" + item + "' (the parts are " + part_list(set) + ")", StatusCode::NotFound,
                                 "part");
        out.parts.push_back(set.parts[std::size_t(k)]);
    }
    return out;
}

Status attach_depth(Image& plate, const Image& depth, int channel, const std::string& name,
                    const std::string& plate_name, const std::string& depth_name) {
    if (channel < 0 || channel >= depth.nchannels())
        return Status::error(depth_name + " has no channel " + std::to_string(channel), StatusCode::NotFound, "depth");
    if (depth.width() != plate.width() || depth.height() != plate.height())
        return Status::error("the depth map " + depth_name + " is " + std::to_string(depth.width()) + "x" +
                                 std::to_string(depth.height()) + " but " + plate_name + " is " +
                                 std::to_string(plate.width()) + "x" + std::to_string(plate.height()),
                             StatusCode::InvalidArgument, "depth");
    if (plate.npixels() == 0) return Status::ok();
    if (const int old = plate.channel_index(name); old >= 0) plate.remove_channel(old);
    const int c = plate.add_channel({name, PixelType::Float});
    float* dst = plate.plane(c);
    const std::size_t n = plate.npixels();
    if (const float* src = depth.plane(channel)) {
        std::memcpy(dst, src, n * sizeof(float));
    } else {
        const std::uint32_t* u = depth.uplane(channel);
        for (std::size_t i = 0; i < n; ++i) dst[i] = float(u[i]);
    }
    return Status::ok();
}

}  // namespace gdof
