// Speckle islands in a depth map: small groups of pixels whose depth no
// neighbour continues. They become holes, which the guided fill then closes.
//
// Surfaces are the 8-connected components of "continuous" neighbours (depth
// ratio within `continuity`, or both sky). A component is a speckle when it
// has at most max_px pixels and most of the pixels around it belong to
// large components: inside a noisy surface that falls apart into small
// pieces nothing is removed (there is no surface to restore from).
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "plate/plate_internal.h"

namespace gdof::plate_detail {

namespace {

struct UnionFind {
    std::vector<int> parent, size;
    explicit UnionFind(std::size_t n) : parent(n), size(n, 1) { std::iota(parent.begin(), parent.end(), 0); }
    int find(int i) {
        while (parent[std::size_t(i)] != i) {
            parent[std::size_t(i)] = parent[std::size_t(parent[std::size_t(i)])];
            i = parent[std::size_t(i)];
        }
        return i;
    }
    void join(int a, int b) {
        a = find(a), b = find(b);
        if (a == b) return;
        if (size[std::size_t(a)] < size[std::size_t(b)]) std::swap(a, b);
        parent[std::size_t(b)] = a;
        size[std::size_t(a)] += size[std::size_t(b)];
    }
};

bool continuous(float a, float b, double ratio) {
    if (std::isnan(a) || std::isnan(b)) return false;
    if (std::isinf(a) || std::isinf(b)) return std::isinf(a) && std::isinf(b);
    const double lo = std::min(a, b), hi = std::max(a, b);
    return hi <= lo * ratio;
}

}  // namespace

std::size_t remove_speckles(std::vector<float>& depth, int W, int H, double continuity, int max_px,
                            const std::vector<unsigned char>& keep) {
    const std::size_t n = depth.size();
    UnionFind uf(n);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const int i = y * W + x;
            const float d = depth[std::size_t(i)];
            if (std::isnan(d)) continue;
            // Forward neighbours only: right, below-left, below, below-right.
            const int nb[4][2] = {{1, 0}, {-1, 1}, {0, 1}, {1, 1}};
            for (const auto& o : nb) {
                const int xx = x + o[0], yy = y + o[1];
                if (xx < 0 || xx >= W || yy >= H) continue;
                const int j = yy * W + xx;
                if (continuous(d, depth[std::size_t(j)], continuity)) uf.join(i, j);
            }
        }
    // Per small component: how many of its outside neighbours lie in large components.
    std::vector<int> big_nb(n, 0), all_nb(n, 0);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const int i = y * W + x;
            if (std::isnan(depth[std::size_t(i)])) continue;
            const int ri = uf.find(i);
            if (uf.size[std::size_t(ri)] > max_px) continue;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const int xx = x + dx, yy = y + dy;
                    if ((dx == 0 && dy == 0) || xx < 0 || xx >= W || yy < 0 || yy >= H) continue;
                    const int j = yy * W + xx;
                    if (std::isnan(depth[std::size_t(j)])) continue;
                    const int rj = uf.find(j);
                    if (rj == ri) continue;
                    ++all_nb[std::size_t(ri)];
                    if (uf.size[std::size_t(rj)] > max_px) ++big_nb[std::size_t(ri)];
                }
        }
    std::size_t removed = 0;
    for (std::size_t i = 0; i < n; ++i) {
        if (std::isnan(depth[i]) || keep[i]) continue;
        const int r = uf.find(int(i));
        if (uf.size[std::size_t(r)] > max_px) continue;
        const int all = all_nb[std::size_t(r)], big = big_nb[std::size_t(r)];
        if (all > 0 && 2 * big >= all) {
            depth[i] = std::numeric_limits<float>::quiet_NaN();
            ++removed;
        }
    }
    return removed;
}

}  // namespace gdof::plate_detail
