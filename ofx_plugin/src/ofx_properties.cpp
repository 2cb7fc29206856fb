#include "ofx_properties.h"

namespace gdof::ofx {

namespace {

const OfxPropertySuiteV1& ps() {
    const OfxPropertySuiteV1* s = suites().prop;
    if (!s) fail("the host's property suite is not available", kOfxStatErrMissingHostFeature);
    return *s;
}

std::string what(const char* verb, const char* name, int index) {
    return std::string(verb) + " property " + name + "[" + std::to_string(index) + "]";
}

}  // namespace

const Props& Props::set(const char* name, const char* value, int index) const {
    check(ps().propSetString(h_, name, index, value), what("setting", name, index));
    return *this;
}
const Props& Props::set(const char* name, int value, int index) const {
    check(ps().propSetInt(h_, name, index, value), what("setting", name, index));
    return *this;
}
const Props& Props::set(const char* name, double value, int index) const {
    check(ps().propSetDouble(h_, name, index, value), what("setting", name, index));
    return *this;
}
const Props& Props::set_pointer(const char* name, void* value, int index) const {
    check(ps().propSetPointer(h_, name, index, value), what("setting", name, index));
    return *this;
}
const Props& Props::set_strings(const char* name, std::initializer_list<const char*> values) const {
    int i = 0;
    for (const char* v : values) set(name, v, i++);
    return *this;
}
const Props& Props::set_strings(const char* name, const std::vector<std::string>& values) const {
    int i = 0;
    for (const std::string& v : values) set(name, v.c_str(), i++);
    return *this;
}
const Props& Props::set_ints(const char* name, std::initializer_list<int> values) const {
    int i = 0;
    for (int v : values) set(name, v, i++);
    return *this;
}
const Props& Props::set_doubles(const char* name, const std::vector<double>& values) const {
    int i = 0;
    for (double v : values) set(name, v, i++);
    return *this;
}

std::string Props::get_string(const char* name, int index) const {
    const char* v = nullptr;
    check(ps().propGetString(h_, name, index, &v), what("reading", name, index));
    return v ? std::string(v) : std::string();
}
int Props::get_int(const char* name, int index) const {
    int v = 0;
    check(ps().propGetInt(h_, name, index, &v), what("reading", name, index));
    return v;
}
double Props::get_double(const char* name, int index) const {
    double v = 0;
    check(ps().propGetDouble(h_, name, index, &v), what("reading", name, index));
    return v;
}
void* Props::get_pointer(const char* name, int index) const {
    void* v = nullptr;
    check(ps().propGetPointer(h_, name, index, &v), what("reading", name, index));
    return v;
}
std::vector<double> Props::get_doubles(const char* name, int count) const {
    std::vector<double> v(static_cast<std::size_t>(count));
    if (count > 0) check(ps().propGetDoubleN(h_, name, count, v.data()), what("reading", name, count - 1));
    return v;
}
std::vector<int> Props::get_ints(const char* name, int count) const {
    std::vector<int> v(static_cast<std::size_t>(count));
    if (count > 0) check(ps().propGetIntN(h_, name, count, v.data()), what("reading", name, count - 1));
    return v;
}
int Props::dimension(const char* name) const {
    int n = 0;
    check(ps().propGetDimension(h_, name, &n), std::string("reading the size of property ") + name);
    return n;
}

std::string Props::string_or(const char* name, const std::string& fallback, int index) const {
    const char* v = nullptr;
    if (!h_ || ps().propGetString(h_, name, index, &v) != kOfxStatOK || !v) return fallback;
    return v;
}
int Props::int_or(const char* name, int fallback, int index) const {
    int v = 0;
    if (!h_ || ps().propGetInt(h_, name, index, &v) != kOfxStatOK) return fallback;
    return v;
}
double Props::double_or(const char* name, double fallback, int index) const {
    double v = 0;
    if (!h_ || ps().propGetDouble(h_, name, index, &v) != kOfxStatOK) return fallback;
    return v;
}

}  // namespace gdof::ofx
