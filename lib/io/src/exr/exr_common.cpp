#include "exr/exr_common.h"

#include <algorithm>
#include <cctype>
#include <mutex>
#include <thread>

#include <OpenEXR/ImfAttribute.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfIDManifestAttribute.h>

namespace gdof::io::detail {

namespace {
struct Named {
    const char* name;
    Imf::Compression c;
};
constexpr Named kCompressions[] = {
    {"none", Imf::NO_COMPRESSION}, {"rle", Imf::RLE_COMPRESSION},     {"zips", Imf::ZIPS_COMPRESSION},
    {"zip", Imf::ZIP_COMPRESSION}, {"piz", Imf::PIZ_COMPRESSION},     {"pxr24", Imf::PXR24_COMPRESSION},
    {"b44", Imf::B44_COMPRESSION}, {"b44a", Imf::B44A_COMPRESSION},   {"dwaa", Imf::DWAA_COMPRESSION},
    {"dwab", Imf::DWAB_COMPRESSION}};
}  // namespace

std::string compression_name(Imf::Compression c) {
    for (const auto& n : kCompressions)
        if (n.c == c) return n.name;
    return "unknown";
}

bool parse_compression(const std::string& text, Imf::Compression& c, double& level) {
    std::string name = text;
    level = -1;
    auto colon = text.find(':');
    if (colon != std::string::npos) {
        name = text.substr(0, colon);
        try {
            std::size_t used = 0;
            level = std::stod(text.substr(colon + 1), &used);
            if (used != text.size() - colon - 1) return false;
        } catch (...) {
            return false;
        }
    }
    std::transform(name.begin(), name.end(), name.begin(), [](unsigned char ch) { return char(std::tolower(ch)); });
    for (const auto& n : kCompressions)
        if (name == n.name) {
            c = n.c;
            return true;
        }
    return false;
}

void ensure_exr_setup() {
    static std::once_flag once;
    std::call_once(once, [] {
        Imf::staticInitialize();
        if (Imf::Attribute::knownType("idmanifest")) Imf::IDManifestAttribute::unRegisterAttributeType();
    });
}

int exr_thread_count() {
    unsigned n = std::thread::hardware_concurrency();
    return int(std::clamp(n, 1u, 16u));
}

}  // namespace gdof::io::detail
