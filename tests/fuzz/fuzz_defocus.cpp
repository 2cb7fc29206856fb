// The post-process core on arbitrary pixels: a small plate (RGBA + Z) or
// deep image made from the bytes, through defocus() with the diffusion or
// bokeh filter, a thin lens or a per-pixel blur map, and the layering,
// depth cleanup and solver the header bytes pick. Depths and colours come
// from small tables that hold surfaces (depths 3% apart, so continuity,
// mixed pixels, silhouette cuts and surfaces onward all see steps and
// ramps) and the values a frame must survive: 0, negative, NaN, infinities,
// the float range's ends. The result must be an error with a message or an
// image whose R, G, B, A are all finite: a NaN or infinite output pixel
// aborts the run, as a crash would.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <string>

#include "fuzz_support.h"
#include "gdof/blur_field.h"
#include "gdof/camera.h"
#include "gdof/deep.h"
#include "gdof/defocus.h"
#include "gdof/image_set.h"

namespace {

constexpr int kMaxSide = 20;
constexpr double kMaxRadius = 25.0;  // px: keeps one input well under a second

// Reads the bytes in order, then zeros.
struct Bytes {
    const std::uint8_t* data;
    std::size_t size, at = 0;
    std::uint8_t next() { return at < size ? data[at++] : 0; }
};

float depth_of(std::uint8_t b) {
    constexpr float inf = std::numeric_limits<float>::infinity();
    switch (b) {
        case 240: return 0.0f;
        case 241: return -1.0f;
        case 242: return std::numeric_limits<float>::quiet_NaN();
        case 243: return inf;
        case 244: return -inf;
        case 245: return 1e-30f;
        case 246: return 1e30f;
        case 247: return std::numeric_limits<float>::max();
        case 248: return std::numeric_limits<float>::denorm_min();
        default: return b < 240 ? float(0.5 * std::pow(1.03, double(b))) : 1.0f;
    }
}

float colour_of(std::uint8_t b) {
    switch (b) {
        case 250: return std::numeric_limits<float>::quiet_NaN();
        case 251: return std::numeric_limits<float>::infinity();
        case 252: return -1.0f;
        case 253: return 1e30f;
        case 254: return -0.0f;
        case 255: return 1e-38f;
        default: return float(b) / 50.0f;  // 0 .. 5: highlights too
    }
}

float alpha_of(std::uint8_t b) {
    switch (b) {
        case 250: return std::numeric_limits<float>::quiet_NaN();
        case 251: return 2.0f;
        case 252: return -0.5f;
        case 253: return std::numeric_limits<float>::infinity();
        default: return b > 250 ? 1.0f : float(b) / 249.0f;
    }
}

bool finite_rgba(const gdof::Image& img) {
    for (int c = 0; c < img.nchannels(); ++c) {
        const std::string& n = img.channel(c).name;
        if (n != "R" && n != "G" && n != "B" && n != "A") continue;
        const float* p = img.plane(c);
        for (std::size_t i = 0; i < img.npixels(); ++i)
            if (!std::isfinite(p[i])) return false;
    }
    return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace gdof;
    Bytes in{data, size};
    const int W = 1 + in.next() % kMaxSide, H = 1 + in.next() % kMaxSide;
    const std::uint8_t flags = in.next(), strength = in.next(), param = in.next();
    const bool deep = flags & 1, bokeh = flags & 2, alpha_varies = flags & 4, thin_lens = flags & 64;
    const Roi win{0, 0, W, H};

    ImageSet input;
    if (deep) {
        DeepImage d({{"R", PixelType::Float}, {"G", PixelType::Float}, {"B", PixelType::Float},
                     {"A", PixelType::Float}, {"Z", PixelType::Float}},
                    win, win);
        std::vector<std::uint32_t> counts(d.npixels());
        for (auto& n : counts) n = in.next() % 4;
        if (!d.set_sample_counts(counts)) return 0;
        for (std::size_t s = 0; s < d.total_samples(); ++s) {
            d.samples(4)[s] = depth_of(in.next());
            const float a = alpha_of(in.next());
            d.samples(3)[s] = a;
            for (int c = 0; c < 3; ++c) d.samples(c)[s] = colour_of(in.next()) * (std::isfinite(a) ? a : 1.0f);
        }
        input.parts.emplace_back(std::move(d));
    } else {
        Image img = Image::with_channels({"R", "G", "B", "A", "Z"}, win);
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x) {
                img.at(4, x, y) = depth_of(in.next());
                const float a = alpha_varies ? alpha_of(in.next()) : 1.0f;
                img.at(3, x, y) = a;
                for (int c = 0; c < 3; ++c) img.at(c, x, y) = colour_of(in.next()) * (std::isfinite(a) ? a : 1.0f);
            }
        input.parts.emplace_back(std::move(img));
    }

    CameraDesc cd;
    cd.display_window = win;
    cd.focal_length_mm = 35.0;
    cd.sensor_width_mm = 36.0;
    auto camera = Camera::create(cd);
    if (!camera) return 0;
    std::string json;
    BlurField::Context ctx;
    char buf[256];
    if (thin_lens) {
        std::snprintf(buf, sizeof buf,
                      R"({"blurfield": {"kind": "thin_lens", "focal_length_mm": 35, "sensor_width_mm": 36, )"
                      R"("f_number": %.6g, "focus_distance": %.9g}})",
                      0.003 * (1 + strength), double(depth_of(param)));
        json = buf;
    } else {
        // A blur map over the frame: radii 0 .. kMaxRadius from the bytes.
        auto map = std::make_shared<Image>(Image::with_channels({"Y"}, win));
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x) map->at(0, x, y) = float(in.next()) / 255.0f;
        ctx.images["m"] = map;
        std::snprintf(buf, sizeof buf, R"({"blurfield": {"kind": "image_map", "image": "m", "scale": %.6g}})",
                      kMaxRadius * strength / 255.0);
        json = buf;
    }
    auto field = BlurField::parse(json, ctx);
    if (!field) return 0;

    DefocusOptions o;
    o.filter = bokeh ? DefocusFilter::Bokeh : DefocusFilter::Diffusion;
    o.diffusion.max_radius = kMaxRadius;
    o.diffusion.solver = flags & 128 ? DiffusionSolver::Adi : DiffusionSolver::Auto;
    switch ((flags >> 3) & 3) {
        case 0: break;  // auto, blur cuts
        case 1:
            o.split.mode = LayerSplit::Mode::Count;
            o.split.count = 1 + param % 8;
            break;
        case 2: o.split.blur_cuts = LayerSplit::BlurCuts::Off; break;
        case 3: o.split.max_layers = 1 + param % 4; break;
    }
    if (flags & 32) o.cleanup = DepthCleanupOptions{false, false, false};
    DefocusStats stats;
    auto r = defocus(input, field.value(), camera.value(), o, &stats);
    if (!r) {
        if (r.message().empty()) __builtin_trap();  // an error must say what
        return 0;
    }
    for (std::size_t i = 0; i < r->size(); ++i)
        if (!r->is_deep(i) && !finite_rgba(r->flat(i))) __builtin_trap();
    return 0;
}
