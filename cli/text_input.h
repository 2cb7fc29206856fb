// The text of a file a flag names (--blurfield, --surfaces, --stack JSON).
#pragma once

#include <string>

namespace gdof::cli {

// The whole file (gdof::read_text); a runtime error otherwise, worded
// "FLAG: WHAT 'path' not found" or "FLAG: <the library's message>".
std::string read_flag_file(const std::string& flag, const std::string& what, const std::string& path);

}  // namespace gdof::cli
