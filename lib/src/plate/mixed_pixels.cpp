// Mixed pixels at silhouettes: a renderer's filtered Z (the mean depth of the
// samples that hit) and a depth sensor's "flying pixels" put a silhouette
// pixel at a depth between the foreground's and the background's, where no
// surface is. Such a pixel is split: it keeps the background's depth, and
// the foreground gets the share of the pixel that the depth's position
// between the two says: share = (far - depth) / (far - near).
//
// A pixel is mixed when, in its 5x5 window, the depths span at least
// `mixed_step` and it lies strictly between them: some neighbour is nearer
// and some farther than it by more than `continuity` (a pixel of a sloping
// surface next to a silhouette is continued by its own surface on at least
// one side). The window is 5x5 so a two-pixel anti-aliasing ramp is found.
#include <algorithm>
#include <cmath>
#include <limits>

#include "plate/plate_internal.h"

namespace gdof::plate_detail {

std::size_t split_mixed(std::vector<float>& depth, int W, int H, double continuity, double mixed_step,
                        std::vector<float>& fg_depth, std::vector<float>& fg_coverage) {
    const std::vector<float> d0 = depth;  // decisions read the unsplit depths
    const float nan = std::numeric_limits<float>::quiet_NaN();
    std::size_t count = 0;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const std::size_t i = std::size_t(y) * std::size_t(W) + std::size_t(x);
            const float d = d0[i];
            if (!std::isfinite(d)) continue;
            float near = d, far = d;
            bool nearer = false, farther = false;
            for (int dy = -2; dy <= 2; ++dy)
                for (int dx = -2; dx <= 2; ++dx) {
                    const int xx = x + dx, yy = y + dy;
                    if (xx < 0 || xx >= W || yy < 0 || yy >= H) continue;
                    const float q = d0[std::size_t(yy) * std::size_t(W) + std::size_t(xx)];
                    if (!std::isfinite(q)) continue;  // sky and holes: no depth to mix with
                    near = std::min(near, q);
                    far = std::max(far, q);
                    const bool adjacent = std::abs(dx) <= 1 && std::abs(dy) <= 1;
                    if (adjacent && q * continuity < d) nearer = true;
                    if (adjacent && q > d * continuity) farther = true;
                }
            if (!nearer || !farther || double(far) < double(near) * mixed_step) continue;
            if (!(double(d) > double(near) * continuity && double(d) * continuity < double(far))) continue;
            if (fg_depth.empty()) {
                fg_depth.assign(depth.size(), nan);
                fg_coverage.assign(depth.size(), nan);
            }
            fg_depth[i] = near;
            fg_coverage[i] = std::clamp((far - d) / (far - near), 0.0f, 1.0f);
            depth[i] = far;
            ++count;
        }
    return count;
}

}  // namespace gdof::plate_detail
