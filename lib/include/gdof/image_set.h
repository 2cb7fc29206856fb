// What one image file holds: one or more parts (EXR multipart, or OIIO
// subimages), each flat or deep. Single-part files have one part.
#pragma once

#include <variant>
#include <vector>

#include "gdof/deep.h"
#include "gdof/image.h"

namespace gdof {

using Part = std::variant<Image, DeepImage>;

struct ImageSet {
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
};

}  // namespace gdof
