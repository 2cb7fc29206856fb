// Internals shared by the test host's files: the one host, the render in
// progress on a thread, the suites and small geometry helpers.
#pragma once

#include <set>
#include <string>

#include "ofx/ofx_test_host.h"

namespace gdof::ofxtest::detail {

extern Host* g_host;  // one host at a time
constexpr int kGuard = 3;  // guard floats after each output row
constexpr float kGuardValue = -12345.0f;

// The render in progress on this thread (the output image and the regions of interest).
struct RenderContext {
    ImageEffect* fx = nullptr;
    OfxPointD scale{1, 1};
    OfxRectI window{0, 0, 0, 0};
    std::map<std::string, OfxRectD> roi;
    std::vector<float> out;  // window rows + guards
    int ncomp = 4;
    std::string components;
    std::string premult;
    int row_floats = 0;
};
extern thread_local RenderContext* t_render;

// Effects (descriptors and instances) messages may be posted to.
std::set<const void*>& effects_registry();

// Parameter types: values per parameter and their C type.
int value_count(const std::string& type);
bool is_double(const std::string& type);
bool is_int(const std::string& type);
bool is_string(const std::string& type);

// Canonical <-> pixel rectangles at a render scale (outward rounding).
OfxRectI to_pixels(const OfxRectD& r, OfxPointD s);
OfxRectD canonical(const OfxRectI& r, OfxPointD s);

const OfxPropertySuiteV1* property_suite();    // ofx_test_suites_params.cpp
const OfxParameterSuiteV1* parameter_suite();  // ofx_test_suites_params.cpp
const OfxImageEffectSuiteV1* image_effect_suite();  // ofx_test_suites_effect.cpp
// OfxHost::fetchSuite (ofx_test_suites_misc.cpp): also messages, threads, memory.
const void* fetch_suite(OfxPropertySetHandle host, const char* name, int version);

}  // namespace gdof::ofxtest::detail
