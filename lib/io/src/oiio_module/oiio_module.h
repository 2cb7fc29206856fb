// The OpenImageIO module's functions (the table of oiio_module_api.h is made
// of them in oiio_module.cpp).
#pragma once

#include <OpenImageIO/imageio.h>

#include "oiio/oiio_module_api.h"

namespace gdof::io::oiio_module {

using detail::OiioHeader;
using detail::OiioPartInfo;

// oiio_read.cpp
Result<ImageSet> read(const std::string& path, std::vector<OiioPartInfo>& info);
void clear_error();
// A spec's attributes as read_image keeps them (file bookkeeping left out).
void spec_to_metadata(const OIIO::ImageSpec& spec, Metadata& md);

// oiio_write.cpp
Status write(const std::string& file, const std::string& display, const Image& image, const WriteOptions& opts);

// oiio_headers.cpp (errors: OIIO's text; the caller names the file)
Result<OiioHeader> header(const std::string& path);
void cache_configure(double max_memory_mb, int strip_rows);
int cache_files_opened();
Result<OiioHeader> cache_header(const std::string& path);
Status cache_read(const std::string& path, const Roi& pixels, int chbegin, int chend, float* out);
void cache_release(const std::string& path);

}  // namespace gdof::io::oiio_module
