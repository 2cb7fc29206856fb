// describe(): the text behind `gdof --info`.
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>

#include "common/format_number.h"
#include "gdof/io/image_io.h"

namespace gdof::io {

namespace {

std::string fmt_num(double v) { return format_number(v, 6); }

std::string window(const Roi& r) {
    std::ostringstream os;
    os << to_string(r) << " " << r.width() << "x" << r.height();
    if (r.empty()) os << " (empty)";
    return os.str();
}

std::string value_text(const Attribute& a, std::size_t max_numbers) {
    if (a.type == "string") {
        std::string t(1, '"');
        t += a.text;
        t += '"';
        return t;
    }
    if (a.type.rfind("string[", 0) == 0) {
        std::string t = "[";
        std::size_t start = 0;
        bool first = true;
        while (true) {
            std::size_t z = a.text.find('\0', start);
            if (!first) t += ", ";
            first = false;
            t += '"';
            t.append(a.text, start, z == std::string::npos ? std::string::npos : z - start);
            t += '"';
            if (z == std::string::npos) break;
            start = z + 1;
        }
        return t + "]";
    }
    if (a.text.rfind("exr:", 0) == 0) {
        std::string t(1, '<');
        t.append(a.text, 4);
        t += ", ";
        t += std::to_string(a.numbers.size());
        t += " bytes>";
        return t;
    }
    std::string t;
    if (a.numbers.size() > 1) t += "[";
    for (std::size_t i = 0; i < a.numbers.size() && i < max_numbers; ++i) {
        if (i) t += ", ";
        t += fmt_num(a.numbers[i]);
    }
    if (a.numbers.size() > max_numbers) t += ", ...";
    if (a.numbers.size() > 1) t += "]";
    return t;
}

void describe_channels(std::ostringstream& os, const std::vector<ChannelSpec>& chans) {
    // Grouped by layer, each layer's channels with their types.
    std::vector<std::string> order;
    std::map<std::string, std::vector<const ChannelSpec*>> layers;
    for (const auto& c : chans) {
        auto d = c.name.rfind('.');
        std::string layer = d == std::string::npos ? std::string() : c.name.substr(0, d);
        if (!layers.count(layer)) order.push_back(layer);
        layers[layer].push_back(&c);
    }
    os << "  channels (" << chans.size() << "):\n";
    for (const auto& layer : order) {
        os << "    " << (layer.empty() ? std::string("(no layer)") : layer) << ":";
        for (const auto* c : layers[layer]) {
            std::string base = layer.empty() ? c->name : c->name.substr(layer.size() + 1);
            os << " " << base << " (" << to_string(c->type) << ")";
        }
        os << "\n";
    }
}

void describe_deep(std::ostringstream& os, const DeepImage& d) {
    const auto& counts = d.sample_counts();
    std::uint32_t mn = counts.empty() ? 0 : *std::min_element(counts.begin(), counts.end());
    std::uint32_t mx = counts.empty() ? 0 : *std::max_element(counts.begin(), counts.end());
    double mean = counts.empty() ? 0.0 : double(d.total_samples()) / double(counts.size());
    os << "  deep samples: " << d.total_samples() << " total; per pixel min " << mn << ", mean " << fmt_num(mean)
       << ", max " << mx << "\n";
    for (int zc : {d.z_channel(), d.zback_channel()}) {
        if (zc < 0 || d.channel(zc).type == PixelType::UInt || d.total_samples() == 0) continue;
        const float* z = d.samples(zc);
        float lo = std::numeric_limits<float>::infinity(), hi = -lo;
        for (std::size_t i = 0; i < d.total_samples(); ++i)
            if (!std::isnan(z[i])) lo = std::min(lo, z[i]), hi = std::max(hi, z[i]);
        os << "  " << d.channel(zc).name << " range: [" << fmt_num(lo) << ", " << fmt_num(hi) << "]\n";
    }
}

void describe_part(std::ostringstream& os, std::size_t i, const std::string& name, const std::string& view,
                   bool deep, const Roi& data, const Roi& display, const std::vector<ChannelSpec>& chans,
                   const Metadata& md, const StorageHints& st, bool verbose) {
    os << "part " << i;
    if (!name.empty()) os << " \"" << name << "\"";
    if (!view.empty()) os << " view \"" << view << "\"";
    os << ": " << (deep ? "deep" : "flat") << ", " << (st.tile_width > 0 ? "tiled " + std::to_string(st.tile_width) + "x" + std::to_string(st.tile_height) : std::string("scanline"));
    if (!st.compression.empty()) os << ", " << st.compression;
    if (!st.format.empty()) os << " (" << st.format << ")";
    os << "\n";
    os << "  data window:    " << window(data) << "\n";
    os << "  display window: " << window(display) << "\n";
    describe_channels(os, chans);
    (void)md;
}

void describe_camera(std::ostringstream& os, const Metadata& md) {
    static const char* kCamera[] = {"worldToCamera", "worldToNDC",    "focalLength",   "aperture",   "fNumber",
                                    "FNumber",       "focus",         "focusDistance", "apertureSize", "sensorWidth",
                                    "filmBackWidth", "horizontalAperture", "verticalAperture", "nearClip", "farClip",
                                    "screenWindowWidth", "screenWindowCenter", "pixelAspectRatio"};
    bool any = false;
    for (const char* n : kCamera) {
        const Attribute* a = md.find(n);
        if (!a) continue;
        if (!any) os << "  camera:\n";
        any = true;
        os << "    " << a->name << " (" << a->type << "): " << value_text(*a, 16) << "\n";
    }
}

}  // namespace

std::string describe(const ImageSet& images, const std::string& path, bool verbose) {
    std::ostringstream os;
    os << path << ": " << images.size() << (images.size() == 1 ? " part" : " parts") << "\n";
    for (std::size_t i = 0; i < images.size(); ++i) {
        const Metadata& md = images.metadata(i);
        if (images.is_deep(i)) {
            const DeepImage& d = images.deep(i);
            describe_part(os, i, d.name, d.view, true, d.data_window(), d.display_window(), d.channels(), md,
                          d.storage, verbose);
            describe_deep(os, d);
        } else {
            const Image& f = images.flat(i);
            describe_part(os, i, f.name, f.view, false, f.data_window(), f.display_window(), f.channels(), md,
                          f.storage, verbose);
        }
        describe_camera(os, md);
        if (verbose && !md.attributes().empty()) {
            os << "  attributes (" << md.attributes().size() << "):\n";
            for (const auto& a : md.attributes())
                os << "    " << a.name << " (" << a.type << "): " << value_text(a, 64) << "\n";
        }
    }
    return os.str();
}

}  // namespace gdof::io
