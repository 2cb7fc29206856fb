// Reading every non-EXR format through OpenImageIO's ImageInput: whole
// subimages in one call as float (8/16-bit integers normalised to 0..1 by
// OIIO), de-interleaved into planes; spec attributes into Metadata.
#include <cstdint>
#include <filesystem>
#include <new>

#include <Imath/half.h>
#include <OpenImageIO/imageio.h>

#include "oiio_module/oiio_module.h"
#include "files/files.h"

namespace gdof::io::oiio_module {

using detail::quoted;

namespace {

bool skipped_oiio_attribute(const std::string& name) {
    // Bookkeeping that describes the file rather than the image, or that the
    // model keeps elsewhere (compression -> StorageHints).
    return name == "oiio:subimages" || name == "openexr:chunkCount" || name == "oiio:UnassociatedAlpha" ||
           name == "compression";
}

double element(const OIIO::ParamValue& p, OIIO::TypeDesc::BASETYPE bt, std::size_t i) {
    const void* d = p.data();
    switch (bt) {
        case OIIO::TypeDesc::UINT8: return double(static_cast<const std::uint8_t*>(d)[i]);
        case OIIO::TypeDesc::INT8: return double(static_cast<const std::int8_t*>(d)[i]);
        case OIIO::TypeDesc::UINT16: return double(static_cast<const std::uint16_t*>(d)[i]);
        case OIIO::TypeDesc::INT16: return double(static_cast<const std::int16_t*>(d)[i]);
        case OIIO::TypeDesc::UINT32: return double(static_cast<const std::uint32_t*>(d)[i]);
        case OIIO::TypeDesc::INT32: return double(static_cast<const std::int32_t*>(d)[i]);
        case OIIO::TypeDesc::UINT64: return double(static_cast<const std::uint64_t*>(d)[i]);
        case OIIO::TypeDesc::INT64: return double(static_cast<const std::int64_t*>(d)[i]);
        case OIIO::TypeDesc::HALF: return double(float(static_cast<const Imath::half*>(d)[i]));
        case OIIO::TypeDesc::FLOAT: return double(static_cast<const float*>(d)[i]);
        case OIIO::TypeDesc::DOUBLE: return static_cast<const double*>(d)[i];
        default: return 0.0;
    }
}

}  // namespace

void clear_error() { (void)OIIO::geterror(); }

void spec_to_metadata(const OIIO::ImageSpec& spec, Metadata& md) {
    for (const auto& p : spec.extra_attribs) {
        std::string name = p.name().string();
        if (skipped_oiio_attribute(name)) continue;
        const OIIO::TypeDesc t = p.type();
        Attribute a;
        a.name = name;
        a.type = t.c_str();
        const std::size_t n = std::size_t(t.basevalues()) * std::size_t(std::max(1, p.nvalues()));
        if (t.basetype == OIIO::TypeDesc::STRING) {
            for (std::size_t i = 0; i < n; ++i) {
                if (i) a.text.push_back('\0');
                a.text += p.get_string_indexed(int(i));
            }
        } else if (t.basetype == OIIO::TypeDesc::PTR || t.basetype == OIIO::TypeDesc::UNKNOWN ||
                   t.basetype == OIIO::TypeDesc::NONE) {
            continue;
        } else {
            a.numbers.reserve(n);
            for (std::size_t i = 0; i < n; ++i) a.numbers.push_back(element(p, OIIO::TypeDesc::BASETYPE(t.basetype), i));
        }
        md.set(std::move(a));
    }
}

Result<ImageSet> read(const std::string& path, std::vector<OiioPartInfo>& info) {
    clear_error();
    std::error_code ec;
    const std::uint64_t file_size = std::filesystem::file_size(path, ec);
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);  // straight colour: linearised before premultiplying
    auto in = OIIO::ImageInput::open(path, &config);
    if (!in) {
        std::string e = OIIO::geterror();
        return Status::error(quoted(path) + ": unknown or unreadable image format" +
                             (e.empty() ? std::string() : " (OpenImageIO: " + e + ")"));
    }
    ImageSet set;
    info.clear();
    try {
        for (int s = 0;; ++s) {
            if (s > 0 && !in->seek_subimage(s, 0)) break;
            const OIIO::ImageSpec spec = in->spec();
            if (spec.deep)
                return Status::error(quoted(path) + ": deep data is only supported in OpenEXR files");
            const int nch = spec.nchannels;
            if (nch <= 0 || spec.width <= 0 || spec.height <= 0 || spec.depth > 1)
                return Status::error(quoted(path) + ": unsupported image layout (" + std::to_string(nch) +
                                     " channels, " + std::to_string(spec.width) + "x" + std::to_string(spec.height) +
                                     "x" + std::to_string(spec.depth) + ")");
            const Roi data{spec.x, spec.y, spec.x + spec.width, spec.y + spec.height};
            Roi display{spec.full_x, spec.full_y, spec.full_x + spec.full_width, spec.full_y + spec.full_height};
            if (display.empty()) display = data;
            const std::uint64_t bytes = std::uint64_t(data.npixels()) * std::uint64_t(nch) * 4u;
            if (ec || bytes > file_size * 4096ull + (std::uint64_t(64) << 20))
                return Status::error(quoted(path) + ": file is truncated or corrupt (implausible image size)");

            std::vector<ChannelSpec> chans;
            for (int c = 0; c < nch; ++c) {
                std::string cname = c < int(spec.channelnames.size()) ? spec.channelnames[std::size_t(c)]
                                                                     : "channel" + std::to_string(c);
                chans.push_back({cname, spec.channelformat(c) == OIIO::TypeHalf ? PixelType::Half : PixelType::Float});
            }
            Image img(chans, data, display);
            std::vector<float> buf(data.npixels() * std::size_t(nch));
            if (!in->read_image(s, 0, 0, nch, OIIO::TypeFloat, buf.data())) {
                std::string e = in->geterror();
                clear_error();
                return Status::error(quoted(path) + ": file is truncated or corrupt (OpenImageIO: " + e + ")");
            }
            const std::size_t np = data.npixels();
            for (int c = 0; c < nch; ++c) {
                float* dst = img.plane(c);
                const float* src = buf.data() + c;
                for (std::size_t i = 0; i < np; ++i) dst[i] = src[i * std::size_t(nch)];
            }
            spec_to_metadata(spec, img.metadata);
            OiioPartInfo pi;
            pi.integer_data = !spec.format.is_floating_point();
            pi.alpha_channel = spec.alpha_channel;
            pi.unassociated_alpha = spec.get_int_attribute("oiio:UnassociatedAlpha", 0) != 0;
            if (pi.integer_data && !img.metadata.has("oiio:BitsPerSample"))
                img.metadata.set_int("oiio:BitsPerSample", (long long)(spec.format.size() * 8));
            img.storage.format = in->format_name();
            img.storage.compression = spec.get_string_attribute("compression");
            img.storage.tile_width = spec.tile_width;
            img.storage.tile_height = spec.tile_height;
            info.push_back(pi);
            set.parts.push_back(std::move(img));
        }
    } catch (const std::bad_alloc&) {
        clear_error();
        return Status::error(quoted(path) + ": out of memory while reading");
    } catch (const std::exception& e) {
        clear_error();
        return Status::error(quoted(path) + ": cannot read (" + std::string(e.what()) + ")");
    }
    in->close();
    clear_error();
    if (set.parts.empty()) return Status::error(quoted(path) + ": file holds no image");
    return set;
}

}  // namespace gdof::io::oiio_module
