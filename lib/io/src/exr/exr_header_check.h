// A walk over an EXR file's headers before OpenEXR reads them. OpenEXR 3.1
// allocates what a header declares before checking it against the file: each
// attribute's size (a 1 KB file that declared a 2 GB string took 2 GB), a
// tile's buffers (a deep tiled file whose tile is 2^31 pixels made it ask
// new[] for a negative size) and the chunk offset tables. Each was found by
// tests/fuzz (fuzz_exr).
#pragma once

#include <cstdint>
#include <string>

#include "gdof/status.h"

namespace gdof::io::detail {

// The most decoded bytes (pixels, samples, a tile's buffer) a file of
// `file_size` bytes can stand for: compressed data cannot be arbitrarily
// smaller than its pixels (4096:1 is far beyond what OpenEXR's codecs reach),
// with room for small files of constant images.
inline std::uint64_t decoded_bytes_limit(std::uint64_t file_size) {
    return file_size * 4096ull + (std::uint64_t(64) << 20);
}

// An error naming the culprit if a header attribute declares more bytes than
// the file has left, the headers run past the end, a part's tile is larger
// than decoded_bytes_limit allows, or the parts need more chunk offsets (8
// bytes each) than the file has after its headers; ok otherwise (including
// files that are not EXR, and header values OpenEXR itself rejects).
Status check_exr_header_sizes(const std::string& path, std::uint64_t file_size);

}  // namespace gdof::io::detail
