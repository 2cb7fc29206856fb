// A plate layer's radii past its coverage (Layer::onward_marked), set over
// the push-pull fill of extrapolated_radius, which averages the layer's
// radii and so puts a blurred object's smaller ones (its limb, the floor it
// stands on in the same layer) into what spreads past its silhouette:
//
//  - its surface onward (Layer::onward: a bound across a ceiling) takes the
//    surface's own radii, so the near part spreads over the far part as the
//    whole surface would;
//  - past a silhouette, a pixel takes the largest radius r_q among the
//    layer's points q whose circle reaches it (|p - q| <= r_q): a lens
//    spreads each point of a blurred object over its own circle of
//    confusion, the larger ones farthest; the fill is kept where no point
//    reaches.
//
// Found in two chamfer passes (steps 1 and sqrt 2, at most 8% over the
// Euclidean distance) that carry per cell the largest radius still
// reaching it and the reach it has left; a candidate that reaches less
// far but has a smaller radius is dropped on the way, so this is a close
// approximation of the rule (docs/diffusion.md, "Past a plate layer's
// coverage": within 0.0005 of the exact rule's edge error on the
// benchmark's panels but one).
#include <cmath>
#include <limits>

#include "diffusion/defocus_internal.h"

namespace gdof::defocus_detail {

namespace {

constexpr float kNone = -std::numeric_limits<float>::infinity();
constexpr float kDiagonal = 1.41421356f;
// Cells per largest radius: the reach is found on a grid of square cells
// of side f = largest radius / 8 px (at least 1 px), each holding its own
// pixels' largest radius; its boundary then lies within about 1/8 of the
// largest radius of the pixel-exact one, at 1/f^2 of its cost (a 4K
// frame's layers blurred up to 42 px: 17 ms a layer, 2 cores).
constexpr double kCellsPerRadius = 8.0;

// Relax cell i from neighbour j at step w. Only candidates that still reach
// count (a reach below 0 never grows again): the largest radius wins, then
// the larger reach left.
inline void relax(float* reach, float* radius, std::size_t i, std::size_t j, float w) {
    const float c = reach[j] - w;
    if (!(c >= 0.0f)) return;
    if (reach[i] < 0.0f || radius[j] > radius[i] || (radius[j] == radius[i] && c > reach[i])) {
        reach[i] = c;
        radius[i] = radius[j];
    }
}

}  // namespace

void radius_past_coverage(const Layer& layer, const LayerAnalysis& analysis, const Roi& ext, RadiusMap& full,
                          const Exec& exec) {
    if (!layer.onward_marked) return;
    const Image& img = layer.image;
    const Roi win = img.data_window();
    const int EW = ext.width(), EH = ext.height();
    const KnownWeight known(analysis, layer);
    const Roi ob = layer.onward_box;
    auto onward = [&](int x, int y) {
        return !layer.onward.empty() && ob.contains(x, y) &&
               layer.onward[std::size_t(y - ob.y0) * std::size_t(ob.width()) + std::size_t(x - ob.x0)];
    };
    // Per cell of ext: the largest radius among the points that reach it,
    // and the reach they have left (radius - distance). Cells with own
    // pixels start with the largest of their radii; every row written here.
    const int f = std::max(1, int(analysis.max_radius / kCellsPerRadius));
    const int CW = (EW + f - 1) / f, CH = (EH + f - 1) / f;
    FrameBuffer<float> reach(std::size_t(CW) * std::size_t(CH)), radius(std::size_t(CW) * std::size_t(CH));
    parallel_for(exec, CH, [&, known](long r0, long r1) {
        for (int cy = int(r0); cy < int(r1); ++cy) {
            float* re = reach.data() + std::size_t(cy) * std::size_t(CW);
            float* ra = radius.data() + std::size_t(cy) * std::size_t(CW);
            std::fill_n(re, CW, kNone);
            std::fill_n(ra, CW, kNone);
            const int y0 = std::max(ext.y0 + cy * f, win.y0), y1 = std::min({ext.y0 + (cy + 1) * f, ext.y1, win.y1});
            const int x0 = std::max(ext.x0, win.x0), x1 = std::min(ext.x1, win.x1);
            for (int y = y0; y < y1; ++y)
                for (int x = x0; x < x1; ++x) {
                    const std::size_t src = img.offset(x, y);
                    if (!(known(src) > 0.0f)) continue;
                    const std::size_t c = std::size_t((x - ext.x0) / f);
                    const float r = std::max(0.0f, known.radius[src]);
                    if (!(r <= ra[c])) re[c] = ra[c] = r;
                }
        }
    }, 4);
    float* re = reach.data();
    float* ra = radius.data();
    const std::size_t W = std::size_t(CW);
    const float step = float(f), diagonal = float(f) * kDiagonal;
    // Forward (dir 1): each row from the row above, then from the left;
    // backward (dir -1): from the row below, then from the right.
    for (const int dir : {1, -1}) {
        for (int k = 0; k < CH; ++k) {
            const int y = dir > 0 ? k : CH - 1 - k;
            const std::size_t row = std::size_t(y) * W;
            if (k > 0)
                for (int x = 0; x < CW; ++x) {
                    const std::size_t i = row + std::size_t(x), prev = dir > 0 ? i - W : i + W;
                    relax(re, ra, i, prev, step);
                    if (x > 0) relax(re, ra, i, prev - 1, diagonal);
                    if (x + 1 < CW) relax(re, ra, i, prev + 1, diagonal);
                }
            for (int j = 1; j < CW; ++j) {
                const int x = dir > 0 ? j : CW - 1 - j;
                relax(re, ra, row + std::size_t(x), row + std::size_t(x - dir), step);
            }
            if (exec.is_cancelled()) return;
        }
    }
    parallel_for(exec, EH, [&, known](long r0, long r1) {
        for (int y = ext.y0 + int(r0); y < ext.y0 + int(r1); ++y)
            for (int x = ext.x0; x < ext.x1; ++x) {
                const std::size_t e = std::size_t(y - ext.y0) * std::size_t(EW) + std::size_t(x - ext.x0);
                const std::size_t c = std::size_t((y - ext.y0) / f) * W + std::size_t((x - ext.x0) / f);
                const bool in_win = win.contains(x, y);
                if (in_win && known(img.offset(x, y)) > 0.0f) continue;  // own
                if (in_win && onward(x, y)) {
                    const float r = analysis.radius[img.offset(x, y)];
                    if (std::isfinite(r)) full[e] = r;
                    continue;
                }
                if (re[c] >= 0.0f) full[e] = ra[c];
            }
    }, 16);
}

}  // namespace gdof::defocus_detail
