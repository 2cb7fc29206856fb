// Flag values parsed strictly: a bad value is a usage error naming the flag
// and the value ("--soft: expected an integer, got '2.5'").
#pragma once

#include <optional>
#include <string>

namespace gdof::cli {

// The whole string as a base-10 integer (strtol's syntax), nullopt otherwise.
std::optional<long> to_integer(const std::string& value);

// A finite or infinite double (strtod's syntax): "expected a number".
double parse_double(const std::string& flag, const std::string& value);
// An integer of magnitude <= 1e6: "expected an integer".
int parse_int(const std::string& flag, const std::string& value);
// An integer in [lo, 1e6]: "expected an integer >= lo".
int parse_count(const std::string& flag, const std::string& value, int lo);

// `v` printed with one printf conversion (`format`, e.g. "%g"), for messages.
std::string format_double(const char* format, double v);

}  // namespace gdof::cli
