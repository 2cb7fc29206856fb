// Internal to gdof::io: every non-EXR format through OpenImageIO
// (oiio_read.cpp / oiio_write.cpp), behind read_image / write_image.
#pragma once

#include <string>
#include <vector>

#include "gdof/export.h"
#include "gdof/image_set.h"
#include "gdof/io/io_options.h"
#include "gdof/status.h"

namespace gdof::io::detail {

struct OiioPartInfo {
    bool integer_data = false;       // 8/16/32-bit integer pixels (normalised to 0..1)
    int alpha_channel = -1;          // index of alpha in the part, -1 if none
    bool unassociated_alpha = false; // colour not yet multiplied by alpha
};
GDOF_API Result<ImageSet> read_oiio(const std::string& path, std::vector<OiioPartInfo>& info);
GDOF_API Status write_oiio(const std::string& file, const std::string& display, const Image& image,
                           const WriteOptions& opts);
// Clears OIIO's global (per-thread) error message so errors do not leak
// from one call into the next.
GDOF_API void clear_oiio_error();

}  // namespace gdof::io::detail
