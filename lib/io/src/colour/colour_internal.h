// Internal to the colour module: the OCIO-backed config factory.
#pragma once

#include <cstddef>
#include <functional>
#include <memory>
#include <string>

#include "gdof/io/colour.h"

namespace gdof::io::detail {

Result<std::shared_ptr<const ColourConfig>> load_ocio_config(const std::string& path);

// Lower-cases ASCII letters.
std::string ascii_lower(std::string s);

// Applies f(r, g, b, count) to each colour triple of an image in row chunks,
// in parallel. The first failure is returned.
Status for_each_colour_plane(Image& image,
                             const std::function<Status(float*, float*, float*, std::size_t)>& f);

}  // namespace gdof::io::detail
