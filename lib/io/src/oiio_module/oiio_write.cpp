// Writing non-EXR formats (PNG, JPEG, TIFF, ...) through OpenImageIO's
// ImageOutput: pick the colour channels the format can hold, convert a copy
// from scene-linear to the output space, clamp and quantise, write.
#include <algorithm>
#include <cmath>
#include <cstdint>

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include "oiio_module/oiio_module.h"
#include "files/files.h"
#include "colour/linearize.h"

namespace gdof::io::oiio_module {

using namespace detail;

namespace {

bool starts_with(const std::string& s, const char* p) { return s.rfind(p, 0) == 0; }

// Copies the chosen channels over `roi` into a float image (zero outside the
// source data window; UInt channels converted to float).
Image gather(const Image& src, const std::vector<int>& chans, const std::vector<std::string>& names, const Roi& roi) {
    std::vector<ChannelSpec> specs;
    for (std::size_t i = 0; i < chans.size(); ++i) specs.push_back({names[i], PixelType::Float});
    Image out(specs, roi, roi);
    const Roi in = intersect(roi, src.data_window());
    if (in.empty()) return out;
    for (std::size_t i = 0; i < chans.size(); ++i) {
        const int c = chans[i];
        float* dst = out.plane(int(i));
        for (int y = in.y0; y < in.y1; ++y) {
            float* d = dst + out.offset(in.x0, y);
            const std::size_t o = src.offset(in.x0, y);
            const int w = in.width();
            if (const float* p = src.plane(c)) std::copy(p + o, p + o + std::size_t(w), d);
            else {
                const std::uint32_t* u = src.uplane(c);
                for (int x = 0; x < w; ++x) d[x] = float(u[o + std::size_t(x)]);
            }
        }
    }
    return out;
}

template <class T>
std::vector<T> quantise(const Image& img, double maxval) {
    const std::size_t np = img.npixels(), nch = std::size_t(img.nchannels());
    std::vector<T> buf(np * nch);
    for (std::size_t c = 0; c < nch; ++c) {
        const float* p = img.plane(int(c));
        for (std::size_t i = 0; i < np; ++i) {
            float v = p[i];
            v = std::isnan(v) ? 0.0f : std::clamp(v, 0.0f, 1.0f);
            buf[i * nch + c] = T(std::lround(double(v) * maxval));
        }
    }
    return buf;
}

std::vector<float> interleave(const Image& img) {
    const std::size_t np = img.npixels(), nch = std::size_t(img.nchannels());
    std::vector<float> buf(np * nch);
    for (std::size_t c = 0; c < nch; ++c) {
        const float* p = img.plane(int(c));
        for (std::size_t i = 0; i < np; ++i) buf[i * nch + c] = p[i];
    }
    return buf;
}

void metadata_to_spec(const Metadata& md, OIIO::ImageSpec& spec) {
    for (const auto& a : md.attributes()) {
        if (starts_with(a.name, "oiio:") || starts_with(a.name, "openexr:") || starts_with(a.name, "gdof:")) continue;
        OIIO::TypeDesc t(a.type);
        if (t.basetype == OIIO::TypeDesc::UNKNOWN) continue;
        if (t.basetype == OIIO::TypeDesc::STRING) {
            if (t.basevalues() == 1) spec.attribute(a.name, a.text);
            continue;
        }
        if (a.numbers.size() != t.basevalues() || a.numbers.empty()) continue;
        if (t.basetype == OIIO::TypeDesc::FLOAT || t.basetype == OIIO::TypeDesc::HALF) {
            std::vector<float> v(a.numbers.begin(), a.numbers.end());
            OIIO::TypeDesc tf = t;
            tf.basetype = OIIO::TypeDesc::FLOAT;
            spec.attribute(a.name, tf, v.data());
        } else if (t.basetype == OIIO::TypeDesc::DOUBLE) {
            spec.attribute(a.name, t, a.numbers.data());
        } else if (t.basetype == OIIO::TypeDesc::INT32 || t.basetype == OIIO::TypeDesc::UINT32) {
            std::vector<std::int32_t> v;
            for (double d : a.numbers) v.push_back(std::int32_t(std::llround(d)));
            spec.attribute(a.name, t, v.data());
        } else if (t.basetype == OIIO::TypeDesc::UINT8) {
            std::vector<std::uint8_t> v;
            for (double d : a.numbers) v.push_back(std::uint8_t(std::llround(d)));
            spec.attribute(a.name, t, v.data());
        } else if (t.basetype == OIIO::TypeDesc::UINT16) {
            std::vector<std::uint16_t> v;
            for (double d : a.numbers) v.push_back(std::uint16_t(std::llround(d)));
            spec.attribute(a.name, t, v.data());
        }
    }
}

// The channels written, by index into the image, their names in the file,
// and where alpha lands among them (-1: none).
struct ChannelChoice {
    std::vector<int> chans;
    std::vector<std::string> names;
    int alpha_out = -1;
};

// Channels the format can hold: R,G,B, else Y, else a lone channel, else all
// of them where the format takes any count; plus alpha where it takes one.
Result<ChannelChoice> choose_channels(const Image& image, const OIIO::ImageOutput& out, const std::string& display) {
    ChannelChoice c;
    const RgbaIndices rgba = find_rgba(image);
    if (rgba.r >= 0 && rgba.g >= 0 && rgba.b >= 0) {
        c.chans = {rgba.r, rgba.g, rgba.b};
        c.names = {"R", "G", "B"};
    } else if (int y = image.channel_index("Y"); y >= 0) {
        c.chans = {y};
        c.names = {"Y"};
    } else if (image.nchannels() == 1) {
        c.chans = {0};
        c.names = {image.channel(0).name};
    } else if (out.supports("nchannels")) {
        for (int i = 0; i < image.nchannels(); ++i) {
            c.chans.push_back(i);
            c.names.push_back(image.channel(i).name);
        }
    } else {
        return Status::error(quoted(display) + ": no R,G,B or Y channels to write to " + out.format_name() +
                             " (write EXR to keep all " + std::to_string(image.nchannels()) + " channels)");
    }
    if (rgba.a >= 0 && out.supports("alpha") && std::find(c.chans.begin(), c.chans.end(), rgba.a) == c.chans.end()) {
        c.alpha_out = int(c.chans.size());
        c.chans.push_back(rgba.a);
        c.names.push_back("A");
    }
    return c;
}

// The file's pixel type: the one asked for, else float for HDR formats,
// 16 bits where the source had them (not JPEG), else 8 bits.
Result<OIIO::TypeDesc> choose_pixel_type(const Image& image, const std::string& fmt, const WriteOptions& opts,
                                         const std::string& display) {
    const std::string& pt = opts.pixel_type;
    if (pt == "uint8") return OIIO::TypeUInt8;
    if (pt == "uint16") return OIIO::TypeUInt16;
    if (pt == "half") return OIIO::TypeHalf;
    if (pt == "float") return OIIO::TypeFloat;
    if (!pt.empty())
        return Status::error(quoted(display) + ": unknown pixel type '" + pt + "' (use uint8, uint16, half or float)");
    if (fmt == "hdr" || fmt == "openexr") return OIIO::TypeFloat;
    if (image.metadata.get_float("oiio:BitsPerSample").value_or(8) >= 16 && fmt != "jpeg") return OIIO::TypeUInt16;
    return OIIO::TypeUInt8;
}

// The chosen channels over roi as float, unpremultiplied, in the output colour space.
Result<Image> output_colour(const Image& image, const ChannelChoice& ch, const Roi& roi, const ColourConfig& config,
                            const std::string& target, const std::string& display) {
    Image work = gather(image, ch.chans, ch.names, roi);
    if (ch.alpha_out >= 0) unpremultiply(work, ch.alpha_out);
    if (config.resolve(target).empty()) return Status::error(quoted(display) + ": unknown colour space '" + target + "'");
    if (Status s = config.convert(work, kWorkingSpace, target); !s) return s.prefix(quoted(display));
    return work;
}

// Size, windows, channels, colour space, metadata, compression and tiling of the file.
OIIO::ImageSpec make_spec(const Image& image, const ChannelChoice& ch, const Roi& roi, OIIO::TypeDesc type,
                          const std::string& colour_space, const OIIO::ImageOutput& out, const WriteOptions& opts) {
    const std::string fmt = out.format_name();
    OIIO::ImageSpec spec(roi.width(), roi.height(), int(ch.chans.size()), type);
    spec.x = roi.x0;
    spec.y = roi.y0;
    const Roi full = image.display_window().empty() ? roi : image.display_window();
    spec.full_x = full.x0;
    spec.full_y = full.y0;
    spec.full_width = full.width();
    spec.full_height = full.height();
    spec.channelnames = ch.names;
    spec.alpha_channel = ch.alpha_out;
    metadata_to_spec(image.metadata, spec);
    spec.attribute("oiio:ColorSpace", colour_space);
    if (ch.alpha_out >= 0) spec.attribute("oiio:UnassociatedAlpha", 1);
    if (!opts.compression.empty()) spec.attribute("compression", opts.compression);
    else if (image.storage.format == fmt && !image.storage.compression.empty())
        spec.attribute("compression", image.storage.compression);
    if (image.storage.format == fmt && image.storage.tile_width > 0 && out.supports("tiles")) {
        spec.tile_width = image.storage.tile_width;
        spec.tile_height = image.storage.tile_height;
    }
    return spec;
}

// Opens the file and writes the pixels: integers clamped and quantised,
// floats as they are. The encoded file is made in memory and written with
// every error checked (write_file): OIIO's writers miss some (a PNG on a
// full disk reports success), which would rename a truncated file into place.
// Not TIFF: OIIO 2.4 writes unreadable TIFFs to memory; libtiff reports its
// write errors itself.
Status write_pixels(OIIO::ImageOutput& out, const std::string& file, const OIIO::ImageSpec& spec, const Image& work,
                    const std::string& display) {
    OIIO::Filesystem::IOVecOutput memory;
    const bool in_memory =
        std::string(out.format_name()) != "tiff" && out.supports("ioproxy") && out.set_ioproxy(&memory);
    if (!out.open(file, spec)) {
        std::string e = out.geterror();
        clear_error();
        return Status::error(quoted(display) + ": cannot write (OpenImageIO: " + e + ")");
    }
    bool ok = false;
    if (spec.format == OIIO::TypeUInt8) {
        auto buf = quantise<std::uint8_t>(work, 255.0);
        ok = out.write_image(OIIO::TypeUInt8, buf.data());
    } else if (spec.format == OIIO::TypeUInt16) {
        auto buf = quantise<std::uint16_t>(work, 65535.0);
        ok = out.write_image(OIIO::TypeUInt16, buf.data());
    } else {
        auto buf = interleave(work);
        ok = out.write_image(OIIO::TypeFloat, buf.data());
    }
    ok = out.close() && ok;
    std::string e = out.geterror();
    clear_error();
    if (!ok) return Status::error(quoted(display) + ": cannot write (OpenImageIO: " + e + ")");
    if (in_memory) return write_file(file, display, memory.buffer().data(), memory.buffer().size());
    return Status::ok();
}

}  // namespace

Status write(const std::string& file, const std::string& display, const Image& image, const WriteOptions& opts) {
    clear_error();
    auto out = OIIO::ImageOutput::create(file);
    if (!out) {
        std::string e = OIIO::geterror();
        return Status::error(quoted(display) + ": unknown or unsupported output format" +
                             (e.empty() ? std::string() : " (OpenImageIO: " + e + ")"));
    }
    const std::string fmt = out->format_name();
    const Result<ChannelChoice> channels = choose_channels(image, *out, display);
    if (!channels) return channels.status();
    const Result<OIIO::TypeDesc> type = choose_pixel_type(image, fmt, opts, display);
    if (!type) return type.status();
    const bool integer = !type->is_floating_point();
    const std::string target = !opts.colorspace.empty() ? opts.colorspace : (integer ? "sRGB" : "linear");

    // Roi: formats without a display window get the display window's pixels.
    Roi roi = image.data_window();
    if (!out->supports("displaywindow") && !image.display_window().empty()) roi = image.display_window();
    if (roi.empty()) return Status::error(quoted(display) + ": nothing to write (empty image) to " + fmt);

    const ColourConfig& config = config_or_default(opts.colour);
    const Result<Image> work = output_colour(image, channels.value(), roi, config, target, display);
    if (!work) return work.status();
    const OIIO::ImageSpec spec = make_spec(image, channels.value(), roi, type.value(), config.resolve(target), *out, opts);
    return write_pixels(*out, file, spec, work.value(), display);
}

}  // namespace gdof::io::oiio_module
