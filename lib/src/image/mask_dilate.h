// Square (chessboard) dilation of a byte mask, for the kernels that need the
// pixels near a set (the pyramid's reach, a layer's coverage rim).
#pragma once

#include <span>

#include "gdof/exec.h"
#include "gdof/export.h"
#include "image/frame_buffer.h"

namespace gdof::image_detail {

// The pixels of a row-major W x H mask within chessboard distance m of a set
// pixel (rows, then columns). The same bits for any thread count.
GDOF_API FrameBuffer<unsigned char> dilate_square(std::span<const unsigned char> mask, int W, int H, int m,
                                                  const Exec& exec = {});

}  // namespace gdof::image_detail
