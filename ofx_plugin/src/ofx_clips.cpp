#include "ofx_clips.h"

#include <algorithm>
#include <cmath>

namespace gdof::ofx {

namespace {

const OfxImageEffectSuiteV1& fx() { return *suites().effect; }

std::string short_name(const std::string& ofx_name) {
    // "OfxImageComponentRGBA" -> "RGBA", "OfxBitDepthByte" -> "Byte"
    for (const char* p : {"OfxImageComponent", "OfxBitDepth"})
        if (ofx_name.rfind(p, 0) == 0) return ofx_name.substr(std::string(p).size());
    return ofx_name.empty() ? std::string("none") : ofx_name;
}

}  // namespace

Props define_clip(OfxImageEffectHandle descriptor, const char* name, const char* label,
                  std::initializer_list<const char*> components, bool optional, bool temporal) {
    OfxPropertySetHandle h = nullptr;
    check(fx().clipDefine(descriptor, name, &h), std::string("defining clip '") + name + "'");
    Props p(h);
    p.set(kOfxPropLabel, label);
    p.set_strings(kOfxImageEffectPropSupportedComponents, components);
    p.set(kOfxImageEffectPropSupportsTiles, 1);
    p.set(kOfxImageEffectPropTemporalClipAccess, temporal ? 1 : 0);
    p.set(kOfxImageClipPropOptional, optional ? 1 : 0);
    return p;
}

Clip::Clip(OfxImageEffectHandle effect, const char* name) : name_(name) {
    OfxPropertySetHandle ph = nullptr;
    check(fx().clipGetHandle(effect, name, &clip_, &ph), std::string("clip '") + name + "'");
    props_ = Props(ph);
}

bool Clip::connected() const { return props_.int_or(kOfxImageClipPropConnected, 0) != 0; }
std::string Clip::components() const { return props_.string_or(kOfxImageEffectPropComponents, ""); }
std::string Clip::pixel_depth() const { return props_.string_or(kOfxImageEffectPropPixelDepth, ""); }
std::string Clip::premultiplication() const {
    return props_.string_or(kOfxImageEffectPropPreMultiplication, kOfxImagePreMultiplied);
}

OfxRectD Clip::region_of_definition(double time) const {
    OfxRectD r{0, 0, 0, 0};
    check(fx().clipGetRegionOfDefinition(clip_, time, &r), "region of definition of clip '" + name_ + "'");
    return r;
}

ClipImage::ClipImage(const Clip& clip, double time, const OfxRectD* region) : clip_(clip.name()) {
    OfxPropertySetHandle h = nullptr;
    const OfxStatus st = fx().clipGetImage(clip.handle(), time, region, &h);
    if (st == kOfxStatFailed || !h) return;  // no image (not connected, or outside the clip's time)
    check(st, "fetching an image of clip '" + clip_ + "'");
    props_ = Props(h);
    try {
        data_ = props_.get_pointer(kOfxImagePropData);
        const std::vector<int> b = props_.get_ints(kOfxImagePropBounds, 4);
        bounds_ = {b[0], b[1], b[2], b[3]};
        rowbytes_ = props_.get_int(kOfxImagePropRowBytes);
        components_ = props_.get_string(kOfxImageEffectPropComponents);
        depth_ = props_.get_string(kOfxImageEffectPropPixelDepth);
        premult_ = props_.string_or(kOfxImageEffectPropPreMultiplication, kOfxImagePreMultiplied);
        ncomp_ = component_count(components_);
    } catch (...) {
        fx().clipReleaseImage(h);
        props_ = Props();
        throw;
    }
}

ClipImage::~ClipImage() {
    if (props_.valid()) fx().clipReleaseImage(props_.handle());
}

void ClipImage::require(std::initializer_list<const char*> components) const {
    if (depth_ != kOfxBitDepthFloat)
        fail("clip '" + clip_ + "': " + short_name(depth_) + " images are not supported (gdof works on 32-bit float)");
    bool ok = false;
    std::string list;
    for (const char* c : components) {
        ok = ok || components_ == c;
        list += (list.empty() ? "" : " or ") + short_name(c);
    }
    if (!ok || ncomp_ == 0) fail("clip '" + clip_ + "': " + short_name(components_) + " images are not supported (needs " + list + ")");
    if (!data_ && bounds_.x2 > bounds_.x1 && bounds_.y2 > bounds_.y1) fail("clip '" + clip_ + "': the host gave no pixel data");
    const long need = long(bounds_.x2 - bounds_.x1) * ncomp_ * long(sizeof(float));
    if (bounds_.y2 > bounds_.y1 + 1 && std::labs(long(rowbytes_)) < need)
        fail("clip '" + clip_ + "': row bytes " + std::to_string(rowbytes_) + " smaller than a row");
    if (bounds_.y2 > bounds_.y1 + 1 && rowbytes_ % int(sizeof(float)) != 0)
        fail("clip '" + clip_ + "': row bytes " + std::to_string(rowbytes_) + " not a whole number of floats");
}

ImageView ClipImage::view(const PixelFrame& f, const OfxRectI& region) const {
    const OfxRectI r{std::max(region.x1, bounds_.x1), std::max(region.y1, bounds_.y1), std::min(region.x2, bounds_.x2),
                     std::min(region.y2, bounds_.y2)};
    if (r.x2 <= r.x1 || r.y2 <= r.y1) return {nullptr, ncomp_, Roi{}, 1, ncomp_, 0};
    // gdof row top - r.y2 (the view's first) is the host's row r.y2 - 1.
    return ImageView::interleaved(pixel(r.x1, r.y2 - 1), ncomp_, f.to_gdof(r),
                                  -std::ptrdiff_t(rowbytes_ / int(sizeof(float))));
}

int component_count(const std::string& c) {
    if (c == kOfxImageComponentRGBA) return 4;
    if (c == kOfxImageComponentRGB) return 3;
    if (c == kOfxImageComponentAlpha) return 1;
    return 0;
}

OfxRectI PixelFrame::to_pixels(const OfxRectD& c) const {
    // Outward rounding, with a small tolerance so exact multiples stay exact.
    auto lo = [](double v) { return int(std::floor(v + 1e-6)); };
    auto hi = [](double v) { return int(std::ceil(v - 1e-6)); };
    return {lo(c.x1 * sx / par), lo(c.y1 * sy), hi(c.x2 * sx / par), hi(c.y2 * sy)};
}

OfxRectD PixelFrame::to_canonical(const OfxRectI& p) const {
    return {p.x1 * par / sx, p.y1 / sy, p.x2 * par / sx, p.y2 / sy};
}

PixelFrame pixel_frame(OfxImageEffectHandle effect, OfxPointD scale) {
    OfxPropertySetHandle ph = nullptr;
    check(fx().getPropertySet(effect, &ph), "effect properties");
    Props p(ph);
    PixelFrame f;
    f.sx = scale.x > 0 ? scale.x : 1.0;
    f.sy = scale.y > 0 ? scale.y : 1.0;
    f.par = p.double_or(kOfxImageEffectPropProjectPixelAspectRatio, 1.0);
    if (!(f.par > 0)) f.par = 1.0;
    const OfxRectD extent{p.double_or(kOfxImageEffectPropProjectOffset, 0.0, 0),
                          p.double_or(kOfxImageEffectPropProjectOffset, 0.0, 1),
                          p.double_or(kOfxImageEffectPropProjectOffset, 0.0, 0) + p.double_or(kOfxImageEffectPropProjectSize, 0.0, 0),
                          p.double_or(kOfxImageEffectPropProjectOffset, 0.0, 1) + p.double_or(kOfxImageEffectPropProjectSize, 0.0, 1)};
    const OfxRectI px = f.to_pixels(extent);
    f.top = px.y2;
    f.display = f.to_gdof(px);
    return f;
}

void read_components(const ClipImage& src, const PixelFrame& f, Image& dst, const std::vector<std::pair<int, int>>& map,
                     float outside) {
    const Roi w = dst.data_window();
    for (int gy = w.y0; gy < w.y1; ++gy) {
        const int oy = f.gdof_y(gy);
        for (int x = w.x0; x < w.x1; ++x) {
            const bool in = src.valid() && src.contains(x, oy);
            const float* p = in ? src.pixel(x, oy) : nullptr;
            for (const auto& [comp, ch] : map) dst.at(ch, x, gy) = in ? p[comp] : outside;
        }
    }
}

Image premultiplied_rgba(const ClipImage& src, const PixelFrame& f, const Roi& window) {
    Image img = Image::with_channels({"R", "G", "B", "A"}, window);
    img.set_display_window(f.display);
    if (!src.valid()) return img;
    const bool rgba = src.ncomponents() == 4;
    read_components(src, f, img, rgba ? std::vector<std::pair<int, int>>{{0, 0}, {1, 1}, {2, 2}, {3, 3}}
                                      : std::vector<std::pair<int, int>>{{0, 0}, {1, 1}, {2, 2}},
                    0.0f);
    const bool unpremultiplied = src.premultiplication() == kOfxImageUnPreMultiplied;
    for (int y = window.y0; y < window.y1; ++y)
        for (int x = window.x0; x < window.x1; ++x) {
            if (!rgba) {
                img.at(3, x, y) = src.contains(x, f.gdof_y(y)) ? 1.0f : 0.0f;
            } else if (unpremultiplied) {
                const float a = img.at(3, x, y);
                for (int c = 0; c < 3; ++c) img.at(c, x, y) *= a;
            }
        }
    return img;
}

void write_rgba(const Image& src, const PixelFrame& f, const ClipImage& out, const OfxRectI& window) {
    const RgbaIndices c = find_rgba(src);
    const int ch[4] = {c.r, c.g, c.b, c.a};
    const int n = out.ncomponents();
    const OfxRectI b = out.bounds();
    for (int oy = std::max(window.y1, b.y1); oy < std::min(window.y2, b.y2); ++oy) {
        const int gy = f.gdof_y(oy);
        for (int x = std::max(window.x1, b.x1); x < std::min(window.x2, b.x2); ++x) {
            float* p = out.pixel(x, oy);
            const bool in = src.data_window().contains(x, gy);
            for (int k = 0; k < n; ++k) p[k] = in && ch[k] >= 0 ? src.at(ch[k], x, gy) : 0.0f;
        }
    }
}

}  // namespace gdof::ofx
