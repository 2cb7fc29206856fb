// The test host's image effect suite: clips, images (regions of interest,
// render scale, bit depths, guard values) and abort.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <limits>

#include "ofx/ofx_test_host_internal.h"

namespace gdof::ofxtest::detail {

thread_local RenderContext* t_render = nullptr;

OfxRectD canonical(const OfxRectI& r, OfxPointD s) { return {r.x1 / s.x, r.y1 / s.y, r.x2 / s.x, r.y2 / s.y}; }

namespace {

ImageEffect* E(OfxImageEffectHandle h) { return reinterpret_cast<ImageEffect*>(h); }
Clip* C(OfxImageClipHandle h) { return reinterpret_cast<Clip*>(h); }

OfxStatus getPropertySet(OfxImageEffectHandle fx, OfxPropertySetHandle* props) {
    if (!fx || !props) return kOfxStatErrBadHandle;
    *props = reinterpret_cast<OfxPropertySetHandle>(&E(fx)->props);
    return kOfxStatOK;
}

OfxStatus getParamSet(OfxImageEffectHandle fx, OfxParamSetHandle* set) {
    if (!fx || !set) return kOfxStatErrBadHandle;
    *set = reinterpret_cast<OfxParamSetHandle>(&E(fx)->params);
    return kOfxStatOK;
}

OfxStatus clipDefine(OfxImageEffectHandle fx, const char* name, OfxPropertySetHandle* props) {
    if (!fx || !name) return kOfxStatErrBadHandle;
    ImageEffect* e = E(fx);
    if (e->instance) return kOfxStatErrBadHandle;  // only in describeInContext
    if (e->clips.count(name)) return kOfxStatErrExists;
    auto c = std::make_unique<Clip>();
    c->name = name;
    c->effect = e;
    c->props.set(kOfxPropType, std::string(kOfxTypeClip));
    c->props.set(kOfxPropName, std::string(name));
    c->props.set(kOfxPropLabel, std::string(name));
    c->props.set_i(kOfxImageClipPropOptional, {0});
    c->props.set_i(kOfxImageClipPropIsMask, {0});
    c->props.set_i(kOfxImageEffectPropSupportsTiles, {1});
    c->props.set_i(kOfxImageEffectPropTemporalClipAccess, {0});
    if (props) *props = reinterpret_cast<OfxPropertySetHandle>(&c->props);
    e->clip_order.push_back(name);
    e->clips[name] = std::move(c);
    return kOfxStatOK;
}

OfxStatus clipGetHandle(OfxImageEffectHandle fx, const char* name, OfxImageClipHandle* clip, OfxPropertySetHandle* props) {
    if (!fx || !name) return kOfxStatErrBadHandle;
    ImageEffect* e = E(fx);
    if (!e->instance) return kOfxStatErrBadHandle;
    auto it = e->clips.find(name);
    if (it == e->clips.end()) return kOfxStatErrUnknown;
    if (clip) *clip = reinterpret_cast<OfxImageClipHandle>(it->second.get());
    if (props) *props = reinterpret_cast<OfxPropertySetHandle>(&it->second->props);
    return kOfxStatOK;
}

OfxStatus clipGetPropertySet(OfxImageClipHandle clip, OfxPropertySetHandle* props) {
    if (!clip || !props) return kOfxStatErrBadHandle;
    *props = reinterpret_cast<OfxPropertySetHandle>(&C(clip)->props);
    return kOfxStatOK;
}

OfxRectD input_rod(const Clip& c, double time) {
    auto it = c.frames.find(int(std::lround(time)));
    if (it == c.frames.end()) return {0, 0, 0, 0};
    const OfxRectI& b = it->second.bounds;
    return {double(b.x1), double(b.y1), double(b.x2), double(b.y2)};
}

OfxRectD output_rod(const Clip& c) {
    const std::vector<double> r = c.props.doubles("testhost:RoD");
    return r.size() == 4 ? OfxRectD{r[0], r[1], r[2], r[3]} : OfxRectD{0, 0, 0, 0};
}

OfxStatus clipGetRegionOfDefinition(OfxImageClipHandle clip, OfxTime time, OfxRectD* rod) {
    if (!clip || !rod) return kOfxStatErrBadHandle;
    const Clip& c = *C(clip);
    *rod = c.name == kOfxImageEffectOutputClipName ? output_rod(c) : input_rod(c, time);
    return kOfxStatOK;
}

}  // namespace

OfxRectI to_pixels(const OfxRectD& r, OfxPointD s) {
    return {int(std::floor(r.x1 * s.x + 1e-9)), int(std::floor(r.y1 * s.y + 1e-9)), int(std::ceil(r.x2 * s.x - 1e-9)),
            int(std::ceil(r.y2 * s.y - 1e-9))};
}

namespace {

OfxRectI intersect(const OfxRectI& a, const OfxRectI& b) {
    OfxRectI r{std::max(a.x1, b.x1), std::max(a.y1, b.y1), std::min(a.x2, b.x2), std::min(a.y2, b.y2)};
    if (r.x2 <= r.x1 || r.y2 <= r.y1) return {0, 0, 0, 0};
    return r;
}

OfxRectD intersect(const OfxRectD& a, const OfxRectD& b) {
    OfxRectD r{std::max(a.x1, b.x1), std::max(a.y1, b.y1), std::min(a.x2, b.x2), std::min(a.y2, b.y2)};
    if (r.x2 <= r.x1 || r.y2 <= r.y1) return {0, 0, 0, 0};
    return r;
}

void image_props(PropertySet& p, void* data, const OfxRectI& b, const OfxRectI& rod, int rowbytes,
                 const std::string& comps, const std::string& depth, const std::string& premult, OfxPointD s) {
    static std::atomic<long> ids{0};
    p.set(kOfxPropType, std::string(kOfxTypeImage));
    p.set_p(kOfxImagePropData, {data});
    p.set_i(kOfxImagePropBounds, {b.x1, b.y1, b.x2, b.y2});
    p.set_i(kOfxImagePropRegionOfDefinition, {rod.x1, rod.y1, rod.x2, rod.y2});
    p.set_i(kOfxImagePropRowBytes, {rowbytes});
    p.set(kOfxImageEffectPropComponents, comps);
    p.set(kOfxImageEffectPropPixelDepth, depth);
    p.set(kOfxImageEffectPropPreMultiplication, premult);
    p.set_d(kOfxImageEffectPropRenderScale, {s.x, s.y});
    p.set_d(kOfxImagePropPixelAspectRatio, {1.0});
    p.set(kOfxImagePropField, std::string(kOfxImageFieldNone));
    p.set(kOfxImagePropUniqueIdentifier, "img" + std::to_string(++ids));
}

OfxStatus clipGetImage(OfxImageClipHandle clip, OfxTime time, const OfxRectD* region, OfxPropertySetHandle* out) {
    if (!clip || !out) return kOfxStatErrBadHandle;
    Clip& c = *C(clip);
    RenderContext* rc = t_render;
    const OfxPointD s = rc ? rc->scale : OfxPointD{1, 1};
    auto img = std::make_unique<Host::Image>();

    if (c.name == kOfxImageEffectOutputClipName) {
        if (!rc) return kOfxStatFailed;  // only during render
        image_props(img->props, rc->out.data(), rc->window, to_pixels(output_rod(c), s), rc->row_floats * 4,
                    rc->components, kOfxBitDepthFloat, rc->premult, s);
    } else {
        auto it = c.frames.find(int(std::lround(time)));
        if (it == c.frames.end()) return kOfxStatFailed;  // not connected or no such frame
        const ClipFrame& fr = it->second;
        const OfxRectD rod = input_rod(c, time);
        OfxRectD want = rod;
        if (region) want = intersect(*region, rod);
        else if (rc && rc->roi.count(c.name)) want = intersect(rc->roi.at(c.name), rod);
        const int k = int(std::lround(1.0 / s.x));
        if (k < 1 || std::abs(1.0 / s.x - k) > 1e-9 || s.x != s.y) return kOfxStatErrUnsupported;
        const OfxRectI fb = to_pixels(rod, s);
        const OfxRectI b = intersect(to_pixels(want, s), fb);
        const int n = fr.ncomp();
        const int w = b.x2 - b.x1, h = b.y2 - b.y1;
        const int row = w * n + 2;  // padded rows
        // Box-filtered reduction by k (k = 1: a copy).
        std::vector<float> v(std::size_t(std::max(0, row)) * std::size_t(std::max(0, h)), 0.0f);
        for (int y = b.y1; y < b.y2; ++y)
            for (int x = b.x1; x < b.x2; ++x)
                for (int ch = 0; ch < n; ++ch) {
                    double sum = 0;
                    int cnt = 0;
                    const int span = fr.filter == "nearest" ? 1 : k;
                    for (int yy = y * k; yy < y * k + span; ++yy)
                        for (int xx = x * k; xx < x * k + span; ++xx)
                            if (xx >= fr.bounds.x1 && xx < fr.bounds.x2 && yy >= fr.bounds.y1 && yy < fr.bounds.y2) {
                                sum += fr.at(xx, yy, ch);
                                ++cnt;
                            }
                    v[std::size_t(y - b.y1) * std::size_t(row) + std::size_t(x - b.x1) * std::size_t(n) + std::size_t(ch)] =
                        cnt ? float(sum / cnt) : 0.0f;
                }
        const std::string depth = c.effect->honour_clip_preferences ? c.props.str(kOfxImageEffectPropPixelDepth) : fr.depth;
        void* data = nullptr;
        int rowbytes = 0;
        if (depth == kOfxBitDepthByte) {
            img->bytes.resize(v.size());
            for (std::size_t i = 0; i < v.size(); ++i) img->bytes[i] = (unsigned char)std::lround(std::clamp(v[i], 0.0f, 1.0f) * 255);
            data = img->bytes.data();
            rowbytes = row;
        } else if (depth == kOfxBitDepthShort) {
            img->shorts.resize(v.size());
            for (std::size_t i = 0; i < v.size(); ++i) img->shorts[i] = (unsigned short)std::lround(std::clamp(v[i], 0.0f, 1.0f) * 65535);
            data = img->shorts.data();
            rowbytes = row * 2;
        } else {
            img->f = std::move(v);
            data = img->f.data();
            rowbytes = row * 4;
        }
        image_props(img->props, data, b, fb, rowbytes, fr.components, depth, fr.premult, s);
    }
    *out = reinterpret_cast<OfxPropertySetHandle>(&img->props);
    std::lock_guard<std::mutex> lock(g_host->mu);
    g_host->images[&img->props] = std::move(img);
    return kOfxStatOK;
}

OfxStatus clipReleaseImage(OfxPropertySetHandle h) {
    std::lock_guard<std::mutex> lock(g_host->mu);
    return g_host->images.erase(h) ? kOfxStatOK : kOfxStatErrBadHandle;
}

int abort_fn(OfxImageEffectHandle fx) {
    if (!fx) return 0;
    ImageEffect* e = E(fx);
    const long n = ++e->abort_polls;
    return e->abort_after >= 0 && n >= e->abort_after ? 1 : 0;
}

OfxStatus imageMemoryAlloc(OfxImageEffectHandle, size_t n, OfxImageMemoryHandle* h) {
    if (!h) return kOfxStatErrBadHandle;
    void* p = std::malloc(n ? n : 1);
    if (!p) return kOfxStatErrMemory;
    *h = reinterpret_cast<OfxImageMemoryHandle>(p);
    return kOfxStatOK;
}
OfxStatus imageMemoryFree(OfxImageMemoryHandle h) {
    std::free(h);
    return kOfxStatOK;
}
OfxStatus imageMemoryLock(OfxImageMemoryHandle h, void** p) {
    if (!h || !p) return kOfxStatErrBadHandle;
    *p = h;
    return kOfxStatOK;
}
OfxStatus imageMemoryUnlock(OfxImageMemoryHandle) { return kOfxStatOK; }

const OfxImageEffectSuiteV1 kImageEffectSuite = {
    getPropertySet, getParamSet, clipDefine,      clipGetHandle,    clipGetPropertySet, clipGetImage,
    clipReleaseImage, clipGetRegionOfDefinition, abort_fn, imageMemoryAlloc, imageMemoryFree, imageMemoryLock,
    imageMemoryUnlock,
};

}  // namespace

const OfxImageEffectSuiteV1* image_effect_suite() { return &kImageEffectSuite; }

}  // namespace gdof::ofxtest::detail
