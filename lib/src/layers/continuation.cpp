// Continued surfaces (layers.h, layers_from_depth_map): the pixels of nearer
// slices that continue a slice's own surface. A breadth-first walk from the
// slice's own pixels over 8-neighbours whose depths lie within `continuity`
// of each other, into nearer slices only, at most `reach` steps
// (chessboard distance) from the slice.
#include <cmath>
#include <deque>

#include "layers/layers_internal.h"

namespace gdof::layers_detail {

Roi continue_surface(const std::vector<float>& depth, const std::vector<unsigned char>& present,
                     const std::vector<int>& slice, int s, int W, int H, const Roi& win, double continuity, int reach,
                     std::vector<unsigned char>& cont) {
    const std::size_t n = depth.size();
    cont.assign(n, 0);
    auto continues = [&](std::size_t i, std::size_t j) {
        const float a = depth[i], b = depth[j];
        if (!std::isfinite(a) || !std::isfinite(b)) return false;
        return double(std::max(a, b)) <= double(std::min(a, b)) * continuity;
    };
    auto nearer = [&](std::size_t j) { return present[j] && slice[j] >= 0 && slice[j] < s; };
    std::vector<int> dist(n, -1);
    std::deque<std::size_t> queue;
    // Start from the own pixels that touch a nearer pixel of their surface.
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const std::size_t i = std::size_t(y) * std::size_t(W) + std::size_t(x);
            if (slice[i] != s) continue;
            bool edge = false;
            for (int dy = -1; dy <= 1 && !edge; ++dy)
                for (int dx = -1; dx <= 1 && !edge; ++dx) {
                    const int xx = x + dx, yy = y + dy;
                    if (xx < 0 || xx >= W || yy < 0 || yy >= H) continue;
                    const std::size_t j = std::size_t(yy) * std::size_t(W) + std::size_t(xx);
                    edge = nearer(j) && continues(i, j);
                }
            if (edge) {
                dist[i] = 0;
                queue.push_back(i);
            }
        }
    Roi box;
    while (!queue.empty()) {
        const std::size_t i = queue.front();
        queue.pop_front();
        if (dist[i] >= reach) continue;
        const int x = int(i % std::size_t(W)), y = int(i / std::size_t(W));
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
                const int xx = x + dx, yy = y + dy;
                if ((dx == 0 && dy == 0) || xx < 0 || xx >= W || yy < 0 || yy >= H) continue;
                const std::size_t j = std::size_t(yy) * std::size_t(W) + std::size_t(xx);
                if (dist[j] >= 0 || !nearer(j) || !continues(i, j)) continue;
                dist[j] = dist[i] + 1;
                cont[j] = 1;
                box = unite(box, Roi{win.x0 + xx, win.y0 + yy, win.x0 + xx + 1, win.y0 + yy + 1});
                queue.push_back(j);
            }
    }
    return box;
}

}  // namespace gdof::layers_detail
