// A walk over an EXR file's headers before OpenEXR reads them: OpenEXR 3.1
// allocates each attribute's declared size before reading it, so a 1 KB file
// that declares a 2 GB string took 2 GB (found by tests/fuzz, fuzz_exr).
#pragma once

#include <cstdint>
#include <string>

#include "gdof/status.h"

namespace gdof::io::detail {

// An error naming the attribute if any header attribute declares more bytes
// than the file has left, or the headers run past the end; ok otherwise
// (including files that are not EXR: OpenEXR reports those).
Status check_exr_header_sizes(const std::string& path, std::uint64_t file_size);

}  // namespace gdof::io::detail
