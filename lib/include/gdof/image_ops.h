// Small whole-image operations the front ends share (channel shuffles for
// previews and AOV handling, scaling).
#pragma once

#include <string>
#include <vector>

#include "gdof/export.h"
#include "gdof/image.h"
#include "gdof/status.h"

namespace gdof {

// Builds an image from a channel list, oiiotool style: each entry is
//   "name"          copy channel `name`,
//   "new=old"       copy channel `old` under the name `new`,
//   "new=0.5"       a float channel filled with a constant.
// Windows and metadata are kept. Unknown channels are errors naming them.
GDOF_API Result<Image> select_channels(const Image& src, const std::vector<std::string>& spec);

// Multiplies float channels by factors: one factor for all, or one per channel.
// UInt channels are left alone.
GDOF_API Status multiply_channels(Image& img, const std::vector<double>& factors);

// Splits "a,b,c" at commas (no empty entries allowed: error naming the list).
GDOF_API Result<std::vector<std::string>> split_list(const std::string& list);

}  // namespace gdof
