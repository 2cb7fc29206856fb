// GDOF_API marks what the gdof libraries export. Every library is built with
// hidden symbols (-fvisibility=hidden), so with BUILD_SHARED_LIBS=ON a
// shared library exports exactly the classes and functions marked here: the
// public headers' API, and the few private helpers that another gdof
// library uses (json_read.h, format_number.h, ...; exported, not installed).
// Static libraries are unaffected (visibility only matters to the dynamic
// linker). Inline functions and templates need no mark.
#pragma once

#if defined(_WIN32)
// Windows DLLs would need dllexport / dllimport per library; gdof builds
// static libraries there (a shared build is Linux / macOS only).
#define GDOF_API
#elif defined(__GNUC__) || defined(__clang__)
#define GDOF_API __attribute__((visibility("default")))
#else
#define GDOF_API
#endif
