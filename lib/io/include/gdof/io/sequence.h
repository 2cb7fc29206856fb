// Frame sequences as in oiiotool / Nuke: "shot.####.exr" (a run of N '#'
// pads to N digits, a lone '#' to 4), "shot.@@@.exr" (one digit per '@'),
// "shot.%04d.exr"; frame ranges "1-10", "1-10x2", "1,3,7-9", "10-1"
// (descending), "-5--1" (negative frames).
#pragma once

#include <string>
#include <vector>

#include "gdof/export.h"
#include "gdof/status.h"

namespace gdof::io {

// Parses a frame range specification into the ordered list of frames.
GDOF_API Result<std::vector<int>> parse_frame_range(const std::string& spec);
// True if the path contains a frame pattern (#, @ or a printf %0Nd).
GDOF_API bool has_frame_pattern(const std::string& path);
// Substitutes a frame number into a pattern.
GDOF_API Result<std::string> expand_frame_pattern(const std::string& pattern, int frame);
// Finds the frames on disk that match a pattern (sorted ascending).
GDOF_API Result<std::vector<int>> frames_on_disk(const std::string& pattern);

}  // namespace gdof::io
