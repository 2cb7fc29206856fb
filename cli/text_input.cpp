// The text of a file a flag names (text_input.h).
#include "text_input.h"

#include "errors.h"
#include "gdof/text_file.h"

namespace gdof::cli {

std::string read_flag_file(const std::string& flag, const std::string& what, const std::string& path) {
    Result<std::string> text = gdof::read_text(path);
    if (text) return std::move(text).value();
    if (text.status().code() == StatusCode::NotFound) runtime_error(flag + ": " + what + " '" + path + "' not found");
    runtime_error(flag + ": " + text.message());
}

}  // namespace gdof::cli
