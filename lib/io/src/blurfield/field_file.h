// Reading a field file (a blur field, a PSF field): JSON whose image_map
// paths are relative to the file's folder. The text, the folder, the
// parser's result; every error prefixed with the path.
#pragma once

#include <filesystem>
#include <string>

#include "gdof/status.h"
#include "gdof/text_file.h"

namespace gdof::io {

// `parse(text, base_dir)` returns a Result<Field>.
template <class Parse>
auto read_field_file(const std::string& path, Parse parse) -> decltype(parse(std::string(), std::string())) {
    auto text = read_text(path);
    if (!text) return text.status();
    std::error_code ec;
    const std::string dir = std::filesystem::absolute(std::filesystem::path(path), ec).parent_path().string();
    auto field = parse(*text, dir);
    if (!field) {
        Status st = field.status();
        return st.prefix("'" + path + "'");
    }
    return field;
}

}  // namespace gdof::io
