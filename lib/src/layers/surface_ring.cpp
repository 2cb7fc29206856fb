// The ring of a layer's extension behind its own surface
// (ExtendOptions::surface_reach_px): where a slice bound crosses a surface
// (a wall, a floor), the far part is extended behind the near part by
// extend_px, but the near part's blurred edge lets it show up to the
// kernel's reach, about 1.5 R. Past extend_px the two parts' coverages
// summed below one: a band along the bound, 3% darker than the surface
// blurred whole (5% for a plate whose wall is not its farthest layer).
//
// The extension goes on there, one ring of pixels at a time from what the
// layer covers (its own pixels and its extension), each pixel the mean of
// its covered or already continued 8-neighbours whose depth continues the
// surface seen there (within `continuity`). It stops where the surface
// seen is another (an object in front), where the layer may not extend
// (not hidden, or another owner's), and after surface_reach_px -
// extend_px rings. The ring is seen only through the near part's Gaussian
// tail, so a local continuation of the extension's edge is enough; a
// second fill over the longer reach cost the 4K deep frame 28%, and a fill
// over a larger region than extend_px's changes the extension within it
// (a lamp cut by a bound lost 10% of its continued coverage).
#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "layers/layers_internal.h"

namespace gdof::layers_detail {

namespace {

// A continued pixel: its unpremultiplied colour, alpha, depth and
// positions, and where it is.
struct RingPixel {
    int x = 0, y = 0;
    std::array<float, 3> colour{};
    float alpha = 0.0f, z = 0.0f;
    std::array<float, 3> p{};
};

// The mean of a pixel's sources (RingPixel without its place).
struct Mean {
    double colour[3] = {0, 0, 0}, alpha = 0, z = 0, p[3] = {0, 0, 0};
    int n = 0;
    void add(const RingPixel& v) {
        for (int c = 0; c < 3; ++c) colour[c] += v.colour[std::size_t(c)], p[c] += v.p[std::size_t(c)];
        alpha += v.alpha;
        z += v.z;
        ++n;
    }
    RingPixel at(int x, int y) const {
        RingPixel r;
        r.x = x, r.y = y;
        for (int c = 0; c < 3; ++c) r.colour[std::size_t(c)] = float(colour[c] / n), r.p[std::size_t(c)] = float(p[c] / n);
        r.alpha = float(alpha / n);
        r.z = float(z / n);
        return r;
    }
};

}  // namespace

Status extend_ring(Layer& L, int s, const ExtensionPlan& plan, const ExtendOptions& opt, const Exec& exec) {
    const int rings = int(std::ceil(opt.surface_reach_px - opt.extend_px));
    const bool fills_frame = opt.farthest_fills_frame && s == plan.farthest;
    if (rings <= 0 || opt.front_depth.empty() || fills_frame || s <= plan.nearest) return Status::ok();
    const Roi& frame = plan.frame;
    const Roi lw = L.image.data_window();
    const Roi search = intersect(lw.grown(rings), frame);
    if (search.empty()) return Status::ok();
    const Image& img = L.image;
    const bool has_p = img.nchannels() >= 8;
    const std::size_t FW = std::size_t(frame.width());
    auto fi = [&](int x, int y) { return std::size_t(y - frame.y0) * FW + std::size_t(x - frame.x0); };
    const float* front = opt.front_depth.data();
    // What the layer covers at (x, y) (own or extension), as a source.
    auto covered = [&](int x, int y, RingPixel& v) {
        if (!lw.contains(x, y)) return false;
        const std::size_t o = img.offset(x, y);
        const float a = img.plane(3)[o];
        if (!(a > 0.0f) || !std::isfinite(img.plane(4)[o])) return false;
        v.alpha = a;
        for (int c = 0; c < 3; ++c) v.colour[std::size_t(c)] = img.plane(c)[o] / a;
        v.z = img.plane(4)[o];
        for (int c = 0; c < 3; ++c) v.p[std::size_t(c)] = has_p ? img.plane(5 + c)[o] : 0.0f;
        return true;
    };
    // Where the layer may go on: a surface seen there that its depths
    // continue (tested first: it rules out most of the frame for one
    // float), hidden by a nearer layer, its own to extend, not covered
    // already.
    const double znear = L.depth_near / opt.continuity, zfar = L.depth_far * opt.continuity;
    if (!(znear > 0.0) || !(zfar >= znear)) return Status::ok();  // no depth of its own (NaN: empty)
    auto open = [&](int x, int y) {
        const std::size_t i = fi(x, y);
        if (!(double(front[i]) >= znear && double(front[i]) <= zfar)) return false;
        if (!(s >= int(plan.hidden_from[i]))) return false;
        if (!opt.owner.empty() && opt.owner[i] != s) return false;
        if (lw.contains(x, y) && img.plane(3)[img.offset(x, y)] > 0.0f) return false;
        return true;
    };
    // The mean of (x, y)'s 8-neighbours that `source` gives (source(nx, ny,
    // value)) and whose depth continues the surface seen at (x, y).
    auto mean_of_sources = [&](int x, int y, const auto& source) {
        const float zf = front[fi(x, y)];
        Mean m;
        RingPixel v;
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx)
                if ((dx || dy) && source(x + dx, y + dy, v) && same_surface(zf, v.z, opt.continuity)) m.add(v);
        return m;
    };
    // Ring 1, rows in parallel: the open pixels beside what the layer covers.
    std::vector<std::vector<RingPixel>> rows(static_cast<std::size_t>(search.height()));
    const bool done = parallel_for(exec, search.height(), [&](long r0, long r1) {
        for (int y = search.y0 + int(r0); y < search.y0 + int(r1); ++y) {
            std::vector<RingPixel>& out = rows[std::size_t(y - search.y0)];
            for (int x = search.x0; x < search.x1; ++x) {
                if (!open(x, y)) continue;
                const Mean m = mean_of_sources(x, y, covered);
                if (m.n > 0) out.push_back(m.at(x, y));
            }
        }
    }, 16);
    if (!done) return Status::cancelled("layer extension");
    std::vector<RingPixel> ring;
    for (const auto& r : rows) ring.insert(ring.end(), r.begin(), r.end());
    if (ring.empty()) return Status::ok();
    rows = {};
    // Rings 2..: from the last ring, serially (a band along the bounds).
    // `index`: per search pixel, its entry in `ring` (-1: none).
    std::vector<int> index(search.npixels(), -1);
    const std::size_t SW = std::size_t(search.width());
    auto si = [&](int x, int y) { return std::size_t(y - search.y0) * SW + std::size_t(x - search.x0); };
    for (std::size_t k = 0; k < ring.size(); ++k) index[si(ring[k].x, ring[k].y)] = int(k);
    std::size_t first = 0;
    for (int level = 2; level <= rings; ++level) {
        if (exec.is_cancelled()) return Status::cancelled("layer extension");
        const std::size_t last = ring.size();
        for (std::size_t k = first; k < last; ++k)
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const int x = ring[k].x + dx, y = ring[k].y + dy;
                    if (!search.contains(x, y) || index[si(x, y)] >= 0 || !open(x, y)) continue;
                    // Sources: covered, or continued by an earlier ring.
                    const Mean m = mean_of_sources(x, y, [&](int nx, int ny, RingPixel& v) {
                        if (!search.contains(nx, ny)) return false;
                        const int j = index[si(nx, ny)];
                        if (j < 0) return covered(nx, ny, v);
                        if (std::size_t(j) >= last) return false;
                        v = ring[std::size_t(j)];
                        return true;
                    });
                    if (m.n == 0) continue;
                    index[si(x, y)] = int(ring.size());
                    ring.push_back(m.at(x, y));
                }
        if (ring.size() == last) break;
        first = last;
    }
    index = {};
    // The layer re-windowed to hold the ring, and the ring written.
    Roi box = lw;
    for (const RingPixel& r : ring) box = unite(box, Roi{r.x, r.y, r.x + 1, r.y + 1});
    if (!(box == lw)) rewindow_layer(L, box, exec);
    Image& out = L.image;
    const std::array<float*, 8> op = layer_planes(out);
    for (const RingPixel& r : ring) {
        const std::size_t o = out.offset(r.x, r.y);
        for (int c = 0; c < 3; ++c) op[std::size_t(c)][o] = r.colour[std::size_t(c)] * r.alpha;
        op[3][o] = r.alpha;
        op[4][o] = r.z;
        for (int c = 0; has_p && c < 3; ++c) op[std::size_t(5 + c)][o] = r.p[std::size_t(c)];
    }
    return Status::ok();
}

}  // namespace gdof::layers_detail
