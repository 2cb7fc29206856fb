// Internal to gdof::io: OpenEXR files straight through the OpenEXR C++ API
// (exr_read.cpp / exr_write.cpp), behind read_image / write_image.
#pragma once

#include <string>
#include <variant>
#include <vector>

#include "gdof/export.h"
#include "gdof/image_set.h"
#include "gdof/io/io_options.h"
#include "gdof/status.h"

namespace gdof::io::detail {

// Attribute marking a part written with an empty data window (OpenEXR cannot
// store one, so a single zero pixel / zero-sample pixel is written instead).
inline constexpr const char* kEmptyDataWindowAttr = "gdof:emptyDataWindow";

// `display` is the name used in messages (the user's path, not the temp file).
GDOF_API Result<ImageSet> read_exr(const std::string& path);
// Parts by reference, so single images are written without a copy.
using PartRef = std::variant<const Image*, const DeepImage*>;
GDOF_API std::vector<PartRef> part_refs(const ImageSet& images);
GDOF_API Status write_exr(const std::string& file, const std::string& display, const std::vector<PartRef>& parts,
                          const WriteOptions& opts);

}  // namespace gdof::io::detail
