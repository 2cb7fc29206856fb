// How images are read and written (read_image / write_image, image_io.h):
// colour conversion at the edges, storage types and compression.
#pragma once

#include <functional>
#include <string>

namespace gdof::io {

class ColourConfig;  // colour.h

struct ReadOptions {
    // Convert colour channels to the working space (scene-linear) on read.
    // The source space comes from `colorspace` if set, else file metadata
    // (oiio:ColorSpace), else by format: 8/16-bit PNG/JPEG/TIFF are sRGB,
    // EXR/HDR/float TIFF are linear.
    bool linearize = true;
    std::string colorspace;
    const ColourConfig* colour = nullptr;  // nullptr: ColourConfig::default_config()
};

struct WriteOptions {
    // Channel storage type for float channels: "" keeps each channel's type
    // (Half stays half, Float stays float), else "half" or "float" for all
    // (UInt stays uint). For non-EXR formats also "uint8" / "uint16"; ""
    // there means 8-bit, or 16-bit when oiio:BitsPerSample says 16 (16-bit
    // PNG in, 16-bit PNG out), float for HDR.
    std::string pixel_type;
    std::string compression;  // "" keeps the image's StorageHints, else OIIO name
    // Output colour space for display-referred formats (PNG/JPEG/8-bit TIFF):
    // "" means sRGB for those formats and linear (no conversion) for EXR.
    std::string colorspace;
    const ColourConfig* colour = nullptr;
    // Polled once the temporary file is complete: true drops it instead of
    // renaming it over the target (a signal came during the write).
    std::function<bool()> cancelled;
};

}  // namespace gdof::io
