// Finds and opens the OpenImageIO module once, on first use, and forwards
// to it. Where it looks, in order:
//   1. $GDOF_OIIO_MODULE, when set: that file only (packagers, tests);
//   2. beside the binary holding this code (the shared library, the Python
//      extension or the OFX bundle's gdof.ofx; an installed tree keeps the
//      module there);
//   3. the install tree's library folder seen from the executables' folder
//      (a statically linked `gdof` in bin/, the module in lib/);
//   4. the library folder of the prefix this build was configured for (a
//      program linking the static libraries, installed elsewhere);
//   5. where this build put it (the build tree: tests, benchmarks).
// The module is never closed: OIIO keeps threads and caches until exit.
#include <dlfcn.h>

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <filesystem>

#include "oiio/oiio_io.h"
#include "colour/linearize.h"
#include "files/files.h"

namespace gdof::io::detail {

namespace {

namespace fs = std::filesystem;

constexpr const char* kModuleFile = "gdof_oiio.so";

// The table, checked against this build; "" when it matches.
std::string mismatch(const OiioModuleApi* api) {
    if (!api) return "its entry point returned nothing";
    if (api->abi != kOiioModuleAbi)
        return "interface " + std::to_string(api->abi) + ", expected " + std::to_string(kOiioModuleAbi);
    if (!api->version || std::string(api->version) != GDOF_VERSION_STRING)
        return std::string("built for gdof ") + (api->version ? api->version : "?") + ", this is " + GDOF_VERSION_STRING;
    const std::size_t sizes[4] = {sizeof(ImageSet), sizeof(Image), sizeof(Metadata), sizeof(WriteOptions)};
    for (int i = 0; i < 4; ++i)
        if (api->sizes[i] != sizes[i]) return "built from other sources (type sizes differ)";
    return "";
}

struct Candidate {
    std::string path, why;  // why: "" or where the name came from
};

std::vector<Candidate> candidates() {
    if (const char* env = std::getenv("GDOF_OIIO_MODULE"); env && *env) return {{env, " (GDOF_OIIO_MODULE)"}};
    std::vector<Candidate> out;
    Dl_info info{};
    if (dladdr(reinterpret_cast<void*>(&oiio_module), &info) && info.dli_fname && *info.dli_fname) {
        std::error_code ec;
        fs::path self = fs::canonical(info.dli_fname, ec);
        if (ec) self = info.dli_fname;
        const fs::path dir = self.parent_path();
        out.push_back({(dir / kModuleFile).string(), ""});
#ifdef GDOF_OIIO_MODULE_FROM_BINDIR
        out.push_back({(dir / GDOF_OIIO_MODULE_FROM_BINDIR / kModuleFile).lexically_normal().string(), ""});
#endif
    }
#ifdef GDOF_OIIO_MODULE_INSTALL_PATH
    out.push_back({GDOF_OIIO_MODULE_INSTALL_PATH, ""});
#endif
#ifdef GDOF_OIIO_MODULE_BUILD_PATH
    out.push_back({GDOF_OIIO_MODULE_BUILD_PATH, " (this build's)"});
#endif
    // Each place once (in the build tree, cli/../lib is the build's).
    std::vector<Candidate> unique;
    for (Candidate& c : out)
        if (std::none_of(unique.begin(), unique.end(), [&](const Candidate& u) { return u.path == c.path; }))
            unique.push_back(std::move(c));
    return unique;
}

Result<const OiioModuleApi*> load() {
    std::string tried;
    for (const auto& [path, why] : candidates()) {
        std::error_code ec;
        if (!tried.empty()) tried += "; ";
        tried += "'" + path + "'" + why + ": ";
        if (!fs::exists(path, ec)) {
            tried += "not found";
            continue;
        }
        void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
        if (!handle) {
            const char* e = dlerror();
            tried += e ? e : "cannot be loaded";
            continue;
        }
        auto entry = reinterpret_cast<GdofOiioModuleEntry>(dlsym(handle, GDOF_OIIO_MODULE_ENTRY));
        const OiioModuleApi* api = entry ? entry() : nullptr;
        const std::string problem = entry ? mismatch(api) : std::string("no entry point " GDOF_OIIO_MODULE_ENTRY);
        if (problem.empty()) return api;
        dlclose(handle);
        tried += problem;
    }
    return Status::error("gdof's OpenImageIO module (" + std::string(kModuleFile) +
                         ", needed for every format but EXR) did not load: " + tried);
}

// Set once the module has loaded.
std::atomic<const OiioModuleApi*> g_loaded{nullptr};

}  // namespace

Result<const OiioModuleApi*> oiio_module() {
    static const Result<const OiioModuleApi*> loaded = [] {
        Result<const OiioModuleApi*> r = load();
        if (r) g_loaded.store(*r);
        return r;
    }();
    return loaded;
}

namespace {

Status unavailable(const Result<const OiioModuleApi*>& m, const std::string& path) {
    Status s = m.status();
    return s.prefix(quoted(path));
}

}  // namespace

Result<ImageSet> read_oiio(const std::string& path, std::vector<OiioPartInfo>& info) {
    const auto m = oiio_module();
    if (!m) return unavailable(m, path);
    return (*m)->read(path, info);
}

Status write_oiio(const std::string& file, const std::string& display, const Image& image, const WriteOptions& opts) {
    const auto m = oiio_module();
    if (!m) return unavailable(m, display);
    if (opts.colour) return (*m)->write(file, display, image, opts);
    // This process's default colour config, not one the module (linking
    // its own copy of io_colour in a static build) would load again.
    WriteOptions with_config = opts;
    with_config.colour = &config_or_default(nullptr);
    return (*m)->write(file, display, image, with_config);
}

Result<OiioHeader> read_oiio_header(const std::string& path) {
    const auto m = oiio_module();
    if (!m) return m.status();
    return (*m)->header(path);
}

void clear_oiio_error() {
    // Before the module loads OIIO has no error to clear (and clearing must
    // not load it).
    if (const OiioModuleApi* m = g_loaded.load()) m->clear_error();
}

}  // namespace gdof::io::detail
