#include "exr/exr_common.h"

#include <algorithm>
#include <cctype>
#include <mutex>

#include <OpenEXR/ImfAttribute.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfIDManifestAttribute.h>
#include <OpenEXR/ImfThreading.h>
#include <tbb/global_control.h>

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

namespace {
std::mutex pool_mutex;
int files_in_flight = 0;  // under pool_mutex
}  // namespace

ExrThreads::ExrThreads() {
    const std::lock_guard<std::mutex> lock(pool_mutex);
    if (files_in_flight == 0) {
        // One thread: no workers (the calling thread does everything).
        const int n = exr_thread_count();
        const int workers = n > 1 ? n : 0;
        if (Imf::globalThreadCount() != workers) Imf::setGlobalThreadCount(workers);
    }
    ++files_in_flight;
}

ExrThreads::~ExrThreads() {
    const std::lock_guard<std::mutex> lock(pool_mutex);
    if (--files_in_flight > 0) return;
    try {
        if (Imf::globalThreadCount() != 0) Imf::setGlobalThreadCount(0);
    } catch (...) {  // the pool keeps its threads; nothing else depends on it
    }
}

#if defined(__SANITIZE_THREAD__)
#define GDOF_EXR_SINGLE_THREADED 1
#elif defined(__has_feature)
#if __has_feature(thread_sanitizer)
#define GDOF_EXR_SINGLE_THREADED 1
#endif
#endif

int exr_thread_count() {
#ifdef GDOF_EXR_SINGLE_THREADED
    // ThreadSanitizer cannot see the synchronisation inside Debian's
    // (uninstrumented) OpenEXR pool: files stay on the calling thread.
    return 1;
#else
    // TBB's limit for the process: all cores, or --threads (a global_control).
    const std::size_t n = tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism);
    return int(std::clamp<std::size_t>(n, 1, 16));
#endif
}

}  // namespace gdof::io::detail
