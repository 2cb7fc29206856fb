// Shared pieces of gdof's JSON readers (blur fields, stack manifests, focus
// surfaces, scenes): an error that carries the key path, thrown inside a
// parser and turned into a Status at its API boundary. Not installed.
#pragma once

#include <cstdio>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace gdof::json_util {

using json = nlohmann::json;

struct JsonError {
    std::string message;
};

// "path: what" (e.g. "references[3].f_number: must be > 0, got -2").
[[noreturn]] inline void fail(const std::string& path, const std::string& what) { throw JsonError{path + ": " + what}; }

// "string \"abc\"", "number", "array" ... for messages.
inline std::string type_name(const json& j) {
    if (j.is_string()) return "string \"" + j.get<std::string>() + "\"";
    return j.type_name();
}

// A number for messages: 10 significant digits; "inf" / "-inf" / "nan".
inline std::string format_number(double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.10g", v);
    return buf;
}

inline std::string join(const std::vector<std::string>& v) {
    std::string s;
    for (std::size_t i = 0; i < v.size(); ++i) s += (i ? ", " : "") + v[i];
    return s;
}

}  // namespace gdof::json_util
