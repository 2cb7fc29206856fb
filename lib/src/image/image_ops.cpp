#include "gdof/image_ops.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>

namespace gdof {

Result<std::vector<std::string>> split_list(const std::string& list) {
    std::vector<std::string> out;
    std::size_t start = 0;
    while (true) {
        std::size_t comma = list.find(',', start);
        std::string item = list.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
        if (item.empty()) return Status::error("empty entry in the list '" + list + "'");
        out.push_back(std::move(item));
        if (comma == std::string::npos) break;
        start = comma + 1;
    }
    return out;
}

namespace {
bool parse_number(const std::string& s, double& v) {
    if (s.empty()) return false;
    char* end = nullptr;
    errno = 0;
    v = std::strtod(s.c_str(), &end);
    return errno == 0 && end && *end == '\0' && std::isfinite(v);
}
}  // namespace

Result<Image> select_channels(const Image& src, const std::vector<std::string>& spec) {
    struct Source {
        std::string name;
        int from = -1;       // channel index, or -1 for a constant
        double value = 0.0;  // constant
    };
    std::vector<Source> sources;
    std::vector<ChannelSpec> specs;
    for (const std::string& entry : spec) {
        Source s;
        std::size_t eq = entry.find('=');
        std::string from = entry;
        s.name = entry;
        if (eq != std::string::npos) {
            s.name = entry.substr(0, eq);
            from = entry.substr(eq + 1);
            if (s.name.empty() || from.empty()) return Status::error("bad channel entry '" + entry + "' (expected new=old)");
        }
        s.from = src.channel_index(from);
        if (s.from < 0) {
            if (eq == std::string::npos || !parse_number(from, s.value)) {
                std::string known;
                for (const auto& c : src.channels()) known += (known.empty() ? "" : ", ") + c.name;
                return Status::error("channel '" + from + "' not found (channels: " + known + ")");
            }
        }
        for (const auto& c : specs)
            if (c.name == s.name) return Status::error("channel '" + s.name + "' named twice");
        specs.push_back(s.from >= 0 ? ChannelSpec{s.name, src.channel(s.from).type} : ChannelSpec{s.name, PixelType::Float});
        sources.push_back(std::move(s));
    }
    Image out(specs, src.data_window(), src.display_window());
    out.metadata = src.metadata;
    out.name = src.name;
    out.view = src.view;
    out.storage = src.storage;
    for (int c = 0; c < out.nchannels(); ++c) {
        const Source& s = sources[std::size_t(c)];
        const std::size_t n = out.npixels();
        if (s.from < 0) {
            float* d = out.plane(c);
            for (std::size_t i = 0; i < n; ++i) d[i] = float(s.value);
        } else if (src.channel(s.from).type == PixelType::UInt) {
            if (n) std::memcpy(out.uplane(c), src.uplane(s.from), n * sizeof(std::uint32_t));
        } else if (n) {
            std::memcpy(out.plane(c), src.plane(s.from), n * sizeof(float));
        }
    }
    return out;
}

Status multiply_channels(Image& img, const std::vector<double>& factors) {
    if (factors.empty()) return Status::error("no factors given");
    if (factors.size() != 1 && int(factors.size()) != img.nchannels())
        return Status::error("expected 1 factor or one per channel (" + std::to_string(img.nchannels()) + "), got " +
                             std::to_string(factors.size()));
    for (double f : factors)
        if (!std::isfinite(f)) return Status::error("factor is not a finite number");
    for (int c = 0; c < img.nchannels(); ++c) {
        float* p = img.plane(c);
        if (!p) continue;
        const float f = float(factors.size() == 1 ? factors[0] : factors[std::size_t(c)]);
        for (std::size_t i = 0; i < img.npixels(); ++i) p[i] *= f;
    }
    return Status::ok();
}

}  // namespace gdof
