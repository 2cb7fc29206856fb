// What one image file holds: one or more parts (EXR multipart, or OIIO
// subimages), each flat or deep. Single-part files have one part.
#pragma once

#include <string>
#include <variant>
#include <vector>

#include "gdof/deep.h"
#include "gdof/export.h"
#include "gdof/image.h"
#include "gdof/status.h"

namespace gdof {

using Part = std::variant<Image, DeepImage>;

struct GDOF_API ImageSet {
    std::vector<Part> parts;

    bool empty() const { return parts.empty(); }
    std::size_t size() const { return parts.size(); }
    bool is_deep(std::size_t i) const { return std::holds_alternative<DeepImage>(parts[i]); }
    Image& flat(std::size_t i) { return std::get<Image>(parts[i]); }
    const Image& flat(std::size_t i) const { return std::get<Image>(parts[i]); }
    DeepImage& deep(std::size_t i) { return std::get<DeepImage>(parts[i]); }
    const DeepImage& deep(std::size_t i) const { return std::get<DeepImage>(parts[i]); }
    const Metadata& metadata(std::size_t i) const;
    Metadata& metadata(std::size_t i);
    const std::string& part_name(std::size_t i) const;
    const std::string& part_view(std::size_t i) const;
};

// Choosing parts, as files come from renderers and stereo rigs.
// The distinct view names of the parts ("left", "right"), in order of first
// appearance; empty when no part names a view.
GDOF_API std::vector<std::string> part_views(const ImageSet& set);
// The parts of one view, and the parts that name no view (which belong to
// every view, as in a multi-view EXR). Errors: a view no part has, naming the
// views there are.
GDOF_API Result<ImageSet> select_view(const ImageSet& set, const std::string& view);
// The parts listed by name or index ("beauty,depth", "0,2"), in the list's
// order. Errors: an unknown name or an index out of range, naming the parts
// there are.
GDOF_API Result<ImageSet> select_parts(const ImageSet& set, const std::string& list);
// Puts channel `channel` of `depth` into `plate` as channel `name` (replacing
// one of that name): a depth map given as its own file or part. Both must be
// the same size; pixels are matched from their data windows' corners (a
// PNG depth map has no window of its own). Errors name `plate_name` and
// `depth_name` with both sizes.
GDOF_API Status attach_depth(Image& plate, const Image& depth, int channel, const std::string& name,
                             const std::string& plate_name, const std::string& depth_name);

}  // namespace gdof
