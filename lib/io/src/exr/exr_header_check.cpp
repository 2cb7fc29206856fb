#include "exr/exr_header_check.h"

#include <fstream>

namespace gdof::io::detail {

namespace {

constexpr std::uint32_t kMagic = 20000630;
constexpr std::uint32_t kMultipartFlag = 0x1000;
constexpr std::size_t kMaxName = 255;  // OpenEXR's long attribute names

// A null-terminated string of at most kMaxName characters; false at EOF or if longer.
bool read_name(std::ifstream& in, std::string& s) {
    s.clear();
    for (char c; in.get(c);) {
        if (c == '\0') return true;
        if (s.size() >= kMaxName) return false;
        s.push_back(c);
    }
    return false;
}

}  // namespace

Status check_exr_header_sizes(const std::string& path, std::uint64_t file_size) {
    std::ifstream in(path, std::ios::binary);
    unsigned char head[8];
    if (!in.read(reinterpret_cast<char*>(head), 8)) return Status::ok();
    const std::uint32_t magic = head[0] | head[1] << 8 | head[2] << 16 | std::uint32_t(head[3]) << 24;
    if (magic != kMagic) return Status::ok();
    const std::uint32_t flags = head[5] | head[6] << 8 | std::uint32_t(head[7]) << 16;
    const bool multipart = (flags & kMultipartFlag) != 0;
    const std::string where = "'" + path + "': file is truncated or corrupt (";
    for (int part = 0;; ++part) {
        std::string name, type;
        int attributes = 0;
        for (;; ++attributes) {
            if (!read_name(in, name)) return Status::error(where + "header " + std::to_string(part) + " is cut short)");
            if (name.empty()) break;  // end of this header
            if (!read_name(in, type)) return Status::error(where + "attribute '" + name + "' has no type)");
            unsigned char sz[4];
            if (!in.read(reinterpret_cast<char*>(sz), 4)) return Status::error(where + "attribute '" + name + "' is cut short)");
            const std::int32_t size = std::int32_t(sz[0] | sz[1] << 8 | sz[2] << 16 | std::uint32_t(sz[3]) << 24);
            const std::uint64_t at = std::uint64_t(in.tellg());
            if (size < 0 || std::uint64_t(size) > file_size - at)
                return Status::error(where + "header attribute '" + name + "' of type " + type + " declares " +
                                     std::to_string(size) + " bytes, more than the " + std::to_string(file_size - at) +
                                     " left in the file)");
            in.seekg(size, std::ios::cur);
        }
        // A single-part file has one header; a multipart file's list ends with an empty one.
        if (!multipart || attributes == 0) return Status::ok();
    }
}

}  // namespace gdof::io::detail
