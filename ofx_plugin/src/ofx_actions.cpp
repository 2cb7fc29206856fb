// OFX actions -> Effect calls, with the C boundary: every exception becomes a
// status (and, for instance actions, a persistent error message).
#include <cstring>
#include <new>

#include "ofx_effect.h"

namespace gdof::ofx {

namespace {

bool is(const char* action, const char* name) { return std::strcmp(action, name) == 0; }

Props effect_props(OfxImageEffectHandle effect) {
    OfxPropertySetHandle h = nullptr;
    check(suites().effect->getPropertySet(effect, &h), "effect properties");
    return Props(h);
}

void describe(Effect& e, OfxImageEffectHandle descriptor) {
    Props p = effect_props(descriptor);
    p.set(kOfxPropLabel, e.label());
    p.set(kOfxPropShortLabel, e.label());
    p.set(kOfxPropLongLabel, e.label());
    p.set(kOfxPropPluginDescription, e.description());
    p.set(kOfxImageEffectPluginPropGrouping, "gdof");
    p.set_strings(kOfxImageEffectPropSupportedContexts, {kOfxImageEffectContextFilter, kOfxImageEffectContextGeneral});
    p.set_strings(kOfxImageEffectPropSupportedPixelDepths, {kOfxBitDepthFloat});
    p.set(kOfxImageEffectPluginPropSingleInstance, 0);
    // Renders read parameters and clips only: instances may render concurrently.
    p.set(kOfxImageEffectPluginRenderThreadSafety, kOfxImageEffectRenderFullySafe);
    // The library threads itself (TBB); the host should not split frames.
    p.set(kOfxImageEffectPluginPropHostFrameThreading, 0);
    p.set(kOfxImageEffectPropSupportsMultiResolution, 1);
    p.set(kOfxImageEffectPropSupportsTiles, 1);
    p.set(kOfxImageEffectPropTemporalClipAccess, e.temporal_clip_access() ? 1 : 0);
    p.set(kOfxImageEffectPropSupportsMultipleClipDepths, 0);
    p.set(kOfxImageEffectPropSupportsMultipleClipPARs, 0);
    p.set(kOfxImageEffectPluginPropFieldRenderTwiceAlways, 0);
}

OfxPointD render_scale(const Props& in) {
    return {in.double_or(kOfxImageEffectPropRenderScale, 1.0, 0), in.double_or(kOfxImageEffectPropRenderScale, 1.0, 1)};
}

OfxStatus run(Effect& e, const char* action, const void* handle, OfxPropertySetHandle inh, OfxPropertySetHandle outh) {
    auto effect = static_cast<OfxImageEffectHandle>(const_cast<void*>(handle));
    const Props in(inh), out(outh);

    if (is(action, kOfxActionLoad) || is(action, kOfxActionUnload)) return kOfxStatOK;
    if (is(action, kOfxActionDescribe)) {
        describe(e, effect);
        return kOfxStatOK;
    }
    if (is(action, kOfxImageEffectActionDescribeInContext)) {
        const std::string context = in.get_string(kOfxImageEffectPropContext);
        if (context != kOfxImageEffectContextFilter && context != kOfxImageEffectContextGeneral)
            return kOfxStatErrMissingHostFeature;
        e.describe_in_context(effect, context);
        return kOfxStatOK;
    }
    if (is(action, kOfxActionCreateInstance) || is(action, kOfxActionDestroyInstance)) return kOfxStatOK;
    if (is(action, kOfxImageEffectActionGetClipPreferences)) {
        e.clip_preferences(effect, out);
        return kOfxStatOK;
    }
    if (is(action, kOfxImageEffectActionGetRegionOfDefinition)) {
        OfxRectD rod{0, 0, 0, 0};
        if (!e.region_of_definition(effect, in.get_double(kOfxPropTime), render_scale(in), rod))
            return kOfxStatReplyDefault;
        out.set_doubles(kOfxImageEffectPropRegionOfDefinition, {rod.x1, rod.y1, rod.x2, rod.y2});
        return kOfxStatOK;
    }
    if (is(action, kOfxImageEffectActionGetRegionsOfInterest)) {
        const std::vector<double> r = in.get_doubles(kOfxImageEffectPropRegionOfInterest, 4);
        e.regions_of_interest(effect, in.get_double(kOfxPropTime), render_scale(in), {r[0], r[1], r[2], r[3]}, out);
        return kOfxStatOK;
    }
    if (is(action, kOfxImageEffectActionGetFramesNeeded))
        return e.frames_needed(effect, in.get_double(kOfxPropTime), out) ? kOfxStatOK : kOfxStatReplyDefault;
    if (is(action, kOfxImageEffectActionRender)) {
        RenderArgs a;
        a.time = in.get_double(kOfxPropTime);
        a.scale = render_scale(in);
        const std::vector<int> w = in.get_ints(kOfxImageEffectPropRenderWindow, 4);
        a.window = {w[0], w[1], w[2], w[3]};
        e.render(effect, a);
        if (suites().message2) suites().message2->clearPersistentMessage(effect);
        return kOfxStatOK;
    }
    return kOfxStatReplyDefault;  // begin/end sequence, isIdentity, instanceChanged, ...
}

// Instance actions may post a persistent message; descriptor actions may not.
bool instance_action(const char* action) {
    return !(is(action, kOfxActionLoad) || is(action, kOfxActionUnload) || is(action, kOfxActionDescribe) ||
             is(action, kOfxImageEffectActionDescribeInContext));
}

void post_error(const void* handle, const std::string& message) {
    void* h = const_cast<void*>(handle);
    if (suites().message2)
        suites().message2->setPersistentMessage(h, kOfxMessageError, "", "%s", message.c_str());
    else if (suites().message1)
        suites().message1->message(h, kOfxMessageError, "", "%s", message.c_str());
}

}  // namespace

Exec render_exec(OfxImageEffectHandle instance) {
    Exec e;
    unsigned n = 0;
    if (suites().thread && suites().thread->multiThreadNumCPUs(&n) == kOfxStatOK) e.nthreads = int(n);
    e.cancelled = [instance] { return suites().effect->abort(instance) != 0; };
    return e;
}

OfxStatus dispatch(Effect& e, const char* action, const void* handle, OfxPropertySetHandle in, OfxPropertySetHandle out) {
    if (!action) return kOfxStatErrBadHandle;
    if (!suites().prop || !suites().param || !suites().effect)
        return is(action, kOfxActionLoad) || is(action, kOfxActionDescribe) ? kOfxStatErrMissingHostFeature
                                                                           : kOfxStatFailed;
    std::string message;
    OfxStatus status = kOfxStatFailed;
    try {
        return run(e, action, handle, in, out);
    } catch (const Error& err) {
        message = err.what();
        status = err.status;
    } catch (const std::bad_alloc&) {
        message = "out of memory";
        status = kOfxStatErrMemory;
    } catch (const std::exception& err) {
        message = err.what();
    } catch (...) {
        message = "unknown error";
    }
    if (instance_action(action) && handle) {
        try {
            post_error(handle, std::string(e.label()) + ": " + message);
        } catch (...) {
        }
    }
    return status;
}

}  // namespace gdof::ofx
