// A slice's surface onward (Layer::onward, layers_from_depth_map): where a
// bound crosses a surface (a ceiling, a floor), the pixels of the farther
// part next to the nearer part's slice. The defocus blurs the nearer layer
// there with those pixels' own radii instead of its own radii extrapolated,
// so its edge spreads over the farther part as the whole surface would: a
// lamp at the largest blur above ceiling rows that blur less no longer
// throws its Gaussian tail over them (docs/diffusion.md, "Past a plate
// layer's coverage").
//
// Reached from the slice's own pixels over 8-neighbours whose depths lie
// within `continuity` of each other, into farther slices only, at most
// `reach` steps, and only while nearer (chessboard distance) to where the
// slice continues than to any of its silhouettes: a floor goes on from the
// base of a blurred object standing on it, but beside the object the floor
// is its background, over which the object must spread with its own blur.
#include <algorithm>
#include <cstdint>

#include "layers/layers_internal.h"

namespace gdof::layers_detail {

namespace {

constexpr std::uint16_t kFar = 0xffff;  // not reached

// Calls f(x, y) for the 8 neighbours of (x, y) inside `g`.
template <typename F>
void for_each_neighbour(int x, int y, const Roi& g, F&& f) {
    for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx)
            if ((dx != 0 || dy != 0) && g.contains(x + dx, y + dy)) f(x + dx, y + dy);
}

// Whether the three slices from p are all s.
inline bool all_own(const int* p, int s) { return p[0] == s && p[1] == s && p[2] == s; }

}  // namespace

SurfaceOnward surface_onward(const SurfaceOnwardInput& in, int s, const Roi& own, int reach, const Exec& exec) {
    SurfaceOnward out;
    const int W = in.width, H = in.height;
    const Roi frame{0, 0, W, H};
    const Roi o = intersect(own, frame);
    reach = std::min(reach, int(kFar) - 2);
    if (o.empty() || reach <= 0) return out;
    // Everything happens within `reach` + 1 of the own pixels.
    const Roi g = intersect(o.grown(reach + 1), frame);
    const int GW = g.width();
    const std::size_t gn = g.npixels();
    auto frame_index = [&](int x, int y) { return std::size_t(y) * std::size_t(W) + std::size_t(x); };
    auto local = [&](int x, int y) { return std::size_t(y - g.y0) * std::size_t(GW) + std::size_t(x - g.x0); };
    const int* slice = in.slice.data();
    const int* fg = in.fg_slice.data();
    const float* depth = in.depth.data();
    const unsigned char* present = in.present.data();
    const int* mixed = in.mixed.empty() ? nullptr : in.mixed.data();
    // A farther pixel the surface may go on into: with a sample, in a
    // farther slice, not a silhouette's mixed pixel (split or not).
    auto farther = [&](std::size_t j) { return present[j] && slice[j] > s && fg[j] < 0 && !(mixed && mixed[j] >= 0); };

    // Own pixels where the surface goes on past them, and the silhouettes
    // (beside a farther pixel of another surface, a split or mixed pixel,
    // emptiness): per row of the own box, in row order.
    std::vector<std::vector<std::size_t>> goes_on(std::size_t(o.height())), silhouette(std::size_t(o.height()));
    parallel_for(exec, o.height(), [&](long r0, long r1) {
        for (int y = o.y0 + int(r0); y < o.y0 + int(r1); ++y)
            for (int x = o.x0; x < o.x1; ++x) {
                const std::size_t i = frame_index(x, y);
                if (slice[i] != s) continue;
                // Inside the slice (all 8 neighbours its own): neither.
                if (x > 0 && x + 1 < W && y > 0 && y + 1 < H && all_own(slice + i - std::size_t(W) - 1, s) &&
                    slice[i - 1] == s && slice[i + 1] == s && all_own(slice + i + std::size_t(W) - 1, s))
                    continue;
                bool on = false, edge = false;
                for_each_neighbour(x, y, frame, [&](int xx, int yy) {
                    const std::size_t j = frame_index(xx, yy);
                    if (slice[j] == s) return;  // own (a split pixel's background part too)
                    if (slice[j] >= 0 && slice[j] < s && present[j]) return;  // a nearer occluder
                    (farther(j) && same_surface(depth[i], depth[j], in.continuity) ? on : edge) = true;
                });
                if (on) goes_on[std::size_t(y - o.y0)].push_back(local(x, y));
                if (edge) silhouette[std::size_t(y - o.y0)].push_back(local(x, y));
            }
    }, 8);
    bool any = false;
    for (const auto& row : goes_on) any = any || !row.empty();
    if (!any) return out;  // no bound crosses a surface of this slice

    // Chessboard distance to the silhouettes, up to reach + 1.
    std::vector<std::uint16_t> to_silhouette(gn, kFar);
    std::vector<std::size_t> queue;
    for (const auto& row : silhouette)
        for (std::size_t l : row) {
            to_silhouette[l] = 0;
            queue.push_back(l);
        }
    for (std::size_t head = 0; head < queue.size(); ++head) {
        const std::size_t l = queue[head];
        const int d = to_silhouette[l];
        if (d > reach) continue;
        for_each_neighbour(g.x0 + int(l % std::size_t(GW)), g.y0 + int(l / std::size_t(GW)), g, [&](int xx, int yy) {
            const std::size_t m = local(xx, yy);
            if (to_silhouette[m] != kFar) return;
            to_silhouette[m] = std::uint16_t(d + 1);
            queue.push_back(m);
        });
    }

    // The walk from where the surface goes on, each step within
    // `continuity`, nearer to that than to a silhouette.
    std::vector<std::uint16_t> steps(gn, kFar);
    queue.clear();
    for (const auto& row : goes_on)
        for (std::size_t l : row) {
            steps[l] = 0;
            queue.push_back(l);
        }
    const std::size_t seeds = queue.size();
    Roi area;
    for (std::size_t head = 0; head < queue.size(); ++head) {
        const std::size_t l = queue[head];
        const int d = steps[l];
        if (d >= reach) continue;
        const int x = g.x0 + int(l % std::size_t(GW)), y = g.y0 + int(l / std::size_t(GW));
        const float zi = depth[frame_index(x, y)];
        for_each_neighbour(x, y, g, [&](int xx, int yy) {
            const std::size_t m = local(xx, yy), j = frame_index(xx, yy);
            if (steps[m] != kFar || !farther(j) || !same_surface(zi, depth[j], in.continuity)) return;
            if (to_silhouette[m] <= d + 1) return;
            steps[m] = std::uint16_t(d + 1);
            area = unite(area, Roi{xx, yy, xx + 1, yy + 1});
            queue.push_back(m);
        });
    }
    if (area.empty()) return out;
    // The walked pixels (the queue past its seeds), over their box.
    out.box = area;
    out.mask.assign(area.npixels(), 0);
    for (std::size_t k = seeds; k < queue.size(); ++k) {
        const int x = g.x0 + int(queue[k] % std::size_t(GW)), y = g.y0 + int(queue[k] / std::size_t(GW));
        out.mask[std::size_t(y - area.y0) * std::size_t(area.width()) + std::size_t(x - area.x0)] = 1;
    }
    return out;
}

void write_onward(Layer& L, const Roi& frame, const float* depth, const std::array<const float*, 3>& p) {
    const Roi& b = L.onward_box;
    const std::array<float*, 8> op = layer_planes(L.image);
    const bool positions = op[5] && p[0];
    for (int y = b.y0; y < b.y1; ++y)
        for (int x = b.x0; x < b.x1; ++x) {
            if (!L.onward[std::size_t(y - b.y0) * std::size_t(b.width()) + std::size_t(x - b.x0)]) continue;
            const std::size_t i = std::size_t(y - frame.y0) * std::size_t(frame.width()) + std::size_t(x - frame.x0);
            const std::size_t o = L.image.offset(x, y);
            op[4][o] = depth[i];
            for (int c = 0; positions && c < 3; ++c) op[std::size_t(5 + c)][o] = p[std::size_t(c)][i];
        }
}

}  // namespace gdof::layers_detail
