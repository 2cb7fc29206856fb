// Colour module: config selection, channel selection and the built-in
// fallback config (linear + sRGB) that needs no OCIO config file.
#include "gdof/io/colour.h"

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <map>
#include <mutex>

#include "colour/colour_internal.h"
#include "gdof/exec.h"

namespace gdof::io {

namespace detail {

std::string ascii_lower(std::string s) {
    for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

Status for_each_colour_plane(Image& image,
                             const std::function<Status(float*, float*, float*, std::size_t)>& f) {
    const std::vector<ColourTriple> triples = colour_channels(image.channels());
    if (triples.empty() || image.npixels() == 0) return Status::ok();
    const long width = image.width();
    const long height = image.height();
    // Rows per chunk: about 64k pixels, so small images run as one call.
    const long rows_per_chunk = std::max(1L, 65536L / std::max(1L, width));
    const long nchunks = (height + rows_per_chunk - 1) / rows_per_chunk;
    std::mutex mu;
    Status first;
    std::atomic<bool> failed{false};
    Exec exec;
    exec.cancelled = [&] { return failed.load(std::memory_order_relaxed); };
    for (const ColourTriple& t : triples) {
        float* r = image.plane(t.r);
        float* g = image.plane(t.g);
        float* b = image.plane(t.b);
        (void)parallel_for(exec, nchunks, [&](long c0, long c1) {
            for (long c = c0; c < c1; ++c) {
                const long y0 = c * rows_per_chunk;
                const long y1 = std::min(height, y0 + rows_per_chunk);
                const std::size_t off = std::size_t(y0) * std::size_t(width);
                const std::size_t n = std::size_t(y1 - y0) * std::size_t(width);
                Status s = f(r + off, g + off, b + off, n);
                if (!s) {
                    std::lock_guard<std::mutex> lock(mu);
                    if (first) first = s;
                    failed = true;
                    return;
                }
            }
        });
        if (!first) return first;
    }
    return first;
}

}  // namespace detail

// ---------------------------------------------------------------------------
// Channel selection

bool is_data_layer(const std::string& layer) {
    static const char* const kData[] = {
        "p",        "pworld",  "pref",     "pobj",   "pcam",     "position", "worldposition",
        "world_position",      "n",        "nworld", "nn",       "ng",       "normal",
        "normals",  "nref",    "motion",   "motionvector",       "motion_vector",
        "motionvectors",       "forward",  "backward",           "velocity", "vel",
        "mv",       "uv",      "st",       "id",     "depth",    "z",        "disparity",
        "disparityl",          "disparityr",         "pz",       "nz"};
    const std::string l = detail::ascii_lower(layer);
    // The last component decides ("left.P" is a position layer).
    const auto dot = l.rfind('.');
    const std::string last = dot == std::string::npos ? l : l.substr(dot + 1);
    for (const char* d : kData)
        if (last == d) return true;
    return last.rfind("crypto", 0) == 0;
}

std::vector<ColourTriple> colour_channels(const std::vector<ChannelSpec>& channels) {
    // Group channels by layer (everything before the last '.').
    std::map<std::string, std::vector<int>> layers;
    std::vector<std::string> order;
    for (int c = 0; c < int(channels.size()); ++c) {
        const std::string& name = channels[std::size_t(c)].name;
        const auto dot = name.rfind('.');
        std::string layer = dot == std::string::npos ? std::string() : name.substr(0, dot);
        if (!layers.count(layer)) order.push_back(layer);
        layers[layer].push_back(c);
    }
    auto find = [&](const std::vector<int>& idx, const std::string& prefix,
                    std::initializer_list<const char*> names) {
        for (const char* n : names)
            for (int c : idx) {
                const ChannelSpec& ch = channels[std::size_t(c)];
                if (ch.type != PixelType::UInt && ch.name == prefix + n) return c;
            }
        return -1;
    };
    std::vector<ColourTriple> out;
    for (const std::string& layer : order) {
        if (!layer.empty() && is_data_layer(layer)) continue;
        const std::string prefix = layer.empty() ? std::string() : layer + ".";
        const auto& idx = layers[layer];
        ColourTriple t;
        t.layer = layer;
        t.r = find(idx, prefix, {"R", "r", "red", "Red"});
        t.g = find(idx, prefix, {"G", "g", "green", "Green"});
        t.b = find(idx, prefix, {"B", "b", "blue", "Blue"});
        if (t.r >= 0 && t.g >= 0 && t.b >= 0) out.push_back(t);
    }
    std::sort(out.begin(), out.end(), [](const ColourTriple& a, const ColourTriple& b) { return a.r < b.r; });
    return out;
}

// ---------------------------------------------------------------------------
// sRGB transfer functions (IEC 61966-2-1)

float srgb_to_linear(float v) {
    const double x = v;
    if (x <= 0.04045) return float(x / 12.92);
    return float(std::pow((x + 0.055) / 1.055, 2.4));
}

float linear_to_srgb(float v) {
    const double x = v;
    if (x <= 0.0031308) return float(x * 12.92);
    return float(1.055 * std::pow(x, 1.0 / 2.4) - 0.055);
}

// ---------------------------------------------------------------------------
// Deep images: the same channel rule on every sample.

Status ColourConfig::convert(DeepImage& image, const std::string& from, const std::string& to) const {
    const std::vector<ColourTriple> triples = colour_channels(image.channels());
    const std::size_t n = image.total_samples();
    for (const ColourTriple& t : triples) {
        if (n == 0) break;
        Status s = convert_planes(image.samples(t.r), image.samples(t.g), image.samples(t.b), n, from, to);
        if (!s) return s;
    }
    if (triples.empty() || n == 0) {
        // Still validate the names so a typo is reported even on empty images.
        if (resolve(from).empty()) return Status::error("unknown colour space '" + from + "'");
        if (resolve(to).empty()) return Status::error("unknown colour space '" + to + "'");
    }
    return Status::ok();
}

// ---------------------------------------------------------------------------
// The built-in fallback config

namespace {

enum class Builtin { Linear, Srgb, Raw };

class BuiltinConfig final : public ColourConfig {
public:
    std::string description() const override {
        return "built-in colour config";
    }
    std::vector<std::string> colour_spaces() const override { return {"linear", "sRGB", "raw"}; }

    std::string resolve(const std::string& name) const override {
        Builtin b;
        if (!lookup(name, b)) return {};
        switch (b) {
            case Builtin::Linear: return "linear";
            case Builtin::Srgb: return "sRGB";
            case Builtin::Raw: return "raw";
        }
        return {};
    }
    bool is_linear(const std::string& name) const override {
        Builtin b;
        return lookup(name, b) && b != Builtin::Srgb;
    }

    Status convert(Image& image, const std::string& from, const std::string& to) const override {
        Builtin a, b;
        if (Status s = check(from, to, a, b); !s) return s;
        if (a == b || a == Builtin::Raw || b == Builtin::Raw) return Status::ok();
        return detail::for_each_colour_plane(image, [&](float* r, float* g, float* bl, std::size_t n) {
            apply(a, b, r, g, bl, n);
            return Status::ok();
        });
    }

    Status convert_planes(float* r, float* g, float* b, std::size_t n, const std::string& from,
                          const std::string& to) const override {
        Builtin fa, tb;
        if (Status s = check(from, to, fa, tb); !s) return s;
        if (fa == tb || fa == Builtin::Raw || tb == Builtin::Raw) return Status::ok();
        apply(fa, tb, r, g, b, n);
        return Status::ok();
    }

private:
    static bool lookup(const std::string& name, Builtin& out) {
        const std::string l = detail::ascii_lower(name);
        if (l == "linear" || l == "scene_linear" || l == "lin_rec709" || l == "lin_srgb" ||
            l == "linear - rec.709" || l == "reference" || l == "default") {
            out = Builtin::Linear;
            return true;
        }
        if (l == "srgb" || l == "srgb - texture" || l == "srgb_texture" || l == "utility - srgb - texture" ||
            l == "srgb_tx" || l == "color_picking" || l == "matte_paint" || l == "texture_paint") {
            out = Builtin::Srgb;
            return true;
        }
        if (l == "raw" || l == "data" || l == "non-color" || l == "utility - raw") {
            out = Builtin::Raw;
            return true;
        }
        return false;
    }
    static Status check(const std::string& from, const std::string& to, Builtin& a, Builtin& b) {
        if (!lookup(from, a))
            return Status::error("unknown colour space '" + from + "' (built-in config knows linear, sRGB, raw)");
        if (!lookup(to, b))
            return Status::error("unknown colour space '" + to + "' (built-in config knows linear, sRGB, raw)");
        return Status::ok();
    }
    static void apply(Builtin from, Builtin to, float* r, float* g, float* b, std::size_t n) {
        float (*fn)(float) = (from == Builtin::Srgb && to == Builtin::Linear) ? &srgb_to_linear : &linear_to_srgb;
        for (float* p : {r, g, b})
            for (std::size_t i = 0; i < n; ++i) p[i] = fn(p[i]);
    }
};

}  // namespace

std::shared_ptr<const ColourConfig> ColourConfig::builtin() {
    static const std::shared_ptr<const ColourConfig> config = std::make_shared<BuiltinConfig>();
    return config;
}

Result<std::shared_ptr<const ColourConfig>> ColourConfig::from_file(const std::string& path) {
    return detail::load_ocio_config(path);
}

Result<std::shared_ptr<const ColourConfig>> ColourConfig::from_environment() {
    const char* env = std::getenv("OCIO");
    if (env && *env) {
        auto r = detail::load_ocio_config(env);
        if (!r) return Status::error("$OCIO: " + r.message());
        return r;
    }
    return builtin();
}

const ColourConfig& ColourConfig::default_config() {
    static const std::shared_ptr<const ColourConfig> config = [] {
        auto r = from_environment();
        return r ? r.value() : builtin();
    }();
    return *config;
}

}  // namespace gdof::io
