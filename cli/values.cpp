// Flag values: numbers (values.h).
#include "values.h"

#include <cerrno>
#include <cstdio>
#include <cstdlib>

#include "errors.h"

namespace gdof::cli {

namespace {
constexpr long kIntLimit = 1000000;  // larger integers are typos, not settings
}

std::optional<long> to_integer(const std::string& v) {
    char* end = nullptr;
    errno = 0;
    const long n = std::strtol(v.c_str(), &end, 10);
    if (v.empty() || *end != '\0' || errno == ERANGE) return std::nullopt;
    return n;
}

double parse_double(const std::string& flag, const std::string& v) {
    char* end = nullptr;
    errno = 0;
    const double d = std::strtod(v.c_str(), &end);
    if (v.empty() || *end != '\0' || errno == ERANGE) usage_error(flag + ": expected a number, got '" + v + "'");
    return d;
}

int parse_int(const std::string& flag, const std::string& v) {
    const std::optional<long> n = to_integer(v);
    if (!n || *n < -kIntLimit || *n > kIntLimit) usage_error(flag + ": expected an integer, got '" + v + "'");
    return int(*n);
}

int parse_count(const std::string& flag, const std::string& v, int lo) {
    const std::optional<long> n = to_integer(v);
    if (!n || *n < lo || *n > kIntLimit)
        usage_error(flag + ": expected an integer >= " + std::to_string(lo) + ", got '" + v + "'");
    return int(*n);
}

std::string format_double(const char* format, double v) {
    char b[64];
    std::snprintf(b, sizeof b, format, v);
    return b;
}

}  // namespace gdof::cli
