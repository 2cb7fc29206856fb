// Whole text files (JSON, OBJ/MTL, CSV) in one call. Every reader of the
// library and its front ends goes through it, so a missing or unreadable
// file is reported the same way everywhere: "'path' not found",
// "'path' is a folder", "'path': cannot read (reason)".
#pragma once

#include <string>

#include "gdof/export.h"
#include "gdof/status.h"

namespace gdof {

// The bytes of the file. Errors: NotFound (no such file), Io (a folder, or
// unreadable), each naming the path.
GDOF_API Result<std::string> read_text(const std::string& path);
// The same, the file named as "<what> 'path'" in errors ("scene 'a.json' not
// found", "table 'b.csv' is a folder"), the code kept.
GDOF_API Result<std::string> read_text(const std::string& path, const std::string& what);

}  // namespace gdof
