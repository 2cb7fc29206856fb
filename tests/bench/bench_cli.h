// What the benchmark programs share on their command line. Each program
// defines bench::die itself (its own name in the message, its exit code).
#pragma once

#include <string>
#include <utility>

#include "gdof/status.h"

namespace gdof::bench {

// Prints the program's error and exits; defined by each benchmark program.
[[noreturn]] void die(const std::string& what);

// The value of a Result, or die with `what` and its message.
template <class T>
T take(Result<T> r, const std::string& what) {
    if (!r) die(what + ": " + r.message());
    return std::move(r).value();
}

// The value after option argv[i] (i moves onto it); die when it is missing.
inline std::string option_value(int argc, char** argv, int& i) {
    if (i + 1 >= argc) die(std::string(argv[i]) + ": missing value");
    return argv[++i];
}

}  // namespace gdof::bench
