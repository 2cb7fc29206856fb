// Internal to gdof::io: colour at the read/write edges (linearize.cpp):
// conversion to the scene-linear working space through ColourConfig, and
// alpha association for straight-alpha formats.
#pragma once

#include <string>

#include "gdof/export.h"
#include "gdof/image.h"
#include "gdof/io/colour.h"
#include "gdof/status.h"

namespace gdof::io::detail {

// Converts the colour channels of `image` to scene-linear in place and sets
// oiio:ColorSpace to "linear". `source` is a colour space name known to the
// config; names that the config does not know are errors.
GDOF_API Status linearize(Image& image, const std::string& source, const ColourConfig& config, const std::string& path);
GDOF_API const ColourConfig& config_or_default(const ColourConfig* c);
// Canonical linear name used as the working space.
inline constexpr const char* kWorkingSpace = "scene_linear";  // a role in OCIO configs, known to the built-in one

// Multiplies colour channels (every channel except alpha and UInt channels)
// by alpha / divides where alpha > 0.
GDOF_API void premultiply(Image& image, int alpha);
GDOF_API void unpremultiply(Image& image, int alpha);

}  // namespace gdof::io::detail
