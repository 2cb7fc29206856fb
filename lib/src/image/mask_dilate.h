// Square (chessboard) dilation of a byte mask, for the kernels that need the
// pixels near a set (the pyramid's reach, a layer's coverage rim).
#pragma once

#include <vector>

#include "gdof/exec.h"
#include "gdof/export.h"

namespace gdof::image_detail {

// The pixels of a row-major W x H mask within chessboard distance m of a set
// pixel (rows, then columns). The same bits for any thread count.
GDOF_API std::vector<unsigned char> dilate_square(const std::vector<unsigned char>& mask, int W, int H, int m,
                                                  const Exec& exec = {});

}  // namespace gdof::image_detail
