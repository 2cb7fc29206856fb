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
#include <unordered_map>
#include <utility>

#include "image/frame_buffer.h"
#include "plate/plate_internal.h"

namespace gdof::plate_detail {

namespace {

// Union-find over the pixels. parent and size are set by the first pass
// (each row's runs); size is meaningful at roots only.
struct UnionFind {
    FrameBuffer<int> parent, size;
    explicit UnionFind(std::size_t n) : parent(n), size(n) {}
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

}  // namespace

std::size_t remove_speckles(std::vector<float>& depth, int W, int H, double continuity, int max_px,
                            const std::vector<unsigned char>& keep, const Exec& exec) {
    const std::size_t n = depth.size();
    UnionFind uf(n);
    // Components in bands of rows, in parallel: a band's joins touch only its
    // own pixels, so the bands' union-find trees are disjoint; the rows
    // between bands are joined after, one band edge at a time. The
    // components (and so what is removed) do not depend on the order.
    // Within a band each row's runs of continuous pixels are one tree at
    // once (parent: the run's first pixel), then joined to the row above
    // through the three lower neighbours; a pair of pixels in the same two
    // runs as the last join is skipped untested (already joined).
    constexpr int kBand = 64;
    const int nbands = (H + kBand - 1) / kBand;
    auto runs = [&](int y, std::vector<int>& run) {
        const int r = y * W;
        int start = r;
        for (int x = 0; x < W; ++x) {
            const int i = r + x;
            if (x > 0 && continuous(depth[std::size_t(i - 1)], depth[std::size_t(i)], continuity)) {
                uf.parent[std::size_t(i)] = start;
                ++uf.size[std::size_t(start)];
            } else {
                start = i;
                uf.parent[std::size_t(i)] = i;
                uf.size[std::size_t(i)] = 1;
            }
            run[std::size_t(x)] = start;
        }
    };
    // Row y - 1 to row y (runs `up` and `cur`): below-left, below, below-right.
    auto join_rows = [&](int y, const std::vector<int>& up, const std::vector<int>& cur) {
        const int ru = (y - 1) * W, r = y * W;
        int last_a = -1, last_b = -1;  // the runs of the last join
        for (int x = 0; x < W; ++x) {
            const float d = depth[std::size_t(ru + x)];
            if (std::isnan(d)) continue;
            for (int xx = std::max(0, x - 1); xx <= std::min(W - 1, x + 1); ++xx) {
                // The runs of the last join are joined already: no test needed
                // (most pixels of two long runs).
                const int a = up[std::size_t(x)], b = cur[std::size_t(xx)];
                if (a == last_a && b == last_b) continue;
                if (!continuous(d, depth[std::size_t(r + xx)], continuity)) continue;
                uf.join(a, b);
                last_a = a, last_b = b;
            }
        }
    };
    // The rows between bands (y the last of a band, y + 1 the first of the
    // next): a pixel's three lower neighbours (its right neighbour is in its
    // own run already).
    auto join_below = [&](int x, int y) {
        const int i = y * W + x;
        const float d = depth[std::size_t(i)];
        if (std::isnan(d)) return;
        for (int xx = std::max(0, x - 1); xx <= std::min(W - 1, x + 1); ++xx) {
            const int j = (y + 1) * W + xx;
            if (continuous(d, depth[std::size_t(j)], continuity)) uf.join(i, j);
        }
    };
    // A cancelled pass leaves parents unset (they are not initialised):
    // nothing after it may follow them. The caller reports the cancel.
    const bool banded = parallel_for(exec, nbands, [&](long b0, long b1) {
        std::vector<int> up(static_cast<std::size_t>(W)), cur(static_cast<std::size_t>(W));
        for (long b = b0; b < b1; ++b) {
            const int y0 = int(b) * kBand, y1 = std::min(H, y0 + kBand);
            for (int y = y0; y < y1; ++y) {
                runs(y, cur);
                if (y > y0) join_rows(y, up, cur);
                std::swap(up, cur);
            }
        }
    });
    if (!banded) return 0;
    for (int b = 1; b < nbands; ++b)
        for (int x = 0; x < W; ++x) join_below(x, b * kBand - 1);
    // Whether each pixel is in a small component, and the roots of those
    // (unset elsewhere): found without path compression (reads only, so in
    // parallel), once per run of pixels with the same parent.
    FrameBuffer<unsigned char> is_small(n);  // every element set below
    FrameBuffer<int> root(n);                // set where is_small
    const bool found = parallel_for(exec, H, [&](long y0, long y1) {
        const int* parent = uf.parent.data();
        const int* size = uf.size.data();
        unsigned char* sm = is_small.data();
        int* rt = root.data();
        const int limit = max_px;
        for (std::size_t i = std::size_t(y0) * std::size_t(W); i < std::size_t(y1) * std::size_t(W);) {
            const int p = parent[i];
            int r = p;
            while (parent[std::size_t(r)] != r) r = parent[std::size_t(r)];
            const bool small = size[std::size_t(r)] <= limit;
            for (; i < std::size_t(y1) * std::size_t(W) && parent[i] == p; ++i) {
                sm[i] = small ? 1 : 0;
                if (small) rt[i] = r;
            }
        }
    }, 16);
    if (!found) return 0;
    // Per small component: how many of its outside neighbours there are, and
    // how many lie in large components (a large neighbour is in another
    // component). Small components are few: each row lists its pixels'
    // counts, summed per component after.
    struct Count {
        int root, all, big;
    };
    std::vector<std::vector<Count>> row_counts(static_cast<std::size_t>(H));
    const bool counted = parallel_for(exec, H, [&](long r0, long r1) {
        for (int y = int(r0); y < int(r1); ++y)
            for (int x = 0; x < W; ++x) {
                const std::size_t i = std::size_t(y) * std::size_t(W) + std::size_t(x);
                if (!is_small[i] || std::isnan(depth[i])) continue;
                Count c{root[i], 0, 0};
                for (int dy = -1; dy <= 1; ++dy)
                    for (int dx = -1; dx <= 1; ++dx) {
                        const int xx = x + dx, yy = y + dy;
                        if ((dx == 0 && dy == 0) || xx < 0 || xx >= W || yy < 0 || yy >= H) continue;
                        const std::size_t j = std::size_t(yy) * std::size_t(W) + std::size_t(xx);
                        if (std::isnan(depth[j]) || (is_small[j] && root[j] == root[i])) continue;
                        ++c.all;
                        if (!is_small[j]) ++c.big;
                    }
                if (c.all) row_counts[std::size_t(y)].push_back(c);
            }
    }, 16);
    if (!counted) return 0;
    std::unordered_map<int, std::pair<int, int>> comp;  // root -> (all, big)
    for (const auto& row : row_counts)
        for (const Count& c : row) {
            auto& t = comp[c.root];
            t.first += c.all, t.second += c.big;
        }
    std::vector<std::size_t> row_removed(std::size_t(H), 0);
    parallel_for(exec, H, [&](long y0, long y1) {
        for (long y = y0; y < y1; ++y)
            for (std::size_t i = std::size_t(y) * std::size_t(W); i < std::size_t(y + 1) * std::size_t(W); ++i) {
                if (!is_small[i] || std::isnan(depth[i]) || keep[i]) continue;
                const auto it = comp.find(root[i]);
                if (it == comp.end()) continue;
                const int all = it->second.first, big = it->second.second;
                if (all > 0 && 2 * big >= all) {
                    depth[i] = std::numeric_limits<float>::quiet_NaN();
                    ++row_removed[std::size_t(y)];
                }
            }
    }, 16);
    std::size_t removed = 0;
    for (std::size_t r : row_removed) removed += r;
    return removed;
}

}  // namespace gdof::plate_detail
