// An image aperture rasterised at one blur radius: each cell the kernel's
// average over it, every channel normalised so spreading conserves energy.
#include <algorithm>
#include <cmath>
#include <numbers>

#include "aperture/aperture_internal.h"
#include "common/format_number.h"

namespace gdof {

Result<ApertureKernel> rasterize_aperture(const Aperture& a, double radius) {
    if (!(radius >= 0.0) || !(radius <= 4096.0))
        return Status::error("aperture kernel: radius must be in [0, 4096] px, got " + format_number(radius, 6),
                             StatusCode::InvalidArgument);
    // Support: the fitted square, turned, reaches sqrt(2) of the radius.
    const double reach = a.rotation_deg == 0.0 && a.squeeze >= 1.0 ? 1.0 : std::numbers::sqrt2 * std::max(1.0, 1.0 / a.squeeze);
    ApertureKernel k;
    k.half = int(std::ceil(radius * reach + 0.5));
    const int n = 2 * k.half + 1;
    const int colours = a.colour() ? 3 : 1;
    k.channels = colours + 1;
    const std::size_t cells = std::size_t(n) * std::size_t(n);
    k.weights.assign(cells * std::size_t(k.channels), 0.0f);
    // Supersampling: enough that a small kernel still sees its shape.
    const int S = radius < 2.0 ? 8 : 4;
    const double inv = radius > 0.0 ? 1.0 / radius : 0.0;
    std::vector<double> sums(std::size_t(k.channels), 0.0);
    std::vector<double> acc(cells * std::size_t(k.channels), 0.0);
    for (int dy = -k.half; dy <= k.half; ++dy)
        for (int dx = -k.half; dx <= k.half; ++dx) {
            const std::size_t cell = std::size_t(dy + k.half) * std::size_t(n) + std::size_t(dx + k.half);
            for (int sy = 0; sy < S; ++sy)
                for (int sx = 0; sx < S; ++sx) {
                    const double u = (dx - 0.5 + (sx + 0.5) / S) * inv;
                    const double v = -(dy - 0.5 + (sy + 0.5) / S) * inv;
                    for (int c = 0; c < colours; ++c) acc[std::size_t(c) * cells + cell] += aperture_detail::density(a, u, v, colours == 1 ? 0 : c);
                }
        }
    if (radius == 0.0 || [&] {
            double t = 0;
            for (std::size_t i = 0; i < cells; ++i) t += acc[i];
            return !(t > 0.0);
        }()) {
        // Smaller than a cell (or missed by the samples): a point.
        for (int c = 0; c < k.channels; ++c) k.weights[std::size_t(c) * cells + cells / 2] = 1.0f;
        return k;
    }
    for (int c = 0; c < colours; ++c) {
        double t = 0;
        for (std::size_t i = 0; i < cells; ++i) t += acc[std::size_t(c) * cells + i];
        sums[std::size_t(c)] = t;
    }
    for (int c = 0; c < colours; ++c)
        for (std::size_t i = 0; i < cells; ++i) {
            const double w = sums[std::size_t(c)] > 0.0 ? acc[std::size_t(c) * cells + i] / sums[std::size_t(c)] : 0.0;
            k.weights[std::size_t(c) * cells + i] = float(w);
            k.weights[std::size_t(colours) * cells + i] += float(w / colours);
        }
    return k;
}

}  // namespace gdof
