// Blur-field files: the JSON of docs/blur_field.md with its image_map masks
// read from disk. The core's BlurField::parse does no file I/O; this gives it
// a Context whose images are read with io::read_flat, without colour
// conversion (a painted mask is data), relative to the JSON's folder.
#pragma once

#include <string>

#include "gdof/blur_field.h"
#include "gdof/export.h"
#include "gdof/status.h"

namespace gdof::io {

// The context an image_map resolves its "image" paths in: files relative to
// base_dir, read as data (no linearisation).
GDOF_API BlurField::Context blur_field_context(const std::string& base_dir);
// Parses JSON text (BlurField::parse) with image_map paths relative to base_dir.
GDOF_API Result<BlurField> parse_blur_field(const std::string& json_text, const std::string& base_dir);
// Reads a blur-field file: its text (read_text's errors: "'f.json' not
// found") and BlurField::parse's errors, each prefixed with the path.
GDOF_API Result<BlurField> read_blur_field(const std::string& path);

}  // namespace gdof::io
