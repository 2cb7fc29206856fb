// A property set (the OFX property suite) with typed, throwing accessors.
#pragma once

#include <initializer_list>
#include <string>
#include <vector>

#include "ofx_api.h"

namespace gdof::ofx {

class Props {
public:
    Props() = default;
    explicit Props(OfxPropertySetHandle h) : h_(h) {}
    OfxPropertySetHandle handle() const { return h_; }
    bool valid() const { return h_ != nullptr; }

    const Props& set(const char* name, const char* value, int index = 0) const;
    const Props& set(const char* name, const std::string& value, int index = 0) const { return set(name, value.c_str(), index); }
    const Props& set(const char* name, int value, int index = 0) const;
    const Props& set(const char* name, double value, int index = 0) const;
    const Props& set_pointer(const char* name, void* value, int index = 0) const;
    const Props& set_strings(const char* name, std::initializer_list<const char*> values) const;
    const Props& set_strings(const char* name, const std::vector<std::string>& values) const;
    const Props& set_ints(const char* name, std::initializer_list<int> values) const;
    const Props& set_doubles(const char* name, const std::vector<double>& values) const;

    std::string get_string(const char* name, int index = 0) const;
    int get_int(const char* name, int index = 0) const;
    double get_double(const char* name, int index = 0) const;
    void* get_pointer(const char* name, int index = 0) const;
    std::vector<double> get_doubles(const char* name, int count) const;
    std::vector<int> get_ints(const char* name, int count) const;
    int dimension(const char* name) const;  // throws if unknown

    // Non-throwing reads for properties a host may not have.
    std::string string_or(const char* name, const std::string& fallback, int index = 0) const;
    int int_or(const char* name, int fallback, int index = 0) const;
    double double_or(const char* name, double fallback, int index = 0) const;

private:
    OfxPropertySetHandle h_ = nullptr;
};

}  // namespace gdof::ofx
