// Depth noise: measured, and smoothed away where a surface continues.
//
// A sensor's depth carries noise of a fraction of a percent (a structured-
// light or stereo sensor's disparity noise, 0.5% in the benchmark's degraded
// map). Two things go wrong with it downstream: the blur radius jitters
// (small), and a surface that faces the camera near a blur cut of the layer
// split falls into a band of speckle across two layers, 20 px wide on the
// benchmark's Cornell box, each speckle a silhouette of its own that
// spreads over the background behind (the degraded Cornell edge error was
// 1.43x the clean one). A renderer's Z has no such noise and is not touched.
//
// Measurement: in inverse depth a plane seen by a pinhole camera is affine in
// pixel coordinates, so the second difference of 1/z along a row or column
// is zero on any plane and, with relative noise s on each pixel, has the
// spread s * sqrt(1.5) (the midpoint of two samples minus a third). The
// upper quartile of the absolute second differences over triples within one
// surface (depth ratios within `continuity`: silhouettes are left out)
// estimates s robustly: not the median, because a sensor's depth is also
// quantised (Kinect-style maps step by 0.25% of the depth) and most triples
// on such a staircase are exactly flat (67% on the TUM frame), while the
// rest carry the noise that dithers between the steps; edges and texture in
// the depth stay a minority.
//
// Smoothing: each pixel takes the value at its centre of the least-squares
// plane in inverse depth through the pixels of its (2r + 1)^2 window that
// continue its surface (ratio within `continuity`): planes are kept exactly
// also where the window is cut by a silhouette or the frame's edge (a mean
// would shift a steep floor there by up to a row's worth of depth), and the
// two sides of a silhouette never mix.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

#include "plate/plate_internal.h"

namespace gdof::plate_detail {

namespace {

// The k-th smallest (0-based) of non-negative floats, exactly, as
// nth_element would give it: non-negative floats order as their bit patterns,
// so a parallel histogram of the top 16 bits finds the bucket that holds
// rank k, and only that bucket's values are sorted.
float kth_smallest(const std::vector<std::vector<float>>& parts, std::size_t k, const Exec& exec) {
    constexpr std::size_t kBuckets = 1 << 16;
    auto bucket = [](float v) {
        std::uint32_t b;
        std::memcpy(&b, &v, sizeof b);
        return std::size_t(b >> 16);
    };
    // A few groups of parts, one histogram each (counts: any order).
    constexpr std::size_t kGroups = 8;
    const std::size_t per = (parts.size() + kGroups - 1) / kGroups;
    std::vector<std::vector<std::uint32_t>> group_hist(kGroups);
    // Cancelled: some histograms were never made (0; the caller reports it).
    const bool counted = parallel_for(exec, long(kGroups), [&](long g0, long g1) {
        for (long g = g0; g < g1; ++g) {
            auto& h = group_hist[std::size_t(g)];
            h.assign(kBuckets, 0);
            for (std::size_t p = std::size_t(g) * per; p < std::min(parts.size(), std::size_t(g + 1) * per); ++p)
                for (float v : parts[p]) ++h[bucket(v)];
        }
    });
    if (!counted) return 0.0f;
    std::vector<std::size_t> hist(kBuckets, 0);
    for (const auto& h : group_hist)
        for (std::size_t b = 0; b < kBuckets; ++b) hist[b] += h[b];
    std::size_t b = 0, below = 0;
    while (below + hist[b] <= k) below += hist[b++];
    std::vector<float> in;
    for (const auto& part : parts)
        for (float v : part)
            if (bucket(v) == b) in.push_back(v);
    std::nth_element(in.begin(), in.begin() + std::ptrdiff_t(k - below), in.end());
    return in[k - below];
}

}  // namespace

double estimate_depth_noise(const std::vector<float>& depth, int width, int height, double continuity,
                            const Exec& exec) {
    // Every fourth row (and its columns at those rows): plenty of samples at
    // any size, a fraction of a pass over the map. The rows in parallel.
    const int nrows = height >= 3 ? (height - 3) / 4 + 1 : 0;  // y = 1, 5, 9, ... < height - 1
    std::vector<std::vector<float>> rows(static_cast<std::size_t>(nrows));
    const bool sampled = parallel_for(exec, nrows, [&](long r0, long r1) {
        for (long r = r0; r < r1; ++r) {
            std::vector<float>& e = rows[std::size_t(r)];
            auto triple = [&](float a, float m, float b) {  // sky (continuous with sky) has no inverse depth to compare
                if (!std::isfinite(m) || !(m > 0.0f) || !continuous(a, m, continuity) || !continuous(b, m, continuity))
                    return;
                const double ua = 1.0 / a, um = 1.0 / m, ub = 1.0 / b;
                e.push_back(float(std::abs(0.5 * (ua + ub) - um) / um));
            };
            const int y = 1 + 4 * int(r);
            const float* row = depth.data() + std::size_t(y) * std::size_t(width);
            for (int x = 1; x + 1 < width; ++x) {
                triple(row[x - 1], row[x], row[x + 1]);
                triple(row[x - width], row[x], row[x + width]);
            }
        }
    }, 8);
    if (!sampled) return 0.0;  // cancelled: the caller reports it
    std::size_t count = 0;
    for (const auto& r : rows) count += r.size();
    if (count < 16) return 0.0;
    constexpr double kQuartileToSigma = 1.0 / 1.1503;  // Gaussian: P(|x| < 1.1503 sigma) = 0.75
    return double(kth_smallest(rows, count * 3 / 4, exec)) * kQuartileToSigma / std::sqrt(1.5);
}

void smooth_depth_noise(std::vector<float>& depth, int width, int height, double continuity, int radius,
                        const std::vector<unsigned char>& keep, const Exec& exec) {
    const std::vector<float> src = depth;
    parallel_for(exec, height, [&](long r0, long r1) {
        for (int y = int(r0); y < int(r1); ++y)
            for (int x = 0; x < width; ++x) {
                const std::size_t i = std::size_t(y) * std::size_t(width) + std::size_t(x);
                const float z = src[i];
                if (!std::isfinite(z) || !(z > 0.0f) || (!keep.empty() && keep[i])) continue;
                const int y0 = std::max(0, y - radius), y1 = std::min(height - 1, y + radius);
                const int x0 = std::max(0, x - radius), x1 = std::min(width - 1, x + radius);
                auto on_surface = [&](std::size_t j) {
                    return (keep.empty() || !keep[j]) && continuous(src[j], z, continuity);
                };
                // A whole window: the plane's value at its centre is the mean.
                double s1 = 0, su = 0;
                for (int yy = y0; yy <= y1; ++yy)
                    for (int xx = x0; xx <= x1; ++xx) {
                        const std::size_t j = std::size_t(yy) * std::size_t(width) + std::size_t(xx);
                        if (!on_surface(j)) continue;
                        s1 += 1, su += 1.0 / double(src[j]);
                    }
                double u = su / s1;
                if (s1 < double((2 * radius + 1) * (2 * radius + 1))) {
                    // Least-squares plane u = a + b dx + c dy (moments about
                    // the centre), a by Cramer's rule; a window too thin for
                    // a plane (a line of pixels, a corner of a few) keeps the mean.
                    double sx = 0, sy = 0, sxx = 0, syy = 0, sxy = 0, sxu = 0, syu = 0;
                    for (int yy = y0; yy <= y1; ++yy)
                        for (int xx = x0; xx <= x1; ++xx) {
                            const std::size_t j = std::size_t(yy) * std::size_t(width) + std::size_t(xx);
                            if (!on_surface(j)) continue;
                            const double dx = xx - x, dy = yy - y, v = 1.0 / double(src[j]);
                            sx += dx, sy += dy, sxx += dx * dx, syy += dy * dy, sxy += dx * dy;
                            sxu += dx * v, syu += dy * v;
                        }
                    const double det =
                        s1 * (sxx * syy - sxy * sxy) - sx * (sx * syy - sxy * sy) + sy * (sx * sxy - sxx * sy);
                    if (s1 >= 6 && det > 1e-6 * s1 * s1 * s1) {
                        const double a = (su * (sxx * syy - sxy * sxy) - sx * (sxu * syy - sxy * syu) +
                                          sy * (sxu * sxy - sxx * syu)) / det;
                        if (a > 0.0) u = a;
                    }
                }
                depth[i] = float(1.0 / u);
            }
    }, 8);
}

}  // namespace gdof::plate_detail
