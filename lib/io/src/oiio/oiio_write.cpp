// Writing non-EXR formats (PNG, JPEG, TIFF, ...) through OpenImageIO's
// ImageOutput: pick the colour channels the format can hold, convert a copy
// from scene-linear to the output space, clamp and quantise, write.
#include <algorithm>
#include <cmath>
#include <cstdint>

#include <OpenImageIO/imageio.h>

#include "oiio/oiio_io.h"
#include "files/files.h"
#include "colour/linearize.h"

namespace gdof::io::detail {

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

}  // namespace

Status write_oiio(const std::string& file, const std::string& display, const Image& image, const WriteOptions& opts) {
    clear_oiio_error();
    auto out = OIIO::ImageOutput::create(file);
    if (!out) {
        std::string e = OIIO::geterror();
        return Status::error(quoted(display) + ": unknown or unsupported output format" +
                             (e.empty() ? std::string() : " (OpenImageIO: " + e + ")"));
    }
    const std::string fmt = out->format_name();

    // Channels the format can hold.
    std::vector<int> chans;
    std::vector<std::string> names;
    int alpha_out = -1;
    RgbaIndices rgba = find_rgba(image);
    const bool alpha_ok = out->supports("alpha");
    if (rgba.r >= 0 && rgba.g >= 0 && rgba.b >= 0) {
        chans = {rgba.r, rgba.g, rgba.b};
        names = {"R", "G", "B"};
    } else if (int y = image.channel_index("Y"); y >= 0) {
        chans = {y};
        names = {"Y"};
    } else if (image.nchannels() == 1) {
        chans = {0};
        names = {image.channel(0).name};
    } else if (out->supports("nchannels")) {
        for (int c = 0; c < image.nchannels(); ++c) {
            chans.push_back(c);
            names.push_back(image.channel(c).name);
        }
    } else {
        return Status::error(quoted(display) + ": no R,G,B or Y channels to write to " + fmt +
                             " (write EXR to keep all " + std::to_string(image.nchannels()) + " channels)");
    }
    if (rgba.a >= 0 && alpha_ok && std::find(chans.begin(), chans.end(), rgba.a) == chans.end()) {
        alpha_out = int(chans.size());
        chans.push_back(rgba.a);
        names.push_back("A");
    }

    // Pixel data type and output colour space.
    OIIO::TypeDesc type = OIIO::TypeUInt8;
    const std::string& pt = opts.pixel_type;
    if (pt == "uint8") type = OIIO::TypeUInt8;
    else if (pt == "uint16") type = OIIO::TypeUInt16;
    else if (pt == "half") type = OIIO::TypeHalf;
    else if (pt == "float") type = OIIO::TypeFloat;
    else if (!pt.empty())
        return Status::error(quoted(display) + ": unknown pixel type '" + pt + "' (use uint8, uint16, half or float)");
    else if (fmt == "hdr" || fmt == "openexr") type = OIIO::TypeFloat;
    else if (image.metadata.get_float("oiio:BitsPerSample").value_or(8) >= 16 && fmt != "jpeg") type = OIIO::TypeUInt16;
    const bool integer = !type.is_floating_point();
    const std::string target = !opts.colorspace.empty() ? opts.colorspace : (integer ? "sRGB" : "linear");

    // Roi: formats without a display window get the display window's pixels.
    Roi roi = image.data_window();
    if (!out->supports("displaywindow") && !image.display_window().empty()) roi = image.display_window();
    if (roi.empty()) return Status::error(quoted(display) + ": nothing to write (empty image) to " + fmt);

    Image work = gather(image, chans, names, roi);
    if (alpha_out >= 0) unpremultiply(work, alpha_out);
    const ColourConfig& config = config_or_default(opts.colour);
    if (config.resolve(target).empty())
        return Status::error(quoted(display) + ": unknown colour space '" + target + "'");
    if (Status s = config.convert(work, kWorkingSpace, target); !s) return s.prefix(quoted(display));

    OIIO::ImageSpec spec(roi.width(), roi.height(), int(chans.size()), type);
    spec.x = roi.x0;
    spec.y = roi.y0;
    const Roi full = image.display_window().empty() ? roi : image.display_window();
    spec.full_x = full.x0;
    spec.full_y = full.y0;
    spec.full_width = full.width();
    spec.full_height = full.height();
    spec.channelnames = names;
    spec.alpha_channel = alpha_out;
    metadata_to_spec(image.metadata, spec);
    spec.attribute("oiio:ColorSpace", config.resolve(target));
    if (alpha_out >= 0) spec.attribute("oiio:UnassociatedAlpha", 1);
    if (!opts.compression.empty()) spec.attribute("compression", opts.compression);
    else if (image.storage.format == fmt && !image.storage.compression.empty())
        spec.attribute("compression", image.storage.compression);
    if (image.storage.format == fmt && image.storage.tile_width > 0 && out->supports("tiles")) {
        spec.tile_width = image.storage.tile_width;
        spec.tile_height = image.storage.tile_height;
    }

    if (!out->open(file, spec)) {
        std::string e = out->geterror();
        clear_oiio_error();
        return Status::error(quoted(display) + ": cannot write (OpenImageIO: " + e + ")");
    }
    bool ok = false;
    if (type == OIIO::TypeUInt8) {
        auto buf = quantise<std::uint8_t>(work, 255.0);
        ok = out->write_image(OIIO::TypeUInt8, buf.data());
    } else if (type == OIIO::TypeUInt16) {
        auto buf = quantise<std::uint16_t>(work, 65535.0);
        ok = out->write_image(OIIO::TypeUInt16, buf.data());
    } else {
        auto buf = interleave(work);
        ok = out->write_image(OIIO::TypeFloat, buf.data());
    }
    ok = out->close() && ok;
    std::string e = out->geterror();
    clear_oiio_error();
    if (!ok) return Status::error(quoted(display) + ": cannot write (OpenImageIO: " + e + ")");
    return Status::ok();
}

}  // namespace gdof::io::detail
