// Internal to gdof::io: file names in messages, extensions, format sniffing
// and atomic writes (a temporary file renamed over the target). Used by every
// io adapter; no OIIO or OpenEXR types here.
#pragma once

#include <functional>
#include <string>

#include "gdof/export.h"
#include "gdof/status.h"

namespace gdof::io::detail {

// "'path'" for messages.
GDOF_API std::string quoted(const std::string& path);

// Lower-case extension without the dot ("exr"), "" if none.
GDOF_API std::string extension_lower(const std::string& path);

// True if the file starts with the OpenEXR magic number.
GDOF_API bool has_exr_magic(const std::string& path);

// Temporary name beside the target that keeps the extension:
// "<dir>/.<name>.gdof-tmp-<pid>-<n>.<ext>".
GDOF_API std::string temp_path_for(const std::string& target);
// Checks the folder, runs `writer` on a temporary file, renames it over the
// target on success; removes the temporary file on any failure.
GDOF_API Status atomic_write(const std::string& target, const std::function<Status(const std::string& tmp)>& writer);

}  // namespace gdof::io::detail
