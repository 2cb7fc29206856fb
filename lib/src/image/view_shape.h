// The shape check every API function taking an ImageView runs first, so a
// view of the wrong size is an error naming it instead of a stray write.
#pragma once

#include <string>

#include "gdof/export.h"
#include "gdof/image.h"
#include "gdof/status.h"

namespace gdof::image_detail {

inline constexpr int kAnyChannelCount = -1;

// Ok when `view` has pixels (valid()), `nchannels` channels (any count for
// kAnyChannelCount) and exactly `window`; else an InvalidArgument error
// "<what> is <its shape>; expected <the shape asked for>".
GDOF_API Status check_view_shape(const ConstImageView& view, int nchannels, const Roi& window, const std::string& what);

}  // namespace gdof::image_detail
