// Public entry points of the image I/O layer: dispatch by format (OpenEXR
// directly, everything else through OIIO), colour at the edges, atomic writes.
#include "gdof/io/image_io.h"

#include <filesystem>
#include <fstream>

#include "exr/exr_io.h"
#include "oiio/oiio_io.h"
#include "colour/linearize.h"
#include "files/files.h"

namespace gdof::io {

namespace fs = std::filesystem;
using namespace detail;

namespace {

// The space an OIIO-read part is in: explicit option, else the file's
// oiio:ColorSpace when the config knows it, else sRGB for integer data and
// linear for float data.
std::string source_space(const Image& img, const OiioPartInfo& info, const ReadOptions& opts,
                         const ColourConfig& config) {
    if (!opts.colorspace.empty()) return opts.colorspace;
    if (auto cs = img.metadata.get_string("oiio:ColorSpace"); cs && !cs->empty() && !config.resolve(*cs).empty())
        return *cs;
    return info.integer_data ? "sRGB" : "linear";
}

}  // namespace

Result<ImageSet> read_image(const std::string& path, const ReadOptions& opts) {
    clear_oiio_error();
    std::error_code ec;
    if (path.empty()) return Status::error("no file name given");
    if (!fs::exists(path, ec)) return Status::error(quoted(path) + ": file not found");
    if (fs::is_directory(path, ec)) return Status::error(quoted(path) + ": is a folder, not an image file");

    const bool exr = has_exr_magic(path);
    if (!exr && extension_lower(path) == "exr")
        return Status::error(quoted(path) + ": file is truncated or corrupt (no OpenEXR magic number)");

    if (exr) {
        auto r = read_exr(path);
        if (!r || !opts.linearize || opts.colorspace.empty()) return r;
        // EXR is scene-linear unless the caller names its space.
        const ColourConfig& config = config_or_default(opts.colour);
        ImageSet& set = r.value();
        for (auto& part : set.parts) {
            if (auto* img = std::get_if<Image>(&part)) {
                if (Status s = linearize(*img, opts.colorspace, config, path); !s) return s;
            } else {
                auto& deep = std::get<DeepImage>(part);
                if (config.resolve(opts.colorspace).empty())
                    return Status::error(quoted(path) + ": unknown colour space '" + opts.colorspace + "'");
                if (!config.is_linear(opts.colorspace)) {
                    Status s = config.convert(deep, opts.colorspace, kWorkingSpace);
                    if (!s) return s.prefix(quoted(path));
                }
                deep.metadata.set_string("oiio:ColorSpace", "linear");
            }
        }
        return r;
    }

    std::vector<OiioPartInfo> info;
    auto r = read_oiio(path, info);
    if (!r) return r;
    ImageSet& set = r.value();
    for (std::size_t i = 0; i < set.size(); ++i) {
        Image& img = set.flat(i);
        if (opts.linearize) {
            const ColourConfig& config = config_or_default(opts.colour);
            if (Status s = linearize(img, source_space(img, info[i], opts, config), config, path); !s) return s;
        }
        if (info[i].alpha_channel >= 0 && info[i].unassociated_alpha) premultiply(img, info[i].alpha_channel);
    }
    return r;
}

Status write_image(const std::string& path, const ImageSet& images, const WriteOptions& opts) {
    clear_oiio_error();
    if (path.empty()) return Status::error("no output file name given");
    if (images.empty()) return Status::error(quoted(path) + ": nothing to write (no image)");
    const std::string ext = extension_lower(path);
    if (ext == "exr")
        return atomic_write(
            path, [&](const std::string& tmp) { return write_exr(tmp, path, part_refs(images), opts); }, opts.cancelled);

    if (images.size() > 1)
        return Status::error(quoted(path) + ": " + std::to_string(images.size()) +
                             " parts can only be written to an OpenEXR (.exr) file");
    if (images.is_deep(0))
        return Status::error(quoted(path) + ": deep images can only be written to an OpenEXR (.exr) file");
    return atomic_write(
        path, [&](const std::string& tmp) { return write_oiio(tmp, path, images.flat(0), opts); }, opts.cancelled);
}

Result<Image> read_flat(const std::string& path, const ReadOptions& opts) {
    auto r = read_image(path, opts);
    if (!r) return r.status();
    if (r->empty()) return Status::error(quoted(path) + ": file holds no image");
    if (r->is_deep(0))
        return Status::error(quoted(path) + ": holds a deep image where a flat image was expected");
    return std::move(r->flat(0));
}

Status write_flat(const std::string& path, const Image& image, const WriteOptions& opts) {
    clear_oiio_error();
    if (path.empty()) return Status::error("no output file name given");
    if (extension_lower(path) == "exr") {
        std::vector<PartRef> refs{PartRef(&image)};
        return atomic_write(
            path, [&](const std::string& tmp) { return write_exr(tmp, path, refs, opts); }, opts.cancelled);
    }
    return atomic_write(
        path, [&](const std::string& tmp) { return write_oiio(tmp, path, image, opts); }, opts.cancelled);
}

Status check_output_path(const std::string& path) { return check_target(path); }

Status write_text(const std::string& path, const std::string& text) {
    return detail::atomic_write(path, [&](const std::string& tmp) -> Status {
        std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
        out << text;
        out.flush();
        if (!out) return Status::error(detail::quoted(path) + ": cannot write '" + tmp + "'");
        return {};
    });
}

}  // namespace gdof::io
