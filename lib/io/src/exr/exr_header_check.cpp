#include "exr/exr_header_check.h"

#include <algorithm>
#include <fstream>
#include <vector>

namespace gdof::io::detail {

namespace {

constexpr std::uint32_t kMagic = 20000630;
constexpr std::uint32_t kSinglePartTiledFlag = 0x200;
constexpr std::uint32_t kMultipartFlag = 0x1000;
constexpr std::size_t kMaxName = 255;  // OpenEXR's long attribute names
// The most scan lines OpenEXR packs into one chunk (DWAB); fewer lines per
// chunk only mean more chunks, so this gives a lower bound on a part's count.
constexpr std::int64_t kMostLinesPerChunk = 256;

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

// The size of an attribute value of a fixed-size type, 0 for the others.
// OpenEXR reads such a value at its type's size whatever the header
// declares, and so reads the rest of the header from another place than the
// declared sizes say (an attribute found there declared 1.6 GB).
std::int32_t fixed_size(const std::string& type) {
    struct Known {
        const char* type;
        std::int32_t size;
    };
    static constexpr Known kKnown[] = {
        {"int", 4},       {"float", 4},        {"double", 8},        {"compression", 1}, {"lineOrder", 1},
        {"envmap", 1},    {"deepImageState", 1}, {"tiledesc", 9},    {"box2i", 16},      {"box2f", 16},
        {"v2i", 8},       {"v2f", 8},          {"v2d", 16},          {"v3i", 12},        {"v3f", 12},
        {"v3d", 24},      {"m33f", 36},        {"m33d", 72},         {"m44f", 64},       {"m44d", 128},
        {"chromaticities", 32}, {"keycode", 28}, {"timecode", 8},    {"rational", 8}};
    for (const Known& k : kKnown)
        if (type == k.type) return k.size;
    return 0;
}

std::uint32_t le32(const unsigned char* b) { return b[0] | b[1] << 8 | b[2] << 16 | std::uint32_t(b[3]) << 24; }

// The size an attribute's content gives, for the types OpenEXR reads by
// their content and not by the declared size: a channel list (names, each
// followed by 16 bytes, up to an empty name), a preview (width, height, then
// 4 bytes a pixel) and a string vector (strings, each after its length, until
// the declared size is reached or passed). -1 if the content does not fit in
// the file (a negative length included). Reads from the value's start; the caller seeks after.
std::int64_t content_size(std::ifstream& in, const std::string& type, std::int32_t declared, std::uint64_t left) {
    if (type == "chlist") {
        std::uint64_t used = 0;
        for (std::string channel;;) {
            if (!read_name(in, channel)) return -1;
            used += channel.size() + 1;
            if (channel.empty()) return std::int64_t(used);
            if (!in.seekg(16, std::ios::cur)) return -1;
            used += 16;
            if (used > left) return -1;
        }
    }
    if (type == "preview") {
        unsigned char wh[8];
        if (!in.read(reinterpret_cast<char*>(wh), 8)) return -1;
        const long double bytes = 8.0L + 4.0L * (long double)le32(wh) * (long double)le32(wh + 4);
        return bytes > (long double)left ? -1 : std::int64_t(bytes);
    }
    if (type == "stringvector") {
        std::int64_t used = 0;
        while (used < declared) {
            unsigned char n[4];
            if (!in.read(reinterpret_cast<char*>(n), 4)) return -1;
            const std::int32_t length = std::int32_t(le32(n));
            if (length < 0) return -1;  // OpenEXR would resize a string to it
            used += 4 + std::int64_t(length);
            if (std::uint64_t(used) > left || !in.seekg(length, std::ios::cur)) return -1;
        }
        return used;
    }
    return -1;
}

bool read_by_content(const std::string& type) { return type == "chlist" || type == "preview" || type == "stringvector"; }

// What the size checks need of one header. Values OpenEXR rejects itself (no
// data window, an empty one, a zero tile) are left to it.
struct PartLayout {
    std::string type;  // the "type" attribute, empty if none
    bool has_tiles = false;
    // A header without a data window reads as OpenEXR's default, 64 x 64
    // (a misspelt "dataWindow" gave a tile of 4 x 11337732 its row of tiles).
    std::int64_t width = 64, height = 64;
    std::uint32_t tile_x = 0, tile_y = 0;
};

// Reads the value of the attributes PartLayout needs; false if it is not one of them.
bool read_layout_value(std::ifstream& in, const std::string& name, const std::string& type, std::int32_t size,
                       PartLayout& part) {
    unsigned char v[64];
    if (name == "dataWindow" && type == "box2i" && size == 16) {
        if (!in.read(reinterpret_cast<char*>(v), size)) return false;
        const auto at = [&](int i) { return std::int64_t(std::int32_t(le32(&v[std::size_t(i) * 4]))); };
        part.width = at(2) - at(0) + 1;
        part.height = at(3) - at(1) + 1;
        return true;
    }
    if (name == "tiles" && type == "tiledesc" && size == 9) {
        if (!in.read(reinterpret_cast<char*>(v), size)) return false;
        part.tile_x = le32(&v[0]);
        part.tile_y = le32(&v[4]);
        part.has_tiles = true;
        return true;
    }
    if (name == "type" && type == "string" && size <= 64) {
        if (!in.read(reinterpret_cast<char*>(v), size)) return false;
        part.type.assign(reinterpret_cast<const char*>(v), std::size_t(size));
        return true;
    }
    return false;
}

// Whether OpenEXR will read the part as tiles: its type says so, or (a
// single-part file without a type) the version field does.
bool is_tiled(const PartLayout& part, bool single_part_tiled) {
    if (part.type == "tiledimage" || part.type == "deeptile") return true;
    if (part.type.empty()) return single_part_tiled;
    return false;
}

}  // namespace

Status check_exr_header_sizes(const std::string& path, std::uint64_t file_size) {
    std::ifstream in(path, std::ios::binary);
    unsigned char head[8];
    if (!in.read(reinterpret_cast<char*>(head), 8)) return Status::ok();
    if (le32(head) != kMagic) return Status::ok();
    // The version field: the version number in its low byte, the flags above.
    const std::uint32_t version = le32(head + 4);
    const bool multipart = (version & kMultipartFlag) != 0;
    const bool single_part_tiled = !multipart && (version & kSinglePartTiledFlag) != 0;
    const std::string where = "'" + path + "': file is truncated or corrupt (";
    std::vector<PartLayout> parts;
    for (int part = 0;; ++part) {
        PartLayout layout;
        std::string name, type;
        int attributes = 0;
        for (;; ++attributes) {
            if (!read_name(in, name)) return Status::error(where + "header " + std::to_string(part) + " is cut short)");
            if (name.empty()) break;  // end of this header
            if (!read_name(in, type)) return Status::error(where + "attribute '" + name + "' has no type)");
            unsigned char sz[4];
            if (!in.read(reinterpret_cast<char*>(sz), 4)) return Status::error(where + "attribute '" + name + "' is cut short)");
            const std::int32_t size = std::int32_t(le32(sz));
            const std::uint64_t at = std::uint64_t(in.tellg());
            if (size < 0 || std::uint64_t(size) > file_size - at)
                return Status::error(where + "header attribute '" + name + "' of type " + type + " declares " +
                                     std::to_string(size) + " bytes, more than the " + std::to_string(file_size - at) +
                                     " left in the file)");
            if (const std::int32_t fixed = fixed_size(type); fixed != 0 && size != fixed)
                return Status::error(where + "header attribute '" + name + "' of type " + type + " declares " +
                                     std::to_string(size) + " bytes, a " + type + " has " + std::to_string(fixed) + ")");
            if (read_by_content(type)) {
                // OpenEXR reads these by their content: where it ends is where
                // OpenEXR reads the next attribute's name from (a channel list
                // shorter than declared had it read a 1.7 GB "string" there).
                const std::int64_t used = content_size(in, type, size, file_size - at);
                if (used != size)
                    return Status::error(where + "header attribute '" + name + "' of type " + type + " declares " +
                                         std::to_string(size) + " bytes, its content " +
                                         (used < 0 ? std::string("does not fit in the file")
                                                   : "takes " + std::to_string(used)) + ")");
                in.clear();
                in.seekg(std::streamoff(at) + size);
            } else if (!read_layout_value(in, name, type, size, layout)) {
                in.seekg(std::streamoff(at) + size);
            }
        }
        // A single-part file has one header; a multipart file's list ends with an empty one.
        if (attributes > 0) parts.push_back(layout);
        if (!multipart || attributes == 0) break;
    }

    // Every chunk (a tile of level 0 at least, or a block of scan lines) has
    // an 8-byte offset in the tables after the headers; OpenEXR allocates the
    // tables, and each tile's buffers, from these numbers.
    const std::uint64_t after_headers = file_size - std::min<std::uint64_t>(file_size, std::uint64_t(in.tellg()));
    long double offsets = 0;
    for (std::size_t i = 0; i < parts.size(); ++i) {
        const PartLayout& p = parts[i];
        if (p.width <= 0 || p.height <= 0) continue;
        const std::string which = parts.size() > 1 ? "part " + std::to_string(i) + ": " : std::string();
        if (is_tiled(p, single_part_tiled)) {
            if (!p.has_tiles || p.tile_x == 0 || p.tile_y == 0) continue;
            const long double tile_bytes = (long double)p.tile_x * p.tile_y * 4;
            if (tile_bytes > (long double)decoded_bytes_limit(file_size))
                return Status::error(where + which + "a tile of " + std::to_string(p.tile_x) + " x " +
                                     std::to_string(p.tile_y) + " pixels cannot come from a file of " +
                                     std::to_string(file_size) + " bytes)");
            offsets += (long double)((p.width + p.tile_x - 1) / p.tile_x) * ((p.height + p.tile_y - 1) / p.tile_y);
        } else {
            offsets += (long double)((p.height + kMostLinesPerChunk - 1) / kMostLinesPerChunk);
        }
    }
    if (offsets * 8 > (long double)after_headers)
        return Status::error(where + "the headers' data windows need at least " +
                             std::to_string((unsigned long long)offsets) + " chunks, whose offsets alone take more than the " +
                             std::to_string(after_headers) + " bytes after the headers)");
    return Status::ok();
}

}  // namespace gdof::io::detail
