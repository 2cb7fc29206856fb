// The bundle's two exported entry points, the host pointer and its suites.
#include <cstring>

#include "effects.h"
#include "ofx_effect.h"

namespace gdof::ofx {

Suites& suites() {
    static Suites s;
    return s;
}

const char* status_name(OfxStatus st) {
    switch (st) {
        case kOfxStatOK: return "kOfxStatOK";
        case kOfxStatFailed: return "kOfxStatFailed";
        case kOfxStatErrFatal: return "kOfxStatErrFatal";
        case kOfxStatErrUnknown: return "kOfxStatErrUnknown";
        case kOfxStatErrMissingHostFeature: return "kOfxStatErrMissingHostFeature";
        case kOfxStatErrUnsupported: return "kOfxStatErrUnsupported";
        case kOfxStatErrExists: return "kOfxStatErrExists";
        case kOfxStatErrFormat: return "kOfxStatErrFormat";
        case kOfxStatErrMemory: return "kOfxStatErrMemory";
        case kOfxStatErrBadHandle: return "kOfxStatErrBadHandle";
        case kOfxStatErrBadIndex: return "kOfxStatErrBadIndex";
        case kOfxStatErrValue: return "kOfxStatErrValue";
        case kOfxStatReplyDefault: return "kOfxStatReplyDefault";
        default: return "unknown status";
    }
}

void check(OfxStatus st, const std::string& what) {
    if (st != kOfxStatOK) fail(what + ": the host answered " + status_name(st), st == kOfxStatErrMemory ? st : kOfxStatFailed);
}

namespace {

void set_host(OfxHost* host) {
    Suites& s = suites();
    s = Suites{};
    s.host = host;
    if (!host || !host->fetchSuite) return;
    auto fetch = [&](const char* name, int version) { return host->fetchSuite(host->host, name, version); };
    s.prop = static_cast<const OfxPropertySuiteV1*>(fetch(kOfxPropertySuite, 1));
    s.param = static_cast<const OfxParameterSuiteV1*>(fetch(kOfxParameterSuite, 1));
    s.effect = static_cast<const OfxImageEffectSuiteV1*>(fetch(kOfxImageEffectSuite, 1));
    s.message2 = static_cast<const OfxMessageSuiteV2*>(fetch(kOfxMessageSuite, 2));
    s.message1 = static_cast<const OfxMessageSuiteV1*>(fetch(kOfxMessageSuite, 1));
    s.thread = static_cast<const OfxMultiThreadSuiteV1*>(fetch(kOfxMultiThreadSuite, 1));
}

OfxStatus defocus_main(const char* action, const void* handle, OfxPropertySetHandle in, OfxPropertySetHandle out) {
    return dispatch(defocus_effect(), action, handle, in, out);
}

OfxStatus focal_stack_main(const char* action, const void* handle, OfxPropertySetHandle in, OfxPropertySetHandle out) {
    return dispatch(focal_stack_effect(), action, handle, in, out);
}

OfxPlugin plugins[] = {
    {kOfxImageEffectPluginApi, 1, "org.gdof.Defocus", 0, 1, set_host, defocus_main},
    {kOfxImageEffectPluginApi, 1, "org.gdof.FocalStack", 0, 1, set_host, focal_stack_main},
};

}  // namespace

}  // namespace gdof::ofx

OfxExport int OfxGetNumberOfPlugins(void) { return int(sizeof gdof::ofx::plugins / sizeof gdof::ofx::plugins[0]); }

OfxExport OfxPlugin* OfxGetPlugin(int nth) {
    if (nth < 0 || nth >= OfxGetNumberOfPlugins()) return nullptr;
    return &gdof::ofx::plugins[nth];
}
