// PSF-field files (docs/psf_field.md) with the image_map masks of their blend
// weights read from disk: PsfField::parse does no file I/O; this gives it the
// blur-field context (masks read as data, relative to the JSON's folder).
// The CLI's --psf-field, the OFX parameter psf_field and the Python module's
// PsfField.read all come through here.
#pragma once

#include <string>

#include "gdof/export.h"
#include "gdof/psf_field.h"
#include "gdof/status.h"

namespace gdof::io {

// Parses JSON text (PsfField::parse) with image_map paths relative to base_dir.
GDOF_API Result<PsfField> parse_psf_field(const std::string& json_text, const std::string& base_dir);
// Reads a PSF-field file: read_text's errors ("'f.json' not found") and
// PsfField::parse's (naming the key path), each prefixed with the path.
GDOF_API Result<PsfField> read_psf_field(const std::string& path);

}  // namespace gdof::io
