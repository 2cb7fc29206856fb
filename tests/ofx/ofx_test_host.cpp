// The test host: loading the bundle, descriptors, instances and the action
// sequence (see ofx_test_host.h). The suites are in ofx_test_suites_*.cpp.
#include "ofx_test_host.h"

#include <dlfcn.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <thread>

#include "ofx/ofx_test_host_internal.h"

namespace gdof::ofxtest {

using namespace detail;

namespace detail {
Host* g_host = nullptr;
}

// ---------------------------------------------------------------------------
// Data helpers

int Property::size() const {
    switch (type) {
        case String: return int(s.size());
        case Int: return int(i.size());
        case Double: return int(d.size());
        case Pointer: return int(p.size());
    }
    return 0;
}

int PropertySet::size(const std::string& n) const {
    auto it = props.find(n);
    return it == props.end() ? 0 : it->second.size();
}
std::string PropertySet::str(const std::string& n, int index) const {
    auto it = props.find(n);
    if (it == props.end() || it->second.type != Property::String || index >= int(it->second.s.size())) return "";
    return it->second.s[std::size_t(index)];
}
int PropertySet::integer(const std::string& n, int index, int fallback) const {
    auto it = props.find(n);
    if (it == props.end() || it->second.type != Property::Int || index >= int(it->second.i.size())) return fallback;
    return it->second.i[std::size_t(index)];
}
double PropertySet::dbl(const std::string& n, int index, double fallback) const {
    auto it = props.find(n);
    if (it == props.end() || it->second.type != Property::Double || index >= int(it->second.d.size())) return fallback;
    return it->second.d[std::size_t(index)];
}
std::vector<std::string> PropertySet::strings(const std::string& n) const {
    auto it = props.find(n);
    return it == props.end() || it->second.type != Property::String ? std::vector<std::string>{} : it->second.s;
}
std::vector<double> PropertySet::doubles(const std::string& n) const {
    auto it = props.find(n);
    return it == props.end() || it->second.type != Property::Double ? std::vector<double>{} : it->second.d;
}
void PropertySet::set(const std::string& n, std::vector<std::string> v) {
    Property& p = props[n];
    p = Property{};
    p.type = Property::String;
    p.s = std::move(v);
}
void PropertySet::set_i(const std::string& n, std::vector<int> v) {
    Property& p = props[n];
    p = Property{};
    p.type = Property::Int;
    p.i = std::move(v);
}
void PropertySet::set_d(const std::string& n, std::vector<double> v) {
    Property& p = props[n];
    p = Property{};
    p.type = Property::Double;
    p.d = std::move(v);
}
void PropertySet::set_p(const std::string& n, std::vector<void*> v) {
    Property& p = props[n];
    p = Property{};
    p.type = Property::Pointer;
    p.p = std::move(v);
}

int ClipFrame::ncomp() const {
    if (components == kOfxImageComponentRGBA) return 4;
    if (components == kOfxImageComponentRGB) return 3;
    if (components == kOfxImageComponentAlpha) return 1;
    return 4;
}

ClipFrame ClipFrame::make(int w, int h, const std::string& components) {
    ClipFrame f;
    f.bounds = {0, 0, w, h};
    f.components = components;
    f.px.assign(std::size_t(w) * std::size_t(h) * std::size_t(f.ncomp()), 0.0f);
    return f;
}

// ---------------------------------------------------------------------------
// Host

Host::Host() {
    if (g_host) throw std::runtime_error("one test host at a time");
    g_host = this;
    ofx_host.host = reinterpret_cast<OfxPropertySetHandle>(&props);
    ofx_host.fetchSuite = fetch_suite;
    props.set(kOfxPropType, std::string(kOfxTypeImageEffectHost));
    props.set(kOfxPropName, std::string("org.gdof.testhost"));
    props.set(kOfxPropLabel, std::string("gdof test host"));
    props.set_i(kOfxPropAPIVersion, {1, 4});
    props.set_i(kOfxImageEffectHostPropIsBackground, {1});
    props.set_i(kOfxImageEffectPropSupportsOverlays, {0});
    props.set_i(kOfxImageEffectPropSupportsMultiResolution, {1});
    props.set_i(kOfxImageEffectPropSupportsTiles, {1});
    props.set_i(kOfxImageEffectPropTemporalClipAccess, {1});
    props.set(kOfxImageEffectPropSupportedComponents,
              std::vector<std::string>{kOfxImageComponentRGBA, kOfxImageComponentRGB, kOfxImageComponentAlpha});
    props.set(kOfxImageEffectPropSupportedContexts,
              std::vector<std::string>{kOfxImageEffectContextFilter, kOfxImageEffectContextGeneral});
    props.set(kOfxImageEffectPropSupportedPixelDepths,
              std::vector<std::string>{kOfxBitDepthFloat, kOfxBitDepthShort, kOfxBitDepthByte});
    props.set_i(kOfxImageEffectPropSupportsMultipleClipDepths, {0});
    props.set_i(kOfxImageEffectPropSupportsMultipleClipPARs, {0});
    props.set_i(kOfxImageEffectPropSetableFrameRate, {0});
    props.set_i(kOfxImageEffectPropSetableFielding, {0});
    props.set_i(kOfxParamHostPropSupportsCustomInteract, {0});
    props.set_i(kOfxParamHostPropSupportsStringAnimation, {0});
    props.set_i(kOfxParamHostPropSupportsChoiceAnimation, {0});
    props.set_i(kOfxParamHostPropSupportsBooleanAnimation, {0});
    props.set_i(kOfxParamHostPropSupportsCustomAnimation, {0});
    props.set_i(kOfxParamHostPropMaxParameters, {-1});
    props.set_i(kOfxParamHostPropMaxPages, {0});
    props.set_i(kOfxParamHostPropPageRowColumnCount, {0, 0});
}

Host::~Host() {
    unload();
    g_host = nullptr;
}

bool Host::load(const std::string& binary, std::string* error) {
    lib_ = ::dlopen(binary.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!lib_) {
        if (error) *error = std::string("dlopen: ") + ::dlerror();
        return false;
    }
    using CountFn = int (*)();
    using GetFn = OfxPlugin* (*)(int);
    auto count = reinterpret_cast<CountFn>(::dlsym(lib_, "OfxGetNumberOfPlugins"));
    auto get = reinterpret_cast<GetFn>(::dlsym(lib_, "OfxGetPlugin"));
    if (!count || !get) {
        if (error) *error = "the bundle does not export OfxGetNumberOfPlugins / OfxGetPlugin";
        return false;
    }
    const int n = count();
    for (int i = 0; i < n; ++i) {
        OfxPlugin* op = get(i);
        if (!op) {
            if (error) *error = "OfxGetPlugin(" + std::to_string(i) + ") returned null";
            return false;
        }
        auto p = std::make_unique<Plugin>();
        p->ofx = op;
        p->id = op->pluginIdentifier ? op->pluginIdentifier : "";
        op->setHost(&ofx_host);
        p->load_status = call(*p, kOfxActionLoad, nullptr, nullptr, nullptr);
        if (p->load_status != kOfxStatOK && p->load_status != kOfxStatReplyDefault) {
            if (error) *error = p->id + ": kOfxActionLoad returned " + std::to_string(p->load_status);
            plugins_.push_back(std::move(p));
            return false;
        }
        plugins_.push_back(std::move(p));
    }
    return true;
}

void Host::unload() {
    for (auto& p : plugins_)
        if (p->load_status == kOfxStatOK || p->load_status == kOfxStatReplyDefault) call(*p, kOfxActionUnload, nullptr, nullptr, nullptr);
    plugins_.clear();
    if (lib_) ::dlclose(lib_);
    lib_ = nullptr;
}

std::vector<std::string> Host::plugin_ids() const {
    std::vector<std::string> ids;
    for (const auto& p : plugins_) ids.push_back(p->id);
    return ids;
}

Plugin* Host::plugin(const std::string& id) {
    for (auto& p : plugins_)
        if (p->id == id) return p.get();
    return nullptr;
}

OfxStatus Host::call(Plugin& p, const char* action, const void* handle, PropertySet* in, PropertySet* out) {
    return p.ofx->mainEntry(action, handle, reinterpret_cast<OfxPropertySetHandle>(in),
                            reinterpret_cast<OfxPropertySetHandle>(out));
}

OfxStatus Host::describe(const std::string& id) {
    Plugin* p = plugin(id);
    if (!p) return kOfxStatErrUnknown;
    p->descriptor = std::make_unique<ImageEffect>();
    p->descriptor->host = this;
    p->descriptor->props.set(kOfxPropType, std::string(kOfxTypeImageEffect));
    return call(*p, kOfxActionDescribe, p->descriptor.get(), nullptr, nullptr);
}

OfxStatus Host::describe_in_context(const std::string& id, const std::string& context) {
    Plugin* p = plugin(id);
    if (!p || !p->descriptor) return kOfxStatErrUnknown;
    auto d = std::make_unique<ImageEffect>();
    d->host = this;
    d->props = p->descriptor->props;
    d->props.set(kOfxImageEffectPropContext, context);
    PropertySet in;
    in.set(kOfxImageEffectPropContext, context);
    const OfxStatus st = call(*p, kOfxImageEffectActionDescribeInContext, d.get(), &in, nullptr);
    p->contexts[context] = std::move(d);
    return st;
}

std::unique_ptr<Instance> Host::create_instance(const std::string& id, const std::string& context, int width, int height) {
    Plugin* p = plugin(id);
    if (!p || !p->contexts.count(context)) return nullptr;
    return std::make_unique<Instance>(*this, *p, context, width, height);
}

int Host::live_images() const {
    std::lock_guard<std::mutex> lock(const_cast<std::mutex&>(mu));
    return int(images.size());
}

// ---------------------------------------------------------------------------
// Instance

Instance::Instance(Host& host, Plugin& plugin, const std::string& context, int width, int height)
    : host_(host), plugin_(plugin), fx_(std::make_unique<ImageEffect>()) {
    const ImageEffect& d = *plugin.contexts.at(context);
    ImageEffect& e = *fx_;
    e.host = &host;
    e.instance = true;
    e.props = d.props;
    e.props.set(kOfxPropType, std::string(kOfxTypeImageEffectInstance));
    e.props.set(kOfxImageEffectPropContext, context);
    e.props.set_p(kOfxPropInstanceData, {nullptr});
    e.props.set_d(kOfxImageEffectPropProjectSize, {double(width), double(height)});
    e.props.set_d(kOfxImageEffectPropProjectOffset, {0.0, 0.0});
    e.props.set_d(kOfxImageEffectPropProjectExtent, {double(width), double(height)});
    e.props.set_d(kOfxImageEffectPropProjectPixelAspectRatio, {1.0});
    e.props.set_d(kOfxImageEffectInstancePropEffectDuration, {1.0});
    e.props.set_i(kOfxImageEffectInstancePropSequentialRender, {0});
    e.props.set_d(kOfxImageEffectPropFrameRate, {24.0});
    e.props.set_i(kOfxPropIsInteractive, {0});
    for (const std::string& name : d.params.order) {
        const Param& dp = *d.params.params.at(name);
        auto p = std::make_unique<Param>();
        p->type = dp.type;
        p->name = dp.name;
        p->props = dp.props;
        if (is_double(p->type)) {
            p->d = dp.props.doubles(kOfxParamPropDefault);
            p->d.resize(std::size_t(value_count(p->type)), 0.0);
        } else if (is_int(p->type)) {
            p->i.assign(std::size_t(value_count(p->type)), 0);
            for (int k = 0; k < value_count(p->type); ++k) p->i[std::size_t(k)] = dp.props.integer(kOfxParamPropDefault, k, 0);
        } else if (is_string(p->type)) {
            p->s = dp.props.str(kOfxParamPropDefault);
        }
        e.params.order.push_back(name);
        e.params.params[name] = std::move(p);
    }
    for (const std::string& name : d.clip_order) {
        auto c = std::make_unique<Clip>();
        c->name = name;
        c->effect = &e;
        c->props = d.clips.at(name)->props;
        const bool output = name == kOfxImageEffectOutputClipName;
        c->props.set_i(kOfxImageClipPropConnected, {output ? 1 : 0});
        c->props.set(kOfxImageEffectPropComponents, std::string(output ? kOfxImageComponentRGBA : kOfxImageComponentNone));
        c->props.set(kOfxImageEffectPropPixelDepth, std::string(output ? kOfxBitDepthFloat : kOfxBitDepthNone));
        c->props.set(kOfxImageEffectPropPreMultiplication, std::string(kOfxImagePreMultiplied));
        c->props.set(kOfxImageClipPropUnmappedComponents, c->props.str(kOfxImageEffectPropComponents));
        c->props.set(kOfxImageClipPropUnmappedPixelDepth, c->props.str(kOfxImageEffectPropPixelDepth));
        c->props.set_d(kOfxImagePropPixelAspectRatio, {1.0});
        c->props.set_i(kOfxImageClipPropContinuousSamples, {0});
        c->props.set(kOfxImageClipPropFieldOrder, std::string(kOfxImageFieldNone));
        c->props.set_d(kOfxImageEffectPropFrameRange, {0.0, 0.0});
        c->props.set_d(kOfxImageEffectPropUnmappedFrameRange, {0.0, 0.0});
        c->props.set_d(kOfxImageEffectPropFrameRate, {24.0});
        e.clip_order.push_back(name);
        e.clips[name] = std::move(c);
    }
    {
        std::lock_guard<std::mutex> lock(host.mu);
        effects_registry().insert(fx_.get());
    }
    create_status_ = host_.call(plugin_, kOfxActionCreateInstance, fx_.get(), nullptr, nullptr);
}

Instance::~Instance() {
    destroy();
    std::lock_guard<std::mutex> lock(host_.mu);
    effects_registry().erase(fx_.get());
}

OfxStatus Instance::destroy() {
    if (destroyed_) return kOfxStatOK;
    destroyed_ = true;
    return host_.call(plugin_, kOfxActionDestroyInstance, fx_.get(), nullptr, nullptr);
}

Param& Instance::param(const std::string& name, const char* type) {
    auto it = fx_->params.params.find(name);
    if (it == fx_->params.params.end()) throw std::runtime_error("no parameter '" + name + "'");
    if (type && it->second->type != type)
        throw std::runtime_error("parameter '" + name + "' is " + it->second->type + ", not " + type);
    return *it->second;
}

void Instance::set(const std::string& name, double v) { param(name, kOfxParamTypeDouble).d.at(0) = v; }
void Instance::set_int(const std::string& name, int v) { param(name, kOfxParamTypeInteger).i.at(0) = v; }
void Instance::set_bool(const std::string& name, bool v) { param(name, kOfxParamTypeBoolean).i.at(0) = v ? 1 : 0; }
void Instance::set_string(const std::string& name, const std::string& v) { param(name, kOfxParamTypeString).s = v; }
void Instance::set2(const std::string& name, double x, double y) {
    Param& p = param(name, kOfxParamTypeDouble2D);
    p.d = {x, y};
}
void Instance::set3(const std::string& name, double x, double y, double z) {
    Param& p = param(name, kOfxParamTypeDouble3D);
    p.d = {x, y, z};
}
void Instance::set_choice(const std::string& name, const std::string& option) {
    Param& p = param(name, kOfxParamTypeChoice);
    const std::vector<std::string> opts = p.props.strings(kOfxParamPropChoiceOption);
    auto it = std::find(opts.begin(), opts.end(), option);
    if (it == opts.end()) throw std::runtime_error("parameter '" + name + "' has no option '" + option + "'");
    p.i.at(0) = int(it - opts.begin());
}

void Instance::connect(const std::string& name, const ClipFrame& img, int frame) {
    auto it = fx_->clips.find(name);
    if (it == fx_->clips.end()) throw std::runtime_error("no clip '" + name + "'");
    Clip& c = *it->second;
    c.frames[frame] = img;
    c.props.set_i(kOfxImageClipPropConnected, {1});
    c.props.set(kOfxImageEffectPropComponents, img.components);
    c.props.set(kOfxImageClipPropUnmappedComponents, img.components);
    c.props.set(kOfxImageEffectPropPixelDepth, img.depth);
    c.props.set(kOfxImageClipPropUnmappedPixelDepth, img.depth);
    c.props.set(kOfxImageEffectPropPreMultiplication, img.premult);
    c.props.set_d(kOfxImageEffectPropFrameRange, {double(c.frames.begin()->first), double(c.frames.rbegin()->first)});
    c.props.set_d(kOfxImageEffectPropUnmappedFrameRange, c.props.doubles(kOfxImageEffectPropFrameRange));
}

void Instance::disconnect(const std::string& name) {
    Clip& c = *fx_->clips.at(name);
    c.frames.clear();
    c.props.set_i(kOfxImageClipPropConnected, {0});
    c.props.set(kOfxImageEffectPropComponents, std::string(kOfxImageComponentNone));
}

OfxStatus Instance::clip_preferences() {
    PropertySet out;
    std::string premult = kOfxImagePreMultiplied;
    for (const std::string& n : fx_->clip_order) {
        Clip& c = *fx_->clips.at(n);
        out.set("OfxImageClipPropComponents_" + n, c.props.str(kOfxImageEffectPropComponents));
        out.set("OfxImageClipPropDepth_" + n, c.props.str(kOfxImageEffectPropPixelDepth));
        out.set_d("OfxImageClipPropPAR_" + n, {1.0});
    }
    out.set(kOfxImageEffectPropPreMultiplication, premult);
    out.set(kOfxImageClipPropFieldOrder, std::string(kOfxImageFieldNone));
    out.set_i(kOfxImageEffectFrameVarying, {0});
    out.set_i(kOfxImageClipPropContinuousSamples, {0});
    out.set_d(kOfxImageEffectPropFrameRate, {24.0});
    const OfxStatus st = host_.call(plugin_, kOfxImageEffectActionGetClipPreferences, fx_.get(), nullptr, &out);
    if (st != kOfxStatOK && st != kOfxStatReplyDefault) return st;
    for (const std::string& n : fx_->clip_order) {
        Clip& c = *fx_->clips.at(n);
        const bool output = n == kOfxImageEffectOutputClipName;
        if (!output && !fx_->honour_clip_preferences) continue;
        if (!output && c.frames.empty()) continue;
        c.props.set(kOfxImageEffectPropPixelDepth, out.str("OfxImageClipPropDepth_" + n));
        if (output) {
            c.props.set(kOfxImageEffectPropComponents, out.str("OfxImageClipPropComponents_" + n));
            c.props.set(kOfxImageEffectPropPreMultiplication, out.str(kOfxImageEffectPropPreMultiplication));
        }
    }
    return st;
}

OfxStatus Instance::region_of_definition(double time, OfxPointD scale, OfxRectD& rod) {
    PropertySet in, out;
    in.set_d(kOfxPropTime, {time});
    in.set_d(kOfxImageEffectPropRenderScale, {scale.x, scale.y});
    // The host's default: the project extent.
    const std::vector<double> ext = fx_->props.doubles(kOfxImageEffectPropProjectExtent);
    out.set_d(kOfxImageEffectPropRegionOfDefinition, {0.0, 0.0, ext[0], ext[1]});
    const OfxStatus st = host_.call(plugin_, kOfxImageEffectActionGetRegionOfDefinition, fx_.get(), &in, &out);
    const std::vector<double> r = out.doubles(kOfxImageEffectPropRegionOfDefinition);
    if (r.size() == 4) rod = {r[0], r[1], r[2], r[3]};
    return st;
}

OfxStatus Instance::regions_of_interest(double time, OfxPointD scale, const OfxRectD& roi,
                                        std::map<std::string, OfxRectD>& rois) {
    PropertySet in, out;
    in.set_d(kOfxPropTime, {time});
    in.set_d(kOfxImageEffectPropRenderScale, {scale.x, scale.y});
    in.set_d(kOfxImageEffectPropRegionOfInterest, {roi.x1, roi.y1, roi.x2, roi.y2});
    for (const std::string& n : fx_->clip_order)
        if (n != kOfxImageEffectOutputClipName) out.set_d("OfxImageClipPropRoI_" + n, {roi.x1, roi.y1, roi.x2, roi.y2});
    const OfxStatus st = host_.call(plugin_, kOfxImageEffectActionGetRegionsOfInterest, fx_.get(), &in, &out);
    rois.clear();
    for (const std::string& n : fx_->clip_order) {
        const std::vector<double> r = out.doubles("OfxImageClipPropRoI_" + n);
        if (r.size() == 4) rois[n] = {r[0], r[1], r[2], r[3]};
    }
    return st;
}

OfxStatus Instance::frames_needed(double time, std::map<std::string, std::vector<double>>& ranges) {
    PropertySet in, out;
    in.set_d(kOfxPropTime, {time});
    for (const std::string& n : fx_->clip_order)
        if (n != kOfxImageEffectOutputClipName) out.set_d("OfxImageClipPropFrameRange_" + n, {time, time});
    const OfxStatus st = host_.call(plugin_, kOfxImageEffectActionGetFramesNeeded, fx_.get(), &in, &out);
    ranges.clear();
    for (const std::string& n : fx_->clip_order)
        if (out.has("OfxImageClipPropFrameRange_" + n)) ranges[n] = out.doubles("OfxImageClipPropFrameRange_" + n);
    return st;
}

OfxStatus Instance::render_tile(double time, OfxPointD scale, const OfxRectI& tile, Rendered& out, std::mutex& out_mu) {
    RenderContext rc;
    rc.fx = fx_.get();
    rc.scale = scale;
    rc.window = tile;
    const Clip& oc = *fx_->clips.at(kOfxImageEffectOutputClipName);
    rc.components = oc.props.str(kOfxImageEffectPropComponents);
    rc.premult = oc.props.str(kOfxImageEffectPropPreMultiplication);
    rc.ncomp = rc.components == kOfxImageComponentRGB ? 3 : rc.components == kOfxImageComponentAlpha ? 1 : 4;
    const int w = tile.x2 - tile.x1, h = tile.y2 - tile.y1;
    rc.row_floats = w * rc.ncomp + kGuard;
    rc.out.assign(std::size_t(rc.row_floats) * std::size_t(h), std::numeric_limits<float>::quiet_NaN());
    for (int y = 0; y < h; ++y)
        for (int g = 0; g < kGuard; ++g) rc.out[std::size_t(y) * std::size_t(rc.row_floats) + std::size_t(w * rc.ncomp + g)] = kGuardValue;

    OfxStatus st = regions_of_interest(time, scale, canonical(tile, scale), rc.roi);
    if (st != kOfxStatOK && st != kOfxStatReplyDefault) return st;
    PropertySet in;
    in.set_d(kOfxPropTime, {time});
    in.set(kOfxImageEffectPropFieldToRender, std::string(kOfxImageFieldNone));
    in.set_i(kOfxImageEffectPropRenderWindow, {tile.x1, tile.y1, tile.x2, tile.y2});
    in.set_d(kOfxImageEffectPropRenderScale, {scale.x, scale.y});
    in.set_i(kOfxImageEffectPropSequentialRenderStatus, {0});
    in.set_i(kOfxImageEffectPropInteractiveRenderStatus, {0});
    in.set_i(kOfxImageEffectPropRenderQualityDraft, {0});
    t_render = &rc;
    st = host_.call(plugin_, kOfxImageEffectActionRender, fx_.get(), &in, nullptr);
    t_render = nullptr;

    std::lock_guard<std::mutex> lock(out_mu);
    for (int y = 0; y < h; ++y) {
        const float* row = rc.out.data() + std::size_t(y) * std::size_t(rc.row_floats);
        for (int g = 0; g < kGuard; ++g)
            if (row[w * rc.ncomp + g] != kGuardValue) out.wrote_outside = true;
        for (int x = 0; x < w; ++x) {
            const int ox = tile.x1 + x, oy = tile.y1 + y;
            if (ox < out.bounds.x1 || ox >= out.bounds.x2 || oy < out.bounds.y1 || oy >= out.bounds.y2) continue;
            for (int c = 0; c < out.ncomp; ++c)
                out.px[(std::size_t(oy - out.bounds.y1) * std::size_t(out.bounds.x2 - out.bounds.x1) + std::size_t(ox - out.bounds.x1)) *
                           std::size_t(out.ncomp) + std::size_t(c)] = row[x * rc.ncomp + c];
        }
    }
    return st;
}

Rendered Instance::render(double time, OfxPointD scale, const std::vector<OfxRectI>& tiles, bool concurrent) {
    Rendered r;
    r.status = clip_preferences();
    if (r.status != kOfxStatOK && r.status != kOfxStatReplyDefault) return r;
    OfxRectD rod{0, 0, 0, 0};
    r.status = region_of_definition(time, scale, rod);
    if (r.status != kOfxStatOK && r.status != kOfxStatReplyDefault) return r;
    Clip& oc = *fx_->clips.at(kOfxImageEffectOutputClipName);
    oc.props.set_d("testhost:RoD", {rod.x1, rod.y1, rod.x2, rod.y2});
    r.bounds = to_pixels(rod, scale);
    const std::string comps = oc.props.str(kOfxImageEffectPropComponents);
    r.ncomp = comps == kOfxImageComponentRGB ? 3 : comps == kOfxImageComponentAlpha ? 1 : 4;
    r.px.assign(std::size_t(std::max(0, r.bounds.x2 - r.bounds.x1)) * std::size_t(std::max(0, r.bounds.y2 - r.bounds.y1)) *
                    std::size_t(r.ncomp),
                std::numeric_limits<float>::quiet_NaN());
    std::vector<OfxRectI> to_render = tiles.empty() ? std::vector<OfxRectI>{r.bounds} : tiles;

    PropertySet seq;
    seq.set_d(kOfxImageEffectPropFrameRange, {time, time});
    seq.set_d(kOfxImageEffectPropFrameStep, {1.0});
    seq.set_i(kOfxPropIsInteractive, {0});
    seq.set_d(kOfxImageEffectPropRenderScale, {scale.x, scale.y});
    seq.set_i(kOfxImageEffectPropSequentialRenderStatus, {0});
    seq.set_i(kOfxImageEffectPropInteractiveRenderStatus, {0});
    host_.call(plugin_, kOfxImageEffectActionBeginSequenceRender, fx_.get(), &seq, nullptr);

    std::mutex out_mu;
    std::vector<OfxStatus> status(to_render.size(), kOfxStatOK);
    if (concurrent) {
        std::vector<std::thread> threads;
        for (std::size_t i = 0; i < to_render.size(); ++i)
            threads.emplace_back([&, i] { status[i] = render_tile(time, scale, to_render[i], r, out_mu); });
        for (auto& t : threads) t.join();
    } else {
        for (std::size_t i = 0; i < to_render.size(); ++i) status[i] = render_tile(time, scale, to_render[i], r, out_mu);
    }
    host_.call(plugin_, kOfxImageEffectActionEndSequenceRender, fx_.get(), &seq, nullptr);
    r.status = kOfxStatOK;
    for (OfxStatus s : status)
        if (s != kOfxStatOK) r.status = s;
    return r;
}

}  // namespace gdof::ofxtest
