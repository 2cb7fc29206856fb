#include "gdof/image_set.h"

namespace gdof {

const Metadata& ImageSet::metadata(std::size_t i) const {
    return std::visit([](const auto& p) -> const Metadata& { return p.metadata; }, parts[i]);
}
Metadata& ImageSet::metadata(std::size_t i) {
    return std::visit([](auto& p) -> Metadata& { return p.metadata; }, parts[i]);
}
const std::string& ImageSet::part_name(std::size_t i) const {
    return std::visit([](const auto& p) -> const std::string& { return p.name; }, parts[i]);
}

}  // namespace gdof
