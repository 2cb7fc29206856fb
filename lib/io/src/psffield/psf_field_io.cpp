// PSF-field files with their blend weights' masks (gdof/io/psf_field_io.h).
#include "gdof/io/psf_field_io.h"

#include "blurfield/field_file.h"
#include "gdof/io/blur_field_io.h"

namespace gdof::io {

Result<PsfField> parse_psf_field(const std::string& json_text, const std::string& base_dir) {
    return PsfField::parse(json_text, blur_field_context(base_dir));
}

Result<PsfField> read_psf_field(const std::string& path) { return read_field_file(path, parse_psf_field); }

}  // namespace gdof::io
