// The OpenFX C API as the plugin uses it: the host's suites (fetched once at
// load) and the glue's one error type. Everything else in ofx_plugin/ builds
// on this; no OFX Support library is used.
#pragma once

#include <stdexcept>
#include <string>

#include "ofxCore.h"
#include "ofxImageEffect.h"
#include "ofxMessage.h"
#include "ofxMultiThread.h"
#include "ofxParam.h"
#include "ofxProperty.h"

namespace gdof::ofx {

// The host and its suites. The first three are required (load fails without
// them); the others may be null.
struct Suites {
    OfxHost* host = nullptr;
    const OfxPropertySuiteV1* prop = nullptr;
    const OfxParameterSuiteV1* param = nullptr;
    const OfxImageEffectSuiteV1* effect = nullptr;
    const OfxMessageSuiteV2* message2 = nullptr;
    const OfxMessageSuiteV1* message1 = nullptr;
    const OfxMultiThreadSuiteV1* thread = nullptr;
};
Suites& suites();

// An error inside an action: thrown by the glue and the effects, turned into a
// persistent message and a status at the C boundary (ofx_actions.cpp).
struct Error : std::runtime_error {
    OfxStatus status;
    Error(const std::string& what, OfxStatus st = kOfxStatFailed) : std::runtime_error(what), status(st) {}
};
[[noreturn]] inline void fail(const std::string& what, OfxStatus st = kOfxStatFailed) { throw Error(what, st); }

// Throws an Error naming `what` unless st is kOfxStatOK.
void check(OfxStatus st, const std::string& what);
// Name of a status code ("kOfxStatErrUnknown").
const char* status_name(OfxStatus st);

}  // namespace gdof::ofx
