// read_text (text_file.h).
#include "gdof/text_file.h"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace gdof {

Result<std::string> read_text(const std::string& path) {
    namespace fs = std::filesystem;
    std::error_code ec;
    const std::string q = "'" + path + "'";
    if (!fs::exists(path, ec)) return Status::error(q + " not found", StatusCode::NotFound);
    if (fs::is_directory(path, ec)) return Status::error(q + " is a folder", StatusCode::Io);
    std::ifstream in(path, std::ios::binary);
    if (!in) return Status::error(q + ": cannot read (" + std::string(std::strerror(errno)) + ")", StatusCode::Io);
    std::ostringstream ss;
    ss << in.rdbuf();
    if (in.bad()) return Status::error(q + ": cannot read (read error)", StatusCode::Io);
    return ss.str();
}

Result<std::string> read_text(const std::string& path, const std::string& what) {
    Result<std::string> text = read_text(path);
    if (!text) return Status::error(what + " " + text.message(), text.status().code(), text.status().subject());
    return text;
}

}  // namespace gdof
