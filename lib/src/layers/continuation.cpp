// Continued surfaces (layers.h, layers_from_depth_map): the pixels of nearer
// slices that continue a slice's own surface. A breadth-first walk from the
// slice's own pixels over 8-neighbours whose depths lie within `continuity`
// of each other, into nearer slices only, at most `reach` steps
// (chessboard distance) from the slice, and only while the surface keeps
// coming nearer: a depth cut crosses a surface that recedes in depth (a
// floor, a side wall), and what lies beyond the cut on it comes nearer with
// every step; an object standing on it (a pole, a box: at about one depth)
// does not, and is not continued behind itself, where it would show twice
// once blurred.
#include <cmath>
#include <deque>
#include <limits>

#include "layers/layers_internal.h"

namespace gdof::layers_detail {

namespace {
// How much nearer (relative depth) a continued pixel must be per step from
// where its walk began: a floor seen from 1.1 m comes 0.6% nearer per pixel at
// 4 m and 640 px wide; a pole standing on it 0.01%.
constexpr double kRecede = 0.002;
}  // namespace

Roi continue_surface(const std::vector<float>& depth, const std::vector<unsigned char>& present,
                     std::span<const int> slice, std::span<const int> owner, int s, int W, int H, const Roi& win,
                     double continuity, int reach, std::vector<unsigned char>& cont) {
    const std::size_t n = depth.size();
    cont.assign(n, 0);
    auto continues = [&](std::size_t i, std::size_t j) { return same_surface(depth[i], depth[j], continuity); };
    auto nearer = [&](std::size_t j) {
        return present[j] && slice[j] >= 0 && slice[j] < s && (owner.empty() || owner[j] == s);
    };
    std::vector<int> dist(n, -1);
    // Depth and step of the first continued pixel on the walk to a pixel
    // (the step across the cut itself may jump by up to `continuity`).
    std::vector<float> start(n, 0.0f);
    std::vector<int> start_step(n, 0);
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
                if (dist[i] == 0) {  // the first step, across the cut
                    start[j] = depth[j];
                    start_step[j] = 1;
                } else {
                    const int steps = dist[i] + 1 - start_step[i];
                    if (double(depth[j]) > double(start[i]) * (1.0 - kRecede * steps)) continue;
                    start[j] = start[i];
                    start_step[j] = start_step[i];
                }
                dist[j] = dist[i] + 1;
                cont[j] = 1;
                box = unite(box, Roi{win.x0 + xx, win.y0 + yy, win.x0 + xx + 1, win.y0 + yy + 1});
                queue.push_back(j);
            }
    }
    return box;
}

BackgroundOwners background_owners(std::span<const int> slice, std::span<const int> fg_slice, int nslices,
                                   int W, int H, const Exec& exec, double bound) {
    const std::size_t n = slice.size();
    constexpr float kInf = std::numeric_limits<float>::infinity();
    // Emptiness (no sample at all: a render's transparent sky) is the
    // farthest candidate: a strip of wall next to it has nothing behind it
    // there, and a copy of the next strip would blur out over it a second time.
    // Per pixel: its front (its nearest slice, the nearer of slice and
    // fg_slice) + 1 (0: no sample; at most 65535 slices, as the extension
    // plan), and the nearest slice behind the front so far, at its distance:
    // the owner and distance being found, set in the pass below.
    BackgroundOwners out;
    FrameBuffer<int>& best_k = out.owner;
    FrameBuffer<float>& best = out.distance;
    best_k.resize(n);
    best.resize(n);
    FrameBuffer<std::uint16_t> front_of(n);
    FrameBuffer<float> dist;
    FrameBuffer<unsigned char> mask;  // every element written before each use
    // Each slice's box (its own pixels, where slice or fg_slice is k), and
    // whether anything is empty, in one pass over bands of rows.
    const int nbands = std::max(1, std::min(H, 64));
    std::vector<Roi> band_box(std::size_t(nbands) * std::size_t(std::max(0, nslices)));
    std::vector<unsigned char> band_empty(std::size_t(nbands), 0);
    parallel_for(exec, nbands, [&](long b0, long b1) {
        for (long b = b0; b < b1; ++b) {
            const int y0 = int(std::int64_t(H) * b / nbands), y1 = int(std::int64_t(H) * (b + 1) / nbands);
            Roi* box = band_box.data() + std::size_t(b) * std::size_t(nslices);
            // Per row, each slice's first and last column (a box per row, not
            // per pixel).
            std::vector<int> xlo_v(std::size_t(std::max(0, nslices))), xhi_v(std::size_t(std::max(0, nslices)));
            // Locals: stores may alias anything of their type reached through a reference.
            int* xlo = xlo_v.data();
            int* xhi = xhi_v.data();
            bool empty = false;
            for (int y = y0; y < y1; ++y) {
                std::fill(xlo_v.begin(), xlo_v.end(), W);
                std::fill(xhi_v.begin(), xhi_v.end(), -1);
                const std::size_t r = std::size_t(y) * std::size_t(W);
                const int* sl = slice.data() + r;
                const int* fg = fg_slice.data() + r;
                std::uint16_t* fr = front_of.data() + r;
                int* bk = best_k.data() + r;
                float* bd = best.data() + r;
                const int ns = nslices, cols = W;
                for (int x = 0; x < cols; ++x) {
                    const int a = sl[x], f = fg[x];
                    fr[x] = std::uint16_t((f >= 0 && f < a ? f : a) + 1);  // the front + 1
                    bk[x] = -1;
                    bd[x] = kInf;
                    empty = empty || a < 0;
                    for (int k : {a, f})
                        if (k >= 0 && k < ns) {
                            xlo[k] = std::min(xlo[k], x);
                            xhi[k] = x;
                        }
                }
                for (int k = 0; k < nslices; ++k)
                    if (xhi[k] >= 0) box[k] = unite(box[k], Roi{xlo[k], y, xhi[k] + 1, y + 1});
            }
            if (empty) band_empty[std::size_t(b)] = 1;
        }
    });
    std::vector<Roi> box(std::size_t(std::max(0, nslices)));
    bool any_empty = false;
    for (int b = 0; b < nbands; ++b) {
        any_empty = any_empty || band_empty[std::size_t(b)];
        for (int k = 0; k < nslices; ++k)
            box[std::size_t(k)] = unite(box[std::size_t(k)], band_box[std::size_t(b) * std::size_t(nslices) + std::size_t(k)]);
    }
    // Bounded: distances beyond `bound` are not needed, only whether some
    // slice is behind at all. That is exact only without emptiness, which
    // competes at every distance.
    const bool bounded = std::isfinite(bound) && !any_empty;
    const int grow = bounded ? int(std::ceil(std::max(0.0, bound))) + 1 : 0;
    const Roi frame{0, 0, W, H};
    if (any_empty) {
        mask.resize(n);
        parallel_for(exec, H, [&](long y0, long y1) {
            for (std::size_t i = std::size_t(y0) * std::size_t(W); i < std::size_t(y1) * std::size_t(W); ++i)
                mask[i] = slice[i] < 0;
        }, 16);
        distance_transform(mask, W, H, best, exec);
    }
    // Back to front, each slice's distances join only at the pixels in front
    // of it: then `best` at a pixel is the nearest of the slices behind its
    // front, which is what it needs. The nearest slice's own distances would
    // serve no pixel: not computed.
    int farthest = -1;  // the farthest non-empty slice
    for (int k = nslices - 1; k >= 0 && farthest < 0; --k)
        if (!box[std::size_t(k)].empty()) farthest = k;
    for (int k = nslices - 1; k >= 1; --k) {
        const Roi& own = box[std::size_t(k)];
        if (own.empty()) continue;
        // The distances to slice k over its box grown by the bound (all of
        // the frame when unbounded): exact there, beyond the bound outside.
        const Roi win = bounded ? intersect(own.grown(grow), frame) : frame;
        const int ww = win.width(), wh = win.height();
        mask.resize(win.npixels());
        parallel_for(exec, wh, [&](long r0, long r1) {
            for (long r = r0; r < r1; ++r) {
                // Locals: a byte store may alias anything reached through a reference.
                const std::size_t src = std::size_t(win.y0 + r) * std::size_t(W) + std::size_t(win.x0);
                const int* sl = slice.data() + src;
                const int* fg = fg_slice.data() + src;
                unsigned char* m = mask.data() + std::size_t(r) * std::size_t(ww);
                const int kk = k, cols = ww;
                for (int x = 0; x < cols; ++x) m[x] = sl[x] == kk || fg[x] == kk;
            }
        }, 16);
        distance_transform(mask, ww, wh, dist, exec, bounded ? bound : kInf);
        parallel_for(exec, wh, [&](long r0, long r1) {
            for (long r = r0; r < r1; ++r) {
                const std::size_t src = std::size_t(win.y0 + r) * std::size_t(W) + std::size_t(win.x0);
                const float* d = dist.data() + std::size_t(r) * std::size_t(ww);
                for (int x = 0; x < ww; ++x) {
                    const std::size_t i = src + std::size_t(x);
                    if (front_of[i] > k || (bounded && !(d[x] <= bound))) continue;
                    if (d[x] <= best[i]) best[i] = d[x], best_k[i] = k;  // ties: the nearer slice
                }
            }
        }, 16);
    }
    // Beyond every slice's bound the farthest fills (the extension's
    // farthest_fills_frame): any owner >= 0 says so. No owner where there is
    // no sample, nor a distance without an owner (emptiness).
    parallel_for(exec, H, [&](long y0, long y1) {
        for (std::size_t i = std::size_t(y0) * std::size_t(W); i < std::size_t(y1) * std::size_t(W); ++i) {
            const int f = int(front_of[i]) - 1;
            if (f >= 0 && best_k[i] >= 0) continue;
            best_k[i] = bounded && f >= 0 && f < farthest ? farthest : -1;
            best[i] = kInf;
        }
    }, 16);
    return out;
}

}  // namespace gdof::layers_detail
