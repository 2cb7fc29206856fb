#include "ofx_params.h"

namespace gdof::ofx {

namespace {

const OfxParameterSuiteV1& pm() {
    const OfxParameterSuiteV1* s = suites().param;
    if (!s) fail("the host's parameter suite is not available", kOfxStatErrMissingHostFeature);
    return *s;
}

OfxParamSetHandle param_set(OfxImageEffectHandle effect) {
    OfxParamSetHandle set = nullptr;
    check(suites().effect->getParamSet(effect, &set), "getting the parameter set");
    return set;
}

}  // namespace

ParamDefiner::ParamDefiner(OfxImageEffectHandle descriptor) : set_(param_set(descriptor)) {}

Props ParamDefiner::define(const char* type, const char* name, const char* label, const char* hint) {
    OfxPropertySetHandle h = nullptr;
    check(pm().paramDefine(set_, type, name, &h), std::string("defining parameter '") + name + "'");
    Props p(h);
    p.set(kOfxPropLabel, label);
    p.set(kOfxParamPropScriptName, name);
    if (hint && *hint) p.set(kOfxParamPropHint, hint);
    if (!group_.empty()) p.set(kOfxParamPropParent, group_);
    return p;
}

Props ParamDefiner::group(const char* name, const char* label, bool open) {
    const std::string keep = group_;
    group_.clear();
    Props p = define(kOfxParamTypeGroup, name, label, "");
    p.set(kOfxParamPropGroupOpen, open ? 1 : 0);
    group_ = keep;
    return p;
}

Props ParamDefiner::number(const char* name, const char* label, double def, double min, double max,
                           double display_min, double display_max, const char* hint) {
    Props p = define(kOfxParamTypeDouble, name, label, hint);
    p.set(kOfxParamPropDoubleType, kOfxParamDoubleTypePlain);
    p.set(kOfxParamPropDefault, def);
    p.set(kOfxParamPropMin, min);
    p.set(kOfxParamPropMax, max);
    p.set(kOfxParamPropDisplayMin, display_min);
    p.set(kOfxParamPropDisplayMax, display_max);
    p.set(kOfxParamPropDigits, 4);
    return p;
}

Props ParamDefiner::integer(const char* name, const char* label, int def, int min, int max, const char* hint) {
    Props p = define(kOfxParamTypeInteger, name, label, hint);
    p.set(kOfxParamPropDefault, def);
    p.set(kOfxParamPropMin, min);
    p.set(kOfxParamPropMax, max);
    p.set(kOfxParamPropDisplayMin, min);
    p.set(kOfxParamPropDisplayMax, max);
    return p;
}

Props ParamDefiner::boolean(const char* name, const char* label, bool def, const char* hint) {
    Props p = define(kOfxParamTypeBoolean, name, label, hint);
    p.set(kOfxParamPropDefault, def ? 1 : 0);
    return p;
}

Props ParamDefiner::choice(const char* name, const char* label, const std::vector<std::string>& options, int def,
                           const char* hint) {
    Props p = define(kOfxParamTypeChoice, name, label, hint);
    p.set_strings(kOfxParamPropChoiceOption, options);
    p.set(kOfxParamPropDefault, def);
    return p;
}

Props ParamDefiner::point3(const char* name, const char* label, std::array<double, 3> def, const char* hint) {
    Props p = define(kOfxParamTypeDouble3D, name, label, hint);
    p.set(kOfxParamPropDoubleType, kOfxParamDoubleTypePlain);
    p.set_doubles(kOfxParamPropDefault, {def[0], def[1], def[2]});
    return p;
}

Props ParamDefiner::point2(const char* name, const char* label, std::array<double, 2> def, const char* hint) {
    Props p = define(kOfxParamTypeDouble2D, name, label, hint);
    p.set(kOfxParamPropDoubleType, kOfxParamDoubleTypeXYAbsolute);
    p.set_doubles(kOfxParamPropDefault, {def[0], def[1]});
    return p;
}

Props ParamDefiner::text(const char* name, const char* label, const char* def, const char* mode, const char* hint) {
    Props p = define(kOfxParamTypeString, name, label, hint);
    p.set(kOfxParamPropDefault, def);
    p.set(kOfxParamPropStringMode, mode);
    if (std::string(mode) == kOfxParamStringIsFilePath) p.set(kOfxParamPropStringFilePathExists, 1);
    p.set(kOfxParamPropAnimates, 0);
    return p;
}

ParamReader::ParamReader(OfxImageEffectHandle instance, double time) : set_(param_set(instance)), time_(time) {}

OfxParamHandle ParamReader::handle(const char* name) const {
    OfxParamHandle h = nullptr;
    check(pm().paramGetHandle(set_, name, &h, nullptr), std::string("parameter '") + name + "'");
    return h;
}

double ParamReader::number(const char* name) const {
    double v = 0;
    check(pm().paramGetValueAtTime(handle(name), time_, &v), std::string("reading parameter '") + name + "'");
    return v;
}

int ParamReader::integer(const char* name) const {
    int v = 0;
    check(pm().paramGetValueAtTime(handle(name), time_, &v), std::string("reading parameter '") + name + "'");
    return v;
}

bool ParamReader::boolean(const char* name) const { return integer(name) != 0; }

int ParamReader::choice(const char* name) const { return integer(name); }

std::string ParamReader::option(const char* name, const std::vector<std::string>& options) const {
    const int i = choice(name);
    if (i < 0 || i >= int(options.size())) fail(std::string("parameter '") + name + "': option " + std::to_string(i) + " out of range");
    return options[std::size_t(i)];
}

std::array<double, 3> ParamReader::point3(const char* name) const {
    std::array<double, 3> v{};
    check(pm().paramGetValueAtTime(handle(name), time_, &v[0], &v[1], &v[2]),
          std::string("reading parameter '") + name + "'");
    return v;
}

std::array<double, 2> ParamReader::point2(const char* name) const {
    std::array<double, 2> v{};
    check(pm().paramGetValueAtTime(handle(name), time_, &v[0], &v[1]), std::string("reading parameter '") + name + "'");
    return v;
}

std::string ParamReader::text(const char* name) const {
    const char* v = nullptr;
    check(pm().paramGetValueAtTime(handle(name), time_, &v), std::string("reading parameter '") + name + "'");
    return v ? std::string(v) : std::string();
}

}  // namespace gdof::ofx
