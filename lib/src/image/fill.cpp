// Push-pull fill (Gortler et al., "The Lumigraph", 1996): push averages
// weighted values down a 2x pyramid; pull blends each level with the
// bilinear upsampling of the filled level above, by the level's own weight.
#include "gdof/fill.h"

#include <algorithm>
#include <span>
#include <vector>

#include "image/row_major_planes.h"
#include "image/view_shape.h"

namespace gdof {

namespace {

struct Level {
    int w = 0, h = 0;
    std::vector<float> weight;               // in [0, 1]
    std::vector<std::vector<float>> values;  // per plane, normalised (not weighted)
};

// The fill on row-major planes of width x height (push_pull_fill's contract).
// Rows of a level are independent in both passes, so they run in parallel
// and the result is the same for any thread count.
bool push_pull(std::span<float* const> planes, const float* weight, int width, int height, const Exec& exec) {
    const std::size_t n = std::size_t(width) * std::size_t(height);
    const int nc = int(planes.size());
    bool any = false, missing = false;
    for (std::size_t i = 0; i < n && !(any && missing); ++i) {
        any = any || weight[i] > 0.0f;
        missing = missing || !(weight[i] > 0.0f);
    }
    if (!any) return false;
    if (!missing) return true;

    std::vector<Level> levels(1);
    Level& l0 = levels[0];
    l0.w = width;
    l0.h = height;
    l0.weight.resize(n);
    l0.values.assign(std::size_t(nc), std::vector<float>(n));
    parallel_for(exec, height, [&](long y0, long y1) {
        for (std::size_t i = std::size_t(y0) * std::size_t(width); i < std::size_t(y1) * std::size_t(width); ++i) {
            const float w = std::clamp(weight[i], 0.0f, 1.0f);
            l0.weight[i] = w;
            for (int c = 0; c < nc; ++c) l0.values[std::size_t(c)][i] = w > 0.0f ? planes[std::size_t(c)][i] : 0.0f;
        }
    }, 16);
    // Push: halve until 1x1.
    while (levels.back().w > 1 || levels.back().h > 1) {
        const Level& f = levels.back();
        Level c;
        c.w = (f.w + 1) / 2;
        c.h = (f.h + 1) / 2;
        const std::size_t cn = std::size_t(c.w) * std::size_t(c.h);
        c.weight.assign(cn, 0.0f);
        c.values.assign(std::size_t(nc), std::vector<float>(cn, 0.0f));
        parallel_for(exec, c.h, [&](long y0, long y1) {
            std::vector<double> vsum(planes.size());
            for (long yl = y0; yl < y1; ++yl) {
                const int y = int(yl);
                for (int x = 0; x < c.w; ++x) {
                    double wsum = 0.0;
                    std::fill(vsum.begin(), vsum.end(), 0.0);
                    for (int dy = 0; dy < 2; ++dy)
                        for (int dx = 0; dx < 2; ++dx) {
                            const int fx = 2 * x + dx, fy = 2 * y + dy;
                            if (fx >= f.w || fy >= f.h) continue;
                            const std::size_t fi = std::size_t(fy) * std::size_t(f.w) + std::size_t(fx);
                            const double w = f.weight[fi];
                            if (!(w > 0.0)) continue;
                            wsum += w;
                            for (int k = 0; k < nc; ++k) vsum[std::size_t(k)] += w * f.values[std::size_t(k)][fi];
                        }
                    const std::size_t ci = std::size_t(y) * std::size_t(c.w) + std::size_t(x);
                    if (wsum > 0.0)
                        for (int k = 0; k < nc; ++k) c.values[std::size_t(k)][ci] = float(vsum[std::size_t(k)] / wsum);
                    c.weight[ci] = float(std::min(1.0, wsum));
                }
            }
        }, 16);
        levels.push_back(std::move(c));
    }
    // Pull: from the top, blend each level with the upsampled level above.
    for (int li = int(levels.size()) - 2; li >= 0; --li) {
        Level& f = levels[std::size_t(li)];
        const Level& c = levels[std::size_t(li) + 1];
        parallel_for(exec, f.h, [&](long y0, long y1) {
            for (long yl = y0; yl < y1; ++yl) {
                const int y = int(yl);
                // Fine pixel centre in coarse pixel coordinates.
                const double cy = std::clamp((y + 0.5) / 2.0 - 0.5, 0.0, double(c.h - 1));
                const int ya = int(cy), yb = std::min(ya + 1, c.h - 1);
                const double ty = cy - ya;
                for (int x = 0; x < f.w; ++x) {
                    const std::size_t fi = std::size_t(y) * std::size_t(f.w) + std::size_t(x);
                    const double w = f.weight[fi];
                    if (w >= 1.0) continue;
                    const double cx = std::clamp((x + 0.5) / 2.0 - 0.5, 0.0, double(c.w - 1));
                    const int xa = int(cx), xb = std::min(xa + 1, c.w - 1);
                    const double tx = cx - xa;
                    for (int k = 0; k < nc; ++k) {
                        const auto& v = c.values[std::size_t(k)];
                        auto at = [&](int xx, int yy) { return double(v[std::size_t(yy) * std::size_t(c.w) + std::size_t(xx)]); };
                        const double up = (1 - ty) * ((1 - tx) * at(xa, ya) + tx * at(xb, ya)) +
                                          ty * ((1 - tx) * at(xa, yb) + tx * at(xb, yb));
                        float& fv = f.values[std::size_t(k)][fi];
                        fv = float(w * fv + (1.0 - w) * up);
                    }
                    f.weight[fi] = 1.0f;
                }
            }
        }, 16);
    }
    // levels[0], not l0: push_back above may have moved the levels.
    const Level& base = levels[0];
    parallel_for(exec, height, [&](long y0, long y1) {
        for (std::size_t i = std::size_t(y0) * std::size_t(width); i < std::size_t(y1) * std::size_t(width); ++i)
            if (!(weight[i] > 0.0f))
                for (int c = 0; c < nc; ++c) planes[std::size_t(c)][i] = base.values[std::size_t(c)][i];
    }, 16);
    return true;
}

}  // namespace

bool push_pull_fill(const ImageView& planes, const ConstImageView& weight, const Exec& exec) {
    using namespace image_detail;
    if (planes.window.empty() || planes.nchannels <= 0) return false;
    if (!check_view_shape(planes, kAnyChannelCount, planes.window, "fill planes") ||
        !check_view_shape(weight, 1, planes.window, "fill weight"))
        return false;
    const RowMajorPlanes<float> p(planes);
    const RowMajorPlanes<const float> w(weight);
    if (!push_pull(p.planes(), w.plane(0), planes.width(), planes.height(), exec)) return false;
    p.store();
    return true;
}

}  // namespace gdof
