// What the OpenImageIO module (lib/io/src/oiio_module, gdof_oiio.so) offers
// the library it is loaded into: a table of functions with gdof types. Both
// sides are compiled from one build; the loader refuses a module whose ABI
// number, version or type sizes differ (a stale copy from another build).
#pragma once

#include <string>
#include <vector>

#include "gdof/image_set.h"
#include "gdof/io/io_options.h"
#include "gdof/metadata.h"
#include "gdof/status.h"

namespace gdof::io::detail {

// Raise when a signature or a struct below changes.
constexpr int kOiioModuleAbi = 1;

struct OiioPartInfo {
    bool integer_data = false;       // 8/16/32-bit integer pixels (normalised to 0..1)
    int alpha_channel = -1;          // index of alpha in the part, -1 if none
    bool unassociated_alpha = false; // colour not yet multiplied by alpha
};

// A file's first subimage as OpenImageIO describes it.
struct OiioHeader {
    Roi data, display;
    std::vector<std::string> channels;
    int alpha_channel = -1;
    bool deep = false;
    bool floating_point = false;
    bool unassociated_alpha = false;  // oiio:UnassociatedAlpha
    std::string colorspace;           // oiio:ColorSpace ("" when absent)
    Metadata attributes;              // every other attribute, as read_image keeps them
};

struct OiioModuleApi {
    int abi = kOiioModuleAbi;
    const char* version = nullptr;  // GDOF_VERSION_STRING of the module's build
    std::size_t sizes[4] = {};      // sizeof ImageSet, Image, Metadata, WriteOptions

    Result<ImageSet> (*read)(const std::string& path, std::vector<OiioPartInfo>& info) = nullptr;
    Status (*write)(const std::string& file, const std::string& display, const Image& image,
                    const WriteOptions& opts) = nullptr;
    // Clears OIIO's per-thread error message.
    void (*clear_error)() = nullptr;
    // The header only (ImageInput): "'<path>': cannot read the header (...)" on failure.
    Result<OiioHeader> (*header)(const std::string& path) = nullptr;

    // The process's one ImageCache (stack references, read tile by tile).
    void (*cache_configure)(double max_memory_mb, int strip_rows) = nullptr;
    int (*cache_files_opened)() = nullptr;  // OIIO's stat:unique_files
    // The file's header through the cache; the error text is OIIO's.
    Result<OiioHeader> (*cache_header)(const std::string& path) = nullptr;
    // Channels [chbegin, chend) of the file's pixels [x0, x1) x [y0, y1) (file
    // coordinates), interleaved floats; the error text is OIIO's.
    Status (*cache_read)(const std::string& path, const Roi& pixels, int chbegin, int chend, float* out) = nullptr;
    // Drops the file's tiles and handle.
    void (*cache_release)(const std::string& path) = nullptr;
};

}  // namespace gdof::io::detail

// The module's one exported symbol.
extern "C" {
using GdofOiioModuleEntry = const gdof::io::detail::OiioModuleApi* (*)();
}
#define GDOF_OIIO_MODULE_ENTRY "gdof_oiio_module_api"
