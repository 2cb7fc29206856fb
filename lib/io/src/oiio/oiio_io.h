// Internal to gdof::io: every non-EXR format, and the stack references'
// tile cache, through OpenImageIO. OpenImageIO (and the ~250 libraries its
// Debian build pulls in: GDAL, FFmpeg, ...) is loaded only when first
// needed: it lives in a module (gdof_oiio.so, lib/io/src/oiio_module) that
// oiio_module_loader.cpp opens, so a process that reads and writes only
// EXR never loads it (start-up: docs/farm.md).
#pragma once

#include <string>
#include <vector>

#include "gdof/export.h"
#include "oiio/oiio_module_api.h"

namespace gdof::io::detail {

// The module, loaded on the first call (thread-safe); later calls return
// the same table, or the same error: which files were looked for and why
// none would load.
GDOF_API Result<const OiioModuleApi*> oiio_module();

GDOF_API Result<ImageSet> read_oiio(const std::string& path, std::vector<OiioPartInfo>& info);
GDOF_API Status write_oiio(const std::string& file, const std::string& display, const Image& image,
                           const WriteOptions& opts);
// The header of a file in any format OIIO reads; the error is OIIO's text
// (the caller names the file).
GDOF_API Result<OiioHeader> read_oiio_header(const std::string& path);
// Clears OIIO's global (per-thread) error message so errors do not leak
// from one call into the next (nothing to clear before the module loads).
GDOF_API void clear_oiio_error();

}  // namespace gdof::io::detail
