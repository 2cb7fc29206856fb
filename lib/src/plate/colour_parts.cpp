// A mixed pixel's two parts from its colour (plate_internal.h): how much of
// it the foreground's colour explains, and each part's colour.
#include <algorithm>
#include <cmath>
#include <limits>

#include "plate/plate_internal.h"

namespace gdof::plate_detail {

void SideColour::add(int d2, const float* const rgb[3], std::size_t j, float q) {
    if (d2 > dist2) return;
    if (d2 < dist2) *this = SideColour{d2};
    for (int c = 0; c < 3; ++c) sum[c] += rgb[c][j];
    depth += q;
    ++n;
}

void SideColour::mean(double out[3]) const {
    for (int c = 0; c < 3; ++c) out[c] = sum[c] / n;
}

double colour_share(const double fg[3], const double bg[3], const float pixel[3]) {
    constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
    double den = 0, num = 0, fb_scale = 0;
    for (int c = 0; c < 3; ++c) {
        den += (fg[c] - bg[c]) * (fg[c] - bg[c]);
        num += (double(pixel[c]) - bg[c]) * (fg[c] - bg[c]);
        fb_scale = std::max({fb_scale, std::abs(fg[c]), std::abs(bg[c])});
    }
    // Surfaces too alike in colour to tell apart.
    if (!(den > 0.0) || std::sqrt(den) < kDistinctColours * fb_scale) return kNaN;
    const double share = num / den;
    // The pixel must lie near the line between the two colours (texture or a
    // third surface otherwise).
    double res = 0;
    for (int c = 0; c < 3; ++c) {
        const double m = share * fg[c] + (1.0 - share) * bg[c];
        res += (double(pixel[c]) - m) * (double(pixel[c]) - m);
    }
    if (share < -kShareSlack || share > 1.0 + kShareSlack || res > kResidual * kResidual * den) return kNaN;
    return share;
}

void unmix(MixedPixel& m, const float pixel[3], const double fg[3], const double bg[3]) {
    for (int c = 0; c < 3; ++c) {
        const double r = pixel[c] - (m.fg_share * fg[c] + (1.0 - m.fg_share) * bg[c]);
        m.fg_rgb[c] = float(fg[c] + r);
        m.bg_rgb[c] = float(bg[c] + r);
        // No negative light: give the deficit to the other part.
        if (m.fg_rgb[c] < 0) {
            m.fg_rgb[c] = 0;
            m.bg_rgb[c] = float(pixel[c] / (1.0 - m.fg_share));
        } else if (m.bg_rgb[c] < 0) {
            m.bg_rgb[c] = 0;
            m.fg_rgb[c] = float(pixel[c] / m.fg_share);
        }
    }
}

}  // namespace gdof::plate_detail
