// Small file helpers: quoting names for messages, extensions, format sniffing.
#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>

#include "files/files.h"

namespace gdof::io::detail {

std::string quoted(const std::string& path) { return "'" + path + "'"; }

std::string lower(std::string text) {
    std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return text;
}

std::string extension_lower(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    if (!ext.empty() && ext[0] == '.') ext.erase(0, 1);
    return lower(ext);
}

bool has_exr_magic(const std::string& path) {
    std::FILE* f = std::fopen(path.c_str(), "rb");
    if (!f) return false;
    unsigned char m[4] = {0, 0, 0, 0};
    std::size_t n = std::fread(m, 1, 4, f);
    std::fclose(f);
    return n == 4 && m[0] == 0x76 && m[1] == 0x2f && m[2] == 0x31 && m[3] == 0x01;
}

}  // namespace gdof::io::detail
