// Internal to gdof::io: file names in messages, extensions, format sniffing
// and atomic writes (a temporary file renamed over the target). Used by every
// io adapter; no OIIO or OpenEXR types here.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>

#include "gdof/export.h"
#include "gdof/status.h"

namespace gdof::io::detail {

// "'path'" for messages.
GDOF_API std::string quoted(const std::string& path);

// ASCII lower case (names compared in any case: channels, attributes).
GDOF_API std::string lower(std::string text);
// Lower-case extension without the dot ("exr"), "" if none.
GDOF_API std::string extension_lower(const std::string& path);

// True if the file starts with the OpenEXR magic number.
GDOF_API bool has_exr_magic(const std::string& path);

// Writes all `n` bytes at `offset` of `fd`, retrying short writes; false
// with errno set on failure (checked_write.cpp).
GDOF_API bool pwrite_all(int fd, const void* data, std::size_t n, std::uint64_t offset);
// Writes `data` to `path` (created or truncated), every write and the close
// checked; errors name `display` and the system's reason.
GDOF_API Status write_file(const std::string& path, const std::string& display, const void* data, std::size_t n);

// Temporary name beside the target that keeps the extension:
// "<dir>/.<name>.gdof-tmp-<host>-<pid>-<n>.<ext>".
GDOF_API std::string temp_path_for(const std::string& target);
// That `target` can be written: a file name whose folder exists and is
// writable, and not a folder itself. Errors name the target and the cause.
GDOF_API Status check_target(const std::string& target);
// Checks the target, removes temporary files of it left by dead processes
// of this host, runs `writer` on a temporary file and renames it over the
// target on success. On any failure, or when `cancelled` returns true once
// the writer is done, the temporary file is removed and the target untouched.
GDOF_API Status atomic_write(const std::string& target, const std::function<Status(const std::string& tmp)>& writer,
                             const std::function<bool()>& cancelled = {});

}  // namespace gdof::io::detail
