// The test host's property and parameter suites.
#include <cstdarg>
#include <set>
#include <string>
#include <vector>

#include "ofx/ofx_test_host_internal.h"

namespace gdof::ofxtest::detail {

namespace {

// ---------------------------------------------------------------------------
// Properties

PropertySet* P(OfxPropertySetHandle h) { return reinterpret_cast<PropertySet*>(h); }

template <class T>
std::vector<T>& values(Property& p);
template <> std::vector<std::string>& values(Property& p) { return p.s; }
template <> std::vector<int>& values(Property& p) { return p.i; }
template <> std::vector<double>& values(Property& p) { return p.d; }
template <> std::vector<void*>& values(Property& p) { return p.p; }

template <class T> constexpr Property::Type type_of();
template <> constexpr Property::Type type_of<std::string>() { return Property::String; }
template <> constexpr Property::Type type_of<int>() { return Property::Int; }
template <> constexpr Property::Type type_of<double>() { return Property::Double; }
template <> constexpr Property::Type type_of<void*>() { return Property::Pointer; }

template <class T>
OfxStatus prop_set(OfxPropertySetHandle h, const char* name, int index, const T& v) {
    if (!h || !name) return kOfxStatErrBadHandle;
    if (index < 0) return kOfxStatErrBadIndex;
    auto& props = P(h)->props;
    auto it = props.find(name);
    if (it == props.end()) {
        Property p;
        p.type = type_of<T>();
        it = props.emplace(name, std::move(p)).first;
    }
    Property& p = it->second;
    if (p.type != type_of<T>()) return kOfxStatErrValue;
    auto& vec = values<T>(p);
    if (std::size_t(index) >= vec.size()) vec.resize(std::size_t(index) + 1);
    vec[std::size_t(index)] = v;
    return kOfxStatOK;
}

template <class T>
OfxStatus prop_get(OfxPropertySetHandle h, const char* name, int index, T* out) {
    if (!h || !name || !out) return kOfxStatErrBadHandle;
    auto& props = P(h)->props;
    auto it = props.find(name);
    if (it == props.end()) return kOfxStatErrUnknown;
    if (it->second.type != type_of<T>()) return kOfxStatErrValue;
    auto& vec = values<T>(it->second);
    if (index < 0 || std::size_t(index) >= vec.size()) return kOfxStatErrBadIndex;
    *out = vec[std::size_t(index)];
    return kOfxStatOK;
}

OfxStatus propSetPointer(OfxPropertySetHandle h, const char* n, int i, void* v) { return prop_set<void*>(h, n, i, v); }
OfxStatus propSetString(OfxPropertySetHandle h, const char* n, int i, const char* v) {
    return v ? prop_set<std::string>(h, n, i, std::string(v)) : kOfxStatErrValue;
}
OfxStatus propSetDouble(OfxPropertySetHandle h, const char* n, int i, double v) { return prop_set<double>(h, n, i, v); }
OfxStatus propSetInt(OfxPropertySetHandle h, const char* n, int i, int v) { return prop_set<int>(h, n, i, v); }
OfxStatus propSetPointerN(OfxPropertySetHandle h, const char* n, int c, void* const* v) {
    for (int i = 0; i < c; ++i)
        if (OfxStatus s = propSetPointer(h, n, i, v[i]); s != kOfxStatOK) return s;
    return kOfxStatOK;
}
OfxStatus propSetStringN(OfxPropertySetHandle h, const char* n, int c, const char* const* v) {
    for (int i = 0; i < c; ++i)
        if (OfxStatus s = propSetString(h, n, i, v[i]); s != kOfxStatOK) return s;
    return kOfxStatOK;
}
OfxStatus propSetDoubleN(OfxPropertySetHandle h, const char* n, int c, const double* v) {
    for (int i = 0; i < c; ++i)
        if (OfxStatus s = propSetDouble(h, n, i, v[i]); s != kOfxStatOK) return s;
    return kOfxStatOK;
}
OfxStatus propSetIntN(OfxPropertySetHandle h, const char* n, int c, const int* v) {
    for (int i = 0; i < c; ++i)
        if (OfxStatus s = propSetInt(h, n, i, v[i]); s != kOfxStatOK) return s;
    return kOfxStatOK;
}
OfxStatus propGetPointer(OfxPropertySetHandle h, const char* n, int i, void** v) { return prop_get<void*>(h, n, i, v); }
OfxStatus propGetString(OfxPropertySetHandle h, const char* n, int i, const char** v) {
    if (!h || !n || !v) return kOfxStatErrBadHandle;
    auto& props = P(h)->props;
    auto it = props.find(n);
    if (it == props.end()) return kOfxStatErrUnknown;
    if (it->second.type != Property::String) return kOfxStatErrValue;
    if (i < 0 || std::size_t(i) >= it->second.s.size()) return kOfxStatErrBadIndex;
    *v = it->second.s[std::size_t(i)].c_str();
    return kOfxStatOK;
}
OfxStatus propGetDouble(OfxPropertySetHandle h, const char* n, int i, double* v) { return prop_get<double>(h, n, i, v); }
OfxStatus propGetInt(OfxPropertySetHandle h, const char* n, int i, int* v) { return prop_get<int>(h, n, i, v); }
OfxStatus propGetPointerN(OfxPropertySetHandle h, const char* n, int c, void** v) {
    for (int i = 0; i < c; ++i)
        if (OfxStatus s = propGetPointer(h, n, i, v + i); s != kOfxStatOK) return s;
    return kOfxStatOK;
}
OfxStatus propGetStringN(OfxPropertySetHandle h, const char* n, int c, const char** v) {
    for (int i = 0; i < c; ++i)
        if (OfxStatus s = propGetString(h, n, i, v + i); s != kOfxStatOK) return s;
    return kOfxStatOK;
}
OfxStatus propGetDoubleN(OfxPropertySetHandle h, const char* n, int c, double* v) {
    for (int i = 0; i < c; ++i)
        if (OfxStatus s = propGetDouble(h, n, i, v + i); s != kOfxStatOK) return s;
    return kOfxStatOK;
}
OfxStatus propGetIntN(OfxPropertySetHandle h, const char* n, int c, int* v) {
    for (int i = 0; i < c; ++i)
        if (OfxStatus s = propGetInt(h, n, i, v + i); s != kOfxStatOK) return s;
    return kOfxStatOK;
}
OfxStatus propReset(OfxPropertySetHandle h, const char* n) {
    if (!h || !n) return kOfxStatErrBadHandle;
    return P(h)->has(n) ? kOfxStatOK : kOfxStatErrUnknown;
}
OfxStatus propGetDimension(OfxPropertySetHandle h, const char* n, int* count) {
    if (!h || !n || !count) return kOfxStatErrBadHandle;
    auto it = P(h)->props.find(n);
    if (it == P(h)->props.end()) return kOfxStatErrUnknown;
    *count = it->second.size();
    return kOfxStatOK;
}

const OfxPropertySuiteV1 kPropertySuite = {
    propSetPointer,  propSetString,  propSetDouble,  propSetInt,     propSetPointerN,  propSetStringN,
    propSetDoubleN,  propSetIntN,    propGetPointer, propGetString,  propGetDouble,    propGetInt,
    propGetPointerN, propGetStringN, propGetDoubleN, propGetIntN,    propReset,        propGetDimension,
};

}  // namespace

// ---------------------------------------------------------------------------
// Parameters

int value_count(const std::string& type) {
    if (type == kOfxParamTypeDouble2D || type == kOfxParamTypeInteger2D) return 2;
    if (type == kOfxParamTypeDouble3D || type == kOfxParamTypeInteger3D || type == kOfxParamTypeRGB) return 3;
    if (type == kOfxParamTypeRGBA) return 4;
    return 1;
}
bool is_double(const std::string& t) {
    return t == kOfxParamTypeDouble || t == kOfxParamTypeDouble2D || t == kOfxParamTypeDouble3D || t == kOfxParamTypeRGB ||
           t == kOfxParamTypeRGBA;
}
bool is_int(const std::string& t) {
    return t == kOfxParamTypeInteger || t == kOfxParamTypeInteger2D || t == kOfxParamTypeInteger3D ||
           t == kOfxParamTypeBoolean || t == kOfxParamTypeChoice;
}
bool is_string(const std::string& t) { return t == kOfxParamTypeString || t == kOfxParamTypeCustom; }

namespace {

OfxStatus paramDefine(OfxParamSetHandle set, const char* type, const char* name, OfxPropertySetHandle* props) {
    if (!set || !type || !name) return kOfxStatErrBadHandle;
    static const std::set<std::string> known = {
        kOfxParamTypeInteger, kOfxParamTypeDouble, kOfxParamTypeBoolean, kOfxParamTypeChoice, kOfxParamTypeRGBA,
        kOfxParamTypeRGB, kOfxParamTypeDouble2D, kOfxParamTypeInteger2D, kOfxParamTypeDouble3D, kOfxParamTypeInteger3D,
        kOfxParamTypeString, kOfxParamTypeCustom, kOfxParamTypeGroup, kOfxParamTypePage, kOfxParamTypePushButton};
    if (!known.count(type)) return kOfxStatErrUnknown;
    auto* ps = reinterpret_cast<ParamSet*>(set);
    if (ps->params.count(name)) return kOfxStatErrExists;
    auto p = std::make_unique<Param>();
    p->type = type;
    p->name = name;
    p->props.set(kOfxParamPropType, std::string(type));
    p->props.set(kOfxPropName, std::string(name));
    p->props.set(kOfxPropLabel, std::string(name));
    if (props) *props = reinterpret_cast<OfxPropertySetHandle>(&p->props);
    ps->order.push_back(name);
    ps->params[name] = std::move(p);
    return kOfxStatOK;
}

OfxStatus paramGetHandle(OfxParamSetHandle set, const char* name, OfxParamHandle* param, OfxPropertySetHandle* props) {
    if (!set || !name) return kOfxStatErrBadHandle;
    auto* ps = reinterpret_cast<ParamSet*>(set);
    auto it = ps->params.find(name);
    if (it == ps->params.end()) return kOfxStatErrUnknown;
    if (param) *param = reinterpret_cast<OfxParamHandle>(it->second.get());
    if (props) *props = reinterpret_cast<OfxPropertySetHandle>(&it->second->props);
    return kOfxStatOK;
}

OfxStatus paramSetGetPropertySet(OfxParamSetHandle set, OfxPropertySetHandle* props) {
    if (!set || !props) return kOfxStatErrBadHandle;
    *props = reinterpret_cast<OfxPropertySetHandle>(&reinterpret_cast<ParamSet*>(set)->props);
    return kOfxStatOK;
}

OfxStatus paramGetPropertySet(OfxParamHandle param, OfxPropertySetHandle* props) {
    if (!param || !props) return kOfxStatErrBadHandle;
    *props = reinterpret_cast<OfxPropertySetHandle>(&reinterpret_cast<Param*>(param)->props);
    return kOfxStatOK;
}

OfxStatus get_value(Param* p, va_list ap) {
    if (is_double(p->type)) {
        for (int k = 0; k < value_count(p->type); ++k) *va_arg(ap, double*) = p->d.at(std::size_t(k));
    } else if (is_int(p->type)) {
        for (int k = 0; k < value_count(p->type); ++k) *va_arg(ap, int*) = p->i.at(std::size_t(k));
    } else if (is_string(p->type)) {
        *va_arg(ap, const char**) = p->s.c_str();
    } else {
        return kOfxStatErrBadHandle;  // groups, pages, buttons have no value
    }
    return kOfxStatOK;
}

OfxStatus set_value(Param* p, va_list ap) {
    if (is_double(p->type)) {
        for (int k = 0; k < value_count(p->type); ++k) p->d.at(std::size_t(k)) = va_arg(ap, double);
    } else if (is_int(p->type)) {
        for (int k = 0; k < value_count(p->type); ++k) p->i.at(std::size_t(k)) = va_arg(ap, int);
    } else if (is_string(p->type)) {
        const char* s = va_arg(ap, const char*);
        p->s = s ? s : "";
    } else {
        return kOfxStatErrBadHandle;
    }
    return kOfxStatOK;
}

OfxStatus paramGetValue(OfxParamHandle h, ...) {
    if (!h) return kOfxStatErrBadHandle;
    va_list ap;
    va_start(ap, h);
    const OfxStatus s = get_value(reinterpret_cast<Param*>(h), ap);
    va_end(ap);
    return s;
}
OfxStatus paramGetValueAtTime(OfxParamHandle h, OfxTime time, ...) {
    if (!h) return kOfxStatErrBadHandle;
    va_list ap;
    va_start(ap, time);
    const OfxStatus s = get_value(reinterpret_cast<Param*>(h), ap);
    va_end(ap);
    return s;
}
OfxStatus paramGetDerivative(OfxParamHandle, OfxTime, ...) { return kOfxStatErrUnsupported; }
OfxStatus paramGetIntegral(OfxParamHandle, OfxTime, OfxTime, ...) { return kOfxStatErrUnsupported; }
OfxStatus paramSetValue(OfxParamHandle h, ...) {
    if (!h) return kOfxStatErrBadHandle;
    va_list ap;
    va_start(ap, h);
    const OfxStatus s = set_value(reinterpret_cast<Param*>(h), ap);
    va_end(ap);
    return s;
}
OfxStatus paramSetValueAtTime(OfxParamHandle h, OfxTime time, ...) {
    if (!h) return kOfxStatErrBadHandle;
    va_list ap;
    va_start(ap, time);
    const OfxStatus s = set_value(reinterpret_cast<Param*>(h), ap);
    va_end(ap);
    return s;
}
OfxStatus paramGetNumKeys(OfxParamHandle, unsigned int* n) {
    if (n) *n = 0;
    return kOfxStatOK;
}
OfxStatus paramGetKeyTime(OfxParamHandle, unsigned int, OfxTime*) { return kOfxStatErrBadIndex; }
OfxStatus paramGetKeyIndex(OfxParamHandle, OfxTime, int, int*) { return kOfxStatFailed; }
OfxStatus paramDeleteKey(OfxParamHandle, OfxTime) { return kOfxStatErrBadIndex; }
OfxStatus paramDeleteAllKeys(OfxParamHandle) { return kOfxStatOK; }
OfxStatus paramCopy(OfxParamHandle, OfxParamHandle, OfxTime, const OfxRangeD*) { return kOfxStatErrUnsupported; }
OfxStatus paramEditBegin(OfxParamSetHandle, const char*) { return kOfxStatOK; }
OfxStatus paramEditEnd(OfxParamSetHandle) { return kOfxStatOK; }

const OfxParameterSuiteV1 kParameterSuite = {
    paramDefine,     paramGetHandle,   paramSetGetPropertySet, paramGetPropertySet, paramGetValue,
    paramGetValueAtTime, paramGetDerivative, paramGetIntegral, paramSetValue,   paramSetValueAtTime,
    paramGetNumKeys, paramGetKeyTime,  paramGetKeyIndex,       paramDeleteKey,      paramDeleteAllKeys,
    paramCopy,       paramEditBegin,   paramEditEnd,
};

}  // namespace

const OfxPropertySuiteV1* property_suite() { return &kPropertySuite; }
const OfxParameterSuiteV1* parameter_suite() { return &kParameterSuite; }

}  // namespace gdof::ofxtest::detail
