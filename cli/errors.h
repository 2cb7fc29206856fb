// Errors inside the CLI: thrown as CliError, turned into "gdof: error: ..."
// and an exit code by main.cpp (usage errors 2, runtime errors 1).
#pragma once

#include <stdexcept>
#include <string>
#include <utility>

#include "gdof/status.h"

namespace gdof::cli {

// 130 / 143: 128 + SIGINT / SIGTERM, as a shell reports a process those signals end.
enum ExitCode : int { kOk = 0, kRuntimeError = 1, kUsageError = 2, kInterrupted = 130, kTerminated = 143 };

struct CliError : std::runtime_error {
    int code;
    CliError(int c, const std::string& what) : std::runtime_error(what), code(c) {}
};
[[noreturn]] inline void usage_error(const std::string& what) { throw CliError(kUsageError, what); }
[[noreturn]] inline void runtime_error(const std::string& what) { throw CliError(kRuntimeError, what); }

// Throws a runtime error with the status message (and a context prefix) if it
// failed; "interrupted" (exit 130 / 143) after SIGINT / SIGTERM.
void check(const Status& s, const std::string& context = {});
template <class T>
T take(Result<T>&& r, const std::string& context = {}) {
    if (!r) check(r.status(), context);
    return std::move(r).value();
}

// A library error's message, followed by the flag that sets the setting it is
// about (its subject, e.g. "focal_length_mm" -> " (--focal-length-mm)"). For
// library calls whose settings come from flags.
std::string message_naming_flag(const Status& s);

}  // namespace gdof::cli
