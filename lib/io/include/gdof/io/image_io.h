// Reading and writing image files (gdof::io, via OpenEXR / OpenImageIO; the
// latter is loaded on the first file in another format: lib/io/src/oiio).
//
// - EXR: single-part flat (multilayer "layer.channel" names kept as they are),
//   multipart (one ImageSet part per file part, part names and views kept),
//   deep scanline and deep tiled (every sample kept). half/float/uint channel
//   types, data and display windows, tiling and compression, and every header
//   attribute (camera: worldToCamera, worldToNDC; lens: focalLength, aperture
//   / fNumber, focusDistance ...) survive a round trip.
// - PNG/JPEG/TIFF/... in (and out) as OIIO allows. Integer images become
//   float; colour is converted to scene-linear on read (see colour.h).
// - Writes are atomic: a temporary file beside the target, renamed on success;
//   on any failure no file is left at the target path.
//
// Details:
// - EXR goes through OpenEXR directly (exact attribute names and types, see
//   lib/io/src/exr_attributes.h for the type strings; unknown attribute types
//   such as idManifest are kept as raw bytes, type "uint8[N]", text
//   "exr:<type>"). Channels are ordered R,G,B,A first within each layer.
// - OpenEXR cannot store an empty data window: such a part is written as one
//   zero pixel (or zero-sample deep pixel) with the int attribute
//   "gdof:emptyDataWindow" and read back empty.
// - The parts of a multipart EXR share one display window (an error otherwise).
// - Only level 0 of mip/rip-mapped tiled EXRs is read; subsampled channels
//   are an error. Deep parts allow none/rle/zips/zip (others become zips).
// - Non-EXR: colour is unpremultiplied/premultiplied around the sRGB
//   conversion where the format stores straight alpha; formats without a data
//   window get the display window's pixels (zero outside the data window).
#pragma once

#include <string>

#include "gdof/export.h"
#include "gdof/image_set.h"
#include "gdof/io/colour.h"
#include "gdof/io/io_options.h"
#include "gdof/status.h"

namespace gdof::io {


GDOF_API Result<ImageSet> read_image(const std::string& path, const ReadOptions& opts = {});
GDOF_API Status write_image(const std::string& path, const ImageSet& images, const WriteOptions& opts = {});

// Convenience for single flat images: read_flat returns the first part (an
// error if it is deep); write_flat writes without copying the image.
GDOF_API Result<Image> read_flat(const std::string& path, const ReadOptions& opts = {});
GDOF_API Status write_flat(const std::string& path, const Image& image, const WriteOptions& opts = {});

// That an output file can be written, before the work that makes it: its
// folder exists and is writable and the name is not a folder. write_image
// checks the same; this lets a caller fail before a long computation.
GDOF_API Status check_output_path(const std::string& path);

// A text file (a stack manifest, JSON) written atomically like the images:
// a temporary file beside the target, renamed over it on success.
GDOF_API Status write_text(const std::string& path, const std::string& text);

// Human-readable description of a file's contents for `gdof --info`:
// parts, layers and channels with types, windows, deep sample statistics,
// camera and lens attributes.
GDOF_API std::string describe(const ImageSet& images, const std::string& path, bool verbose);

}  // namespace gdof::io
