// Error of a result against the ground truth, for the method benchmark.
#pragma once

#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "gdof/image.h"

namespace gdof::bench {

struct ErrorMetrics {
    double psnr = 0;      // dB, peak 1 (display white) on linear RGB
    double rel_l1 = 0;    // sum |a - b| / sum |b| over linear RGB
    double rel_l2 = 0;    // sqrt(sum (a - b)^2 / sum b^2)
    double ssim = 0;      // mean SSIM of sRGB-encoded luminance clamped to [0, 1] (Gaussian window, sigma 1.5)
    double edge_rel_l1 = 0;  // rel_l1 restricted to the depth-discontinuity mask
    double away_rel_l1 = 0;  // rel_l1 outside it (seams on continuous surfaces show here)
};

// Pixels within `radius` px of a depth discontinuity of `z` (a float plane
// over w x h): neighbours whose depths differ by more than 10% (or one finite,
// one not).
std::vector<char> discontinuity_mask(const float* z, int w, int h, int radius);

// R, G, B, A (float) over `window` (the frame): results whose data window
// differs (a defocused layer grown past, or not covering, the frame) are
// cropped or zero-padded.
Image rgba_over(const Image& img, const Roi& window);

// R, G, B of both images over the same window (premultiplied linear).
ErrorMetrics compare(const Image& result, const Image& truth, const std::vector<char>& edge_mask);

// |result - truth| luminance in false colour (0 .. scale -> dark .. bright), 8-bit BGR.
cv::Mat error_map(const Image& result, const Image& truth, double scale);
// The image itself, sRGB-encoded, 8-bit BGR (for the picture grid).
cv::Mat preview(const Image& img);

}  // namespace gdof::bench
