// A layer's large blurs solved at reduced resolution (docs/diffusion.md,
// "pyramid"). A blur of radius R at full resolution is a blur of R / 2^j on
// the image averaged over 2^j x 2^j cells, so every pixel is solved on the
// level where its radius is kLevelRadius .. 2 kLevelRadius cells, and the
// result is blended per pixel between the two levels around log2(R / c).
// Every level's radii are capped at 2c, so each level costs about as much as
// a full-resolution blur of 2c px over a quarter of the pixels of the level
// before it: the cost no longer grows with the largest blur.
//
// - Variance: taking the pixels into cells (a quadratic B-spline, 1/4 cell^2)
//   and the cubic B-spline return (1/3 cell^2) add 7/12 cell^2 of variance,
//   7/3 cell^2 of R^2 (sigma = R / 2), at every phase; level radii are
//   reduced by it, so a constant blur keeps its width.
// - A change of blur: both splines keep each pixel's centroid, and cells are
//   linked by the harmonic mean of their diffusivities (conductance.h), so a
//   ramp of blur keeps its width and position (the full-resolution solve's
//   within 1%).
// - Insulation: a level averages only the pixels blurred enough for it (a
//   quarter of its smallest radius and up); sharper ones are insulating holes
//   in it, as they are at full resolution, and returning from the level is
//   weighted by what each cell kept, so no colour crosses a sharp boundary.
// - Sub-regions: cells are aligned to absolute pixel coordinates and every
//   level's step count comes from the whole layer's largest radius, so a
//   sub-region runs the same operator as the whole render (as for one level).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

#include "common/simd_clones.h"
#include "diffusion/conductance.h"
#include "diffusion/defocus_internal.h"
#include "image/mask_dilate.h"

namespace gdof::defocus_detail {

namespace {

constexpr double kLevelRadius = 3.0;  // c: level j solves R / 2^j in [c, 2c)
constexpr int kMaxLevels = 16;
constexpr int kMinCells = 16;
// Variance the round trip adds, in cell^2: the quadratic B-spline that takes
// pixels into cells (1/4) and the cubic B-spline of the return (1/3); as
// R^2 = 4 sigma^2.
constexpr double kResampleR2 = 4.0 * (1.0 / 4.0 + 1.0 / 3.0);

int floor_div(int a, int s) { return a >= 0 ? a / s : -((-a + s - 1) / s); }
int ceil_div(int a, int s) { return -floor_div(-a, s); }

// The cells of `s` pixels that cover the work region (absolute cell
// coordinates, aligned to absolute pixels).
Roi level_window(const Roi& work, int s) {
    return Roi{floor_div(work.x0, s), floor_div(work.y0, s), ceil_div(work.x1, s), ceil_div(work.y1, s)};
}

// Four planes and a radius map over a window of cells (absolute cell
// coordinates of the level), row-major. Only the cells build_level()
// computes are set: the ones solved and read back.
struct Grid {
    Roi win;
    Roi built;                  // the cells computed (the rest is not set)
    FrameBuffer<float> rgba;    // 4 planes
    FrameBuffer<float> radius;  // RMS full-resolution radius of the cell's kept pixels
    FrameBuffer<float> area;    // the weight it kept over a whole cell's (0: an insulating cell)
    FrameBuffer<float> sharpest;  // the smallest radius among the pixels it kept (+inf: none)
    explicit Grid(Roi w)
        : win(w), rgba(4 * w.npixels()), radius(w.npixels()), area(w.npixels()), sharpest(w.npixels()) {}
    std::size_t at(int x, int y) const {
        return std::size_t(y - win.y0) * std::size_t(win.width()) + std::size_t(x - win.x0);
    }
    float* plane(int c) { return rgba.data() + std::size_t(c) * win.npixels(); }
    const float* plane(int c) const { return rgba.data() + std::size_t(c) * win.npixels(); }
};

// The level of a pixel of radius r: log2(r / c) clamped to [0, levels].
float level_of(float r, int levels) {
    if (!(r > float(kLevelRadius))) return 0.0f;
    return std::min(float(levels), std::log2(r / float(kLevelRadius)));
}

// A level's cells take the pixels around them with quadratic B-spline
// weights (pixel p at (p + 0.5) / s - 0.5 cells, to the three cells nearest
// it). Unlike a box, which moves every pixel to its cell's centre (up to half
// a cell), the spline keeps each pixel's centroid, and its variance is
// 1/4 cell^2 at every phase: a box shifted the blurred edge of a bright lamp
// by 3 px at 1080p on the benchmark's Cornell box (the pixels of a straight
// edge share one phase, so their shifts add up).
double bspline2(double v) {
    v = std::abs(v);
    return v < 0.5 ? 0.75 - v * v : v < 1.5 ? 0.5 * (1.5 - v) * (1.5 - v) : 0.0;
}

// How the positions of a finer grid (pixels, or the cells of the level
// below) fall onto a level's cells along one axis: s positions per cell, and
// pat[k] the weight of position X s - s + k to cell X (3s of them).
struct Kernel {
    int s = 1;
    std::vector<float> pat;
    // Pixels onto level j: the spline at the pixel centres.
    static Kernel pixels(int j) {
        Kernel k{1 << j, {}};
        for (int i = 0; i < 3 * k.s; ++i) k.pat.push_back(float(bspline2((i + 0.5) / k.s - 1.5)));
        return k;
    }
    // The cells of level j - 1 onto level j: the spline at twice the scale is
    // four at the finer one, weights (1, 3, 3, 1) / 4 (its two-scale
    // relation), so this is exact for what the finer cells hold.
    static Kernel finer_cells() { return Kernel{2, {0.0f, 0.25f, 0.75f, 0.75f, 0.25f, 0.0f}}; }
    // Position p's natural cells (c - 1 .. c + 1, c = floor(p / s)) and
    // weights.
    void taps(int p, int cell[3], float w[3]) const {
        const int c = floor_div(p, s);
        for (int d = 0; d < 3; ++d) {
            cell[d] = c - 1 + d;
            w[d] = pat[std::size_t(p - cell[d] * s + s)];
        }
    }
};

// The six sums a cell takes (weight times R, G, B, A, R^2, and the weight),
// and a seventh row plane: each kept position's smallest radius (+inf where
// nothing is kept), of which a cell takes the minimum.
constexpr int kSums = 6;
constexpr int kPlanes = kSums + 1;
constexpr float kNone = std::numeric_limits<float>::infinity();

// One finer row's sums over the cells [cx0, cx0 + ncell): `pad` holds one of
// the row's weighted quantities over positions (cx0 - 1) s .. (cx0 + ncell +
// 1) s (nb = ncell + 2 blocks of s; 0 where there is nothing). A cell takes
// three blocks (the one before, its own, the one after): each block's three
// weighted sums are formed phase by phase (contiguous loops over the blocks
// of a transposed copy, which vectorise), then added. `scratch`: 4 nb floats.
GDOF_CLONES
void row_sums(const float* pad, const float* pat, int s, std::size_t ncell, float* out, float* scratch) {
    if (s == 2) {
        // Level 1 and every level built from the one below: the same sums in
        // the same order as the loop below (0 + x is x), the two phases read
        // as even and odd elements (no transposed copy).
        const float p0 = pat[0], p1 = pat[1], p2 = pat[2], p3 = pat[3], p4 = pat[4], p5 = pat[5];
        for (std::size_t X = 0; X < ncell; ++X) {
            const float* v = pad + 2 * X;
            out[X] = ((p0 * v[0] + p1 * v[1]) + (p2 * v[2] + p3 * v[3])) + (p4 * v[4] + p5 * v[5]);
        }
        return;
    }
    const std::size_t nb = ncell + 2, st = std::size_t(s);
    float* a0 = scratch;  // per block: its sum weighted as the cell after it takes it
    float* a1 = a0 + nb;  // as its own cell takes it
    float* a2 = a1 + nb;  // as the cell before it takes it
    float* ph = a2 + nb;  // one phase of every block
    std::fill_n(a0, 3 * nb, 0.0f);
    for (int f = 0; f < s; ++f) {
        for (std::size_t b = 0; b < nb; ++b) ph[b] = pad[b * st + std::size_t(f)];
        const float p0 = pat[f], p1 = pat[s + f], p2 = pat[2 * s + f];
        for (std::size_t b = 0; b < nb; ++b) {
            a0[b] += p0 * ph[b];
            a1[b] += p1 * ph[b];
            a2[b] += p2 * ph[b];
        }
    }
    for (std::size_t X = 0; X < ncell; ++X) out[X] = (a0[X] + a1[X + 1]) + a2[X + 2];
}

// The smallest of `rs` over the positions each cell takes with weight > 0,
// [X s + k0, X s + k1) in the padded row (see row_sums). When that is three
// whole blocks (the pixels' spline), per block first, phase by phase.
GDOF_CLONES
void row_min(const float* rs, int s, int k0, int k1, std::size_t ncell, float* out, float* scratch) {
    const std::size_t st = std::size_t(s);
    if (k0 == 0 && k1 == 3 * s) {
        const std::size_t nb = ncell + 2;
        float* bm = scratch;
        std::fill_n(bm, nb, kNone);
        for (std::size_t f = 0; f < st; ++f)
            for (std::size_t b = 0; b < nb; ++b) bm[b] = std::min(bm[b], rs[b * st + f]);
        for (std::size_t X = 0; X < ncell; ++X) out[X] = std::min(std::min(bm[X], bm[X + 1]), bm[X + 2]);
        return;
    }
    for (std::size_t X = 0; X < ncell; ++X) {
        float v = kNone;
        for (int t = k0; t < k1; ++t) v = std::min(v, rs[X * st + std::size_t(t)]);
        out[X] = v;
    }
}

// A row's six quantities (kSums planes of padw) from its weights, already in
// plane 5 (0 for what the level leaves out): weight times colour and R^2.
GDOF_CLONES
void weighted_row(const float* const pl[4], const float* rad, int n, float* pad, std::size_t padw) {
    const float* m = pad + 5 * padw;
    for (int q = 0; q < 4; ++q) {
        const float* src = pl[q];
        float* d = pad + std::size_t(q) * padw;
        for (int x = 0; x < n; ++x) d[x] = m[x] * src[x];
    }
    float* r2 = pad + 4 * padw;
    for (int x = 0; x < n; ++x) r2[x] = m[x] * (rad[x] * rad[x]);
}

// What a level is built from: positions [span.x0, span.x1) x [span.y0,
// span.y1) of a finer grid, and fill(y, xa, xb, pad, padw) writing row y's
// quantities for positions [xa, xb) at pad[x - xa].
template <class Fill>
Grid build_level(const Roi& span, const Fill& fill, const Kernel& k, const Roi& work, int j, const Roi& needed,
                 const Exec& exec) {
    const int ls = 1 << j, s = k.s;
    Grid g(level_window(work, ls));
    const Roi w = intersect(g.win, needed);  // only the cells that are solved
    g.built = w;
    if (w.empty()) return g;
    const std::size_t ncell = std::size_t(w.width());
    const int px0 = (w.x0 - 1) * s;  // the padded positions of a row
    const std::size_t padw = (ncell + 2) * std::size_t(s);
    const int xa = std::max(span.x0, px0), xb = std::min(span.x1, px0 + int(padw));
    // Positions whose natural cells lie beyond the level's window fold onto
    // its edge cells (the return mirrors there): their extra weights.
    struct Fold {
        int x, cell;
        float w;
    };
    std::vector<Fold> folds;
    for (int x = xa; x < xb; ++x) {
        int cell[3];
        float wt[3];
        k.taps(x, cell, wt);
        for (int d = 0; d < 3; ++d) {
            if (cell[d] >= g.win.x0 && cell[d] < g.win.x1) continue;
            const int c = std::clamp(cell[d], g.win.x0, g.win.x1 - 1);
            if (c >= w.x0 && c < w.x1 && wt[d] > 0.0f) folds.push_back({x, c, wt[d]});
        }
    }
    // The taps of weight > 0 (contiguous): all 3s for pixels, 4 for cells.
    int k0 = 0, k1 = 3 * s;
    while (k0 < k1 && !(k.pat[std::size_t(k0)] > 0.0f)) ++k0;
    while (k1 > k0 && !(k.pat[std::size_t(k1 - 1)] > 0.0f)) --k1;
    parallel_for(exec, w.height(), [&](long y0, long y1) {
        // Each finer row's sums once (a ring of the 3s rows a cell row
        // takes), then the cell rows from them in order of rows: the same
        // sums in the same order whatever the split into threads.
        std::vector<float> pad(kPlanes * padw, 0.0f);
        std::fill(pad.begin() + kSums * std::ptrdiff_t(padw), pad.end(), kNone);
        const int ring = 3 * s;
        std::vector<float> hrows(std::size_t(ring) * kPlanes * ncell);
        std::vector<int> hrow_of(std::size_t(ring), std::numeric_limits<int>::min());
        std::vector<float> acc(kPlanes * ncell), scratch(4 * (ncell + 2));
        auto hrow = [&](int y) -> const float* {
            const std::size_t slot = std::size_t((y % ring + ring) % ring);
            float* h = hrows.data() + slot * kPlanes * ncell;
            if (hrow_of[slot] == y) return h;
            hrow_of[slot] = y;
            fill(y, xa, xb, pad.data() + (xa - px0), padw);
            for (int q = 0; q < kSums; ++q)
                row_sums(pad.data() + std::size_t(q) * padw, k.pat.data(), s, ncell, h + std::size_t(q) * ncell, scratch.data());
            // The sharpest kept position a cell takes.
            const float* rs = pad.data() + kSums * padw;
            float* hm = h + kSums * ncell;
            row_min(rs, s, k0, k1, ncell, hm, scratch.data());
            for (const Fold& f : folds) {
                const std::size_t o = std::size_t(f.x - px0), X = std::size_t(f.cell - w.x0);
                for (int q = 0; q < kSums; ++q) h[std::size_t(q) * ncell + X] += f.w * pad[std::size_t(q) * padw + o];
                hm[X] = std::min(hm[X], rs[o]);
            }
            return h;
        };
        for (long yl = y0; yl < y1; ++yl) {
            const int Y = w.y0 + int(yl);
            std::fill(acc.begin(), acc.begin() + kSums * std::ptrdiff_t(ncell), 0.0f);
            std::fill(acc.begin() + kSums * std::ptrdiff_t(ncell), acc.end(), kNone);
            float* am = acc.data() + kSums * ncell;
            for (int y = std::max(span.y0, (Y - 2) * s); y < std::min(span.y1, (Y + 3) * s); ++y) {
                int cell[3];
                float wt[3];
                k.taps(y, cell, wt);
                float wy = 0.0f;
                for (int d = 0; d < 3; ++d) wy += std::clamp(cell[d], g.win.y0, g.win.y1 - 1) == Y ? wt[d] : 0.0f;
                if (!(wy > 0.0f)) continue;
                const float* h = hrow(y);
                for (std::size_t i = 0; i < kSums * ncell; ++i) acc[i] += wy * h[i];
                const float* hm = h + kSums * ncell;
                for (std::size_t X = 0; X < ncell; ++X) am[X] = std::min(am[X], hm[X]);
            }
            for (std::size_t X = 0; X < ncell; ++X) {
                const float kw = acc[5 * ncell + X];
                const std::size_t o = g.at(w.x0 + int(X), Y);
                g.area[o] = kw / float(ls * ls);
                g.radius[o] = kw > 0.0f ? std::sqrt(std::max(0.0f, acc[4 * ncell + X] / kw)) : 0.0f;
                g.sharpest[o] = kw > 0.0f ? am[X] : kNone;
                for (int q = 0; q < 4; ++q) g.plane(q)[o] = kw > 0.0f ? acc[std::size_t(q) * ncell + X] / kw : 0.0f;
            }
        }
    });
    return g;
}

// Level j of the work region's planes (the cells `needed`): each cell the
// spline-weighted average of the pixels around it whose radius is at least
// c 2^(j-2), a quarter of the smallest radius the level serves. Sharper
// pixels are left out as the insulators they are at full resolution, so a
// blurred background next to a sharp subject of the same layer takes none of
// the subject's colour; `area` is the weight kept over a whole cell's (0: an
// insulating cell), and `radius` the RMS of the kept radii (diffusivity goes
// with R^2; the smallest radius, tried first, under-blurred cells that
// straddle a change of blur: +5% error on the benchmark's Cornell box).
// Level 1 is built from the pixels; every coarser level from the one below
// (Kernel::finer_cells: the same weights, at a quarter of the cost), taking a
// finer cell only when every pixel it kept is blurred enough for the level
// (`sharpest`), so that no pixel too sharp for a level reaches it. (Taking
// finer cells by their RMS radius let a slightly blurred subject's colour
// out with the background around it.)
Grid build_level(int j, const float* const planes[4], const RadiusMap& radius, const Grid* finer, const Roi& work,
                 const Roi& needed, const Exec& exec) {
    const float keep = float(kLevelRadius * std::ldexp(1.0, j - 2));
    if (!finer) {
        const int W = work.width();
        auto fill = [&](int y, int xa, int xb, float* pad, std::size_t padw) {
            const std::size_t i0 = std::size_t(y - work.y0) * std::size_t(W) + std::size_t(xa - work.x0);
            const float* pl[4] = {planes[0] + i0, planes[1] + i0, planes[2] + i0, planes[3] + i0};
            const float* r = radius.data() + i0;
            float* m = pad + 5 * padw;  // a pixel's weight: 1, or 0 when too sharp for the level
            float* rs = pad + 6 * padw;
            for (int x = 0; x < xb - xa; ++x) {
                const bool kept = r[x] >= keep;
                m[x] = kept ? 1.0f : 0.0f;
                rs[x] = kept ? r[x] : kNone;
            }
            weighted_row(pl, r, xb - xa, pad, padw);
        };
        return build_level(work, fill, Kernel::pixels(j), work, j, needed, exec);
    }
    const Grid& f = *finer;
    const float cell_px = float(std::ldexp(1.0, 2 * (j - 1)));
    auto fill = [&](int y, int xa, int xb, float* pad, std::size_t padw) {
        const std::size_t i0 = f.at(xa, y);
        const float* pl[4] = {f.plane(0) + i0, f.plane(1) + i0, f.plane(2) + i0, f.plane(3) + i0};
        const float *r = f.radius.data() + i0, *area = f.area.data() + i0, *sharpest = f.sharpest.data() + i0;
        // A finer cell's weight: the pixels it kept, or 0 when any of them is
        // too sharp for this level (so none of a sharper subject's colour
        // comes up with the background around it).
        float* m = pad + 5 * padw;
        float* rs = pad + 6 * padw;
        for (int x = 0; x < xb - xa; ++x) {
            const bool kept = sharpest[x] >= keep && area[x] > 0.0f;
            m[x] = kept ? area[x] * cell_px : 0.0f;
            rs[x] = kept ? sharpest[x] : kNone;
        }
        weighted_row(pl, r, xb - xa, pad, padw);
    };
    return build_level(f.built, fill, Kernel::finer_cells(), work, j, needed, exec);
}

// For every level, the cells its pixels' blends use (pixel l uses levels
// floor(l) and, when l is not whole, the next), grown by the reach of a
// level blur (2c) and the B-spline footprint, within the level's window.
std::vector<Roi> needed_cells(const FrameBuffer<float>& lev, const Roi& work, int levels, const Exec& exec) {
    // Per row and level: the span of pixels that use the level.
    const int W = work.width(), H = work.height();
    const std::size_t nl = std::size_t(levels) + 1;
    std::vector<int> lo(std::size_t(H) * nl, W), hi(std::size_t(H) * nl, -1);
    parallel_for(exec, H, [&](long r0, long r1) {
        for (long y = r0; y < r1; ++y) {
            int* l = lo.data() + std::size_t(y) * nl;
            int* h = hi.data() + std::size_t(y) * nl;
            for (int x = 0; x < W; ++x) {
                const float v = lev[std::size_t(y) * std::size_t(W) + std::size_t(x)];
                const int j0 = std::min(int(v), levels);
                l[j0] = std::min(l[j0], x);
                h[j0] = std::max(h[j0], x);
                if (j0 < levels && v > float(j0)) {
                    l[j0 + 1] = std::min(l[j0 + 1], x);
                    h[j0 + 1] = std::max(h[j0 + 1], x);
                }
            }
        }
    }, 16);
    std::vector<Roi> px(nl);  // pixels that use each level
    for (int y = 0; y < H; ++y)
        for (std::size_t j = 0; j < nl; ++j) {
            const std::size_t k = std::size_t(y) * nl + j;
            if (hi[k] >= lo[k]) px[j] = unite(px[j], Roi{work.x0 + lo[k], work.y0 + y, work.x0 + hi[k] + 1, work.y0 + y + 1});
        }
    std::vector<Roi> cells(px.size());
    for (int j = 0; j <= levels; ++j) {
        const Roi& r = px[std::size_t(j)];
        if (r.empty()) continue;
        const int s = 1 << j;
        const Roi level_win = level_window(work, s);
        const Roi c = level_window(r, s);
        cells[std::size_t(j)] = intersect(c.grown(defocus_margin(2.0 * kLevelRadius) + 1), level_win);
    }
    return cells;
}

// Diffuses the cells `box` of a level; `layer_max` is the whole layer's
// largest radius (full-resolution px), which sets the step count.
// The level's radii: min(R / scale, 2c), less the resampling variance on
// coarse levels.
double level_radius(double r_full, int scale) {
    const double r = std::min(r_full / scale, 2.0 * kLevelRadius);
    return scale == 1 ? r : std::sqrt(std::max(0.0, r * r - kResampleR2));
}

// Diffuses four row-major planes over `box` in place (the cells of a level,
// or level 0's pixels), with the radii of `cell_radius` (rows row_stride
// apart). `used` (optional, over box): the pixels whose result is read. The
// explicit stencil moves values one pixel per iteration, so pixels farther
// than the iteration count from every used pixel cannot reach one: they are
// made insulating (radius 0), which the solver skips, and the used pixels
// get the same bits.
Status solve_level_in_place(const ImageView& planes, const float* cell_radius, std::size_t row_stride, int scale,
                            double layer_max, const DiffusionOptions& settings, const Exec& exec,
                            const FrameBuffer<unsigned char>* used = nullptr) {
    const Roi& box = planes.window;
    const int W = box.width();
    RadiusMap radius(box.npixels());  // every element set below
    parallel_for(exec, box.height(), [&](long r0, long r1) {
        for (int y = int(r0); y < int(r1); ++y)
            for (int x = 0; x < W; ++x)
                radius[std::size_t(y) * std::size_t(W) + std::size_t(x)] =
                    float(level_radius(cell_radius[std::size_t(y) * row_stride + std::size_t(x)], scale));
    }, 16);
    DiffusionOptions s = layer_solver_settings(settings, level_radius(layer_max, scale), radius, exec);
    if (used && s.solver == DiffusionSolver::Explicit) {
        const int iterations = explicit_iterations(level_radius(layer_max, scale), settings);
        const FrameBuffer<unsigned char> reach = image_detail::dilate_square(*used, W, box.height(), iterations + 2, exec);
        std::vector<unsigned char> row_cut(std::size_t(box.height()), 0);
        parallel_for(exec, box.height(), [&](long r0, long r1) {
            for (long y = r0; y < r1; ++y)
                for (std::size_t i = std::size_t(y) * std::size_t(W); i < std::size_t(y + 1) * std::size_t(W); ++i)
                    if (!reach[i] && radius[i] > 0.0f) radius[i] = 0.0f, row_cut[std::size_t(y)] = 1;
        }, 16);
        if (std::find(row_cut.begin(), row_cut.end(), 1) != row_cut.end()) s = layer_solver_settings(settings, level_radius(layer_max, scale), radius, exec);
    }
    // Coarse levels link cells by the harmonic mean of their diffusivities
    // (conductance.h): a cell step spans `scale` pixels of a change of blur,
    // where min() took the blur a whole cell away.
    return diffusion_detail::diffuse_planes(planes, ConstImageView::planar(radius.data(), 1, box), s, exec,
                                            scale > 1 ? diffusion_detail::Conductance::Harmonic
                                                      : diffusion_detail::Conductance::Min);
}

// The four planes' rows of `box` (row stride `row_stride` from planes[c])
// into `out`, packed: four planes over box.
void copy_box(const float* const planes[4], const Roi& box, std::size_t row_stride, const Exec& exec,
              FrameBuffer<float>& out) {
    const std::size_t n = box.npixels();
    const std::size_t W = std::size_t(box.width());
    out.resize(4 * n);  // every element copied below
    parallel_for(exec, box.height(), [&](long r0, long r1) {
        for (long y = r0; y < r1; ++y)
            for (int c = 0; c < 4; ++c)
                std::copy_n(planes[c] + std::size_t(y) * row_stride, W, out.data() + std::size_t(c) * n + std::size_t(y) * W);
    }, 16);
}

// The same on a copy of the box's planes, in `out` (4 planes over box).
Status solve_level(const float* const planes[4], const float* cell_radius, const Roi& box, std::size_t row_stride,
                   int scale, double layer_max, const DiffusionOptions& settings, const Exec& exec,
                   FrameBuffer<float>& out) {
    copy_box(planes, box, row_stride, exec, out);
    return solve_level_in_place(ImageView::planar(out.data(), 4, box), cell_radius, row_stride, scale, layer_max, settings, exec);
}

// Cubic B-spline weights of the four cells around a fractional position t
// in [0, 1) after the second of them: positive, a partition of unity, and
// exactly conservative on an integer refinement (variance 1/3 cell^2).
void bspline_weights(double t, double w[4]) {
    const double t2 = t * t, t3 = t2 * t;
    w[0] = (1 - t) * (1 - t) * (1 - t) / 6.0;
    w[1] = (3 * t3 - 6 * t2 + 4) / 6.0;
    w[2] = (-3 * t3 + 3 * t2 + 3 * t + 1) / 6.0;
    w[3] = t3 / 6.0;
}

// Index i of a level window [lo, hi) mirrored at its edges (the insulated
// boundary), then clamped to the solved box [blo, bhi).
int tap(int i, int lo, int hi, int blo, int bhi) {
    if (i < lo) i = 2 * lo - i - 1;
    if (i >= hi) i = 2 * hi - i - 1;
    return std::clamp(i, blo, bhi - 1);
}

// The four cells a pixel's cubic B-spline return reads along one axis
// (indices relative to the solved box) and their weights.
struct Taps {
    int at[4];
    float w[4];
};

// Taps of every pixel p in [p0, p1) of one axis for a level of `scale`
// pixels per cell, window [lo, hi) and solved box [blo, bhi) (cells).
std::vector<Taps> axis_taps(int p0, int p1, int scale, int lo, int hi, int blo, int bhi) {
    std::vector<Taps> out(static_cast<std::size_t>(std::max(0, p1 - p0)));
    for (int p = p0; p < p1; ++p) {
        const double v = (p + 0.5) / scale - 0.5;
        const int c0 = int(std::floor(v));
        double w[4];
        bspline_weights(v - c0, w);
        Taps& t = out[std::size_t(p - p0)];
        for (int k = 0; k < 4; ++k) {
            t.at[k] = tap(c0 - 1 + k, lo, hi, blo, bhi) - blo;
            t.w[k] = float(w[k]);
        }
    }
    return out;
}

// A returned row holds, per cell, the 4 colour planes times area, then the
// area, side by side (kReturnStride floats per cell, padded with 0, so that a
// pixel's taps are whole short vectors).
constexpr std::size_t kReturnStride = 8;

// The vertical sums of one work row over a level's solved box (BW cells
// wide, n cells, 4 planes of `sol`, the kept `area`): per cell the four taps'
// colour times area, and the area, into row[kReturnStride X + c] (c = 4: the
// area; 5-7 padding, 0). Summed plane by plane along the row (loops the compiler
// vectorises, into `scratch`), each element in the same order as a cell at
// a time, then interleaved.
GDOF_CLONES
void vertical_sums(const Taps& t, const float* sol, const float* area, std::size_t BW, std::size_t n,
                   std::vector<float>& row, std::vector<float>& scratch) {
    scratch.resize(6 * BW);
    std::fill_n(scratch.data(), 5 * BW, 0.0f);
    float* wa = scratch.data() + 5 * BW;  // this tap's weight times area, per cell (plane 4: their sum)
    for (int k = 0; k < 4; ++k) {
        const std::size_t r = std::size_t(t.at[k]) * BW;
        const float w = t.w[k];
        const float* a = area + r;
        for (std::size_t X = 0; X < BW; ++X) wa[X] = w * a[X];
        for (int c = 0; c < 4; ++c) {
            float* o = scratch.data() + std::size_t(c) * BW;
            const float* v = sol + std::size_t(c) * n + r;
            for (std::size_t X = 0; X < BW; ++X) o[X] += wa[X] * v[X];
        }
        float* o = scratch.data() + 4 * BW;
        for (std::size_t X = 0; X < BW; ++X) o[X] += wa[X];
    }
    row.resize(kReturnStride * BW);
    for (std::size_t X = 0; X < BW; ++X) {
        float* o = row.data() + kReturnStride * X;
        for (std::size_t c = 0; c < kReturnStride; ++c) o[c] = c < 5 ? scratch[c * BW + X] : 0.0f;
    }
}

// One level brought back to full resolution, row by row: cubic B-spline
// weighted by each cell's kept area (normalised), so that insulating cells
// do not darken the blurred pixels beside them. The taps depend only on a
// pixel's column or row, so they are computed once.
struct LevelReturn {
    const FrameBuffer<float>* sol = nullptr;  // 4 planes over box
    Roi box;
    std::vector<Taps> cols, rows;   // per pixel column / row of the work region
    FrameBuffer<float> area;        // kept area over box (every element copied)
    LevelReturn() = default;
    LevelReturn(const FrameBuffer<float>& s, const Roi& b, const Grid& level, int scale, const Roi& work)
        : sol(&s), box(b) {
        if (b.empty()) return;
        cols = axis_taps(work.x0, work.x1, scale, level.win.x0, level.win.x1, b.x0, b.x1);
        rows = axis_taps(work.y0, work.y1, scale, level.win.y0, level.win.y1, b.y0, b.y1);
        area.resize(b.npixels());
        for (int Y = b.y0; Y < b.y1; ++Y)
            std::copy_n(level.area.data() + level.at(b.x0, Y), b.width(),
                        area.data() + std::size_t(Y - b.y0) * std::size_t(b.width()));
    }
    // Sums over the box's columns for work row yl (vertical_sums).
    void vertical(int yl, std::vector<float>& row, std::vector<float>& scratch) const {
        vertical_sums(rows[std::size_t(yl)], sol->data(), area.data(), std::size_t(box.width()), box.npixels(), row,
                      scratch);
    }
    // The level's value at work column xl of that row, times wgt, added to acc.
    // The sums are one 8-float vector (4 colours times area, the area,
    // padding): each lane the same operations in the same order as a scalar
    // loop, so the same bits, in one AVX2 instruction or two SSE ones.
    void horizontal(const std::vector<float>& row, int xl, float wgt, float acc[4]) const {
        typedef float Vec8 __attribute__((vector_size(32)));
        const Taps& t = cols[std::size_t(xl)];
        Vec8 sum = {0, 0, 0, 0, 0, 0, 0, 0};
        for (int k = 0; k < 4; ++k) {
            Vec8 v;
            std::memcpy(&v, row.data() + kReturnStride * std::size_t(t.at[k]), sizeof v);
            sum += t.w[k] * v;
        }
        const float den = sum[4];
        if (!(den > 0.0f)) return;
        const float f = wgt / den;
        for (int c = 0; c < 4; ++c) acc[c] += f * sum[c];
    }
};

// One work row returned: per pixel the two levels around its own (`lrow`),
// blended linearly in log2(R); level 0 from s0 (at x + dx0), the others from
// their vertical sums `rows`. Compiled for AVX2 too (the taps' 8-float sums).
GDOF_CLONES
void return_row(const float* lrow, int W, int levels, const LevelReturn* ret, const std::vector<float>* rows,
                const float* const s0[4], std::ptrdiff_t dx0, float* const out[4]) {
    for (int x = 0; x < W; ++x) {
        const float l = lrow[x];
        const int j0 = std::min(int(l), levels);
        const float f = l - float(j0);
        float a4[4] = {0, 0, 0, 0};
        for (int k = 0; k < 2; ++k) {
            const int j = j0 + k;
            const float w = k == 0 ? 1.0f - f : f;
            if (!(w > 0.0f) || j > levels) continue;
            if (j == 0) {
                for (int c = 0; c < 4; ++c) a4[c] += w * s0[c][std::ptrdiff_t(x) + dx0];
            } else {
                ret[j].horizontal(rows[j], x, w, a4);
            }
        }
        for (int c = 0; c < 4; ++c) out[c][x] = a4[c];
    }
}

// Number of coarse levels of a layer (0: solved at full resolution only).
// A layer that needs coarse levels at all (its largest blur above 2c) takes
// their count from the frame's largest radius: a pixel of radius R blends
// the two levels around log2(R / c), or takes the top level alone beyond
// the count. With a count from each layer's own largest radius, the same R
// blended two levels in one layer and took one alone in another whose
// largest blur was a little smaller (the Cornell box's lamp glowed
// differently depending on the layer it fell in). Layers within 2c stay at
// full resolution: putting them on the pyramid too cost 0.1 s on the 4K
// frame and measured no better.
int pyramid_levels(double layer_max_radius, double frame_radius, const Roi& layer_region) {
    if (!(layer_max_radius > 2.0 * kLevelRadius)) return 0;
    const double count_radius = std::max(layer_max_radius, frame_radius);
    int levels = std::min(kMaxLevels, int(std::ceil(std::log2(count_radius / (2.0 * kLevelRadius)))));
    // A level keeps at least kMinCells cells across the layer's region: a
    // blur that wide is a near-constant over so small a region anyway.
    const int side = std::min(layer_region.width(), layer_region.height());
    while (levels > 0 && (side >> levels) < kMinCells) --levels;
    return levels;
}

}  // namespace

Status diffuse_pyramid(const ImageView& planes, const RadiusMap& radius, double layer_max_radius,
                       double frame_radius, const Roi& layer_region, const DiffusionOptions& settings,
                       const Exec& exec, PyramidSolve& how) {
    const Roi work = planes.window;
    const int levels = settings.pyramid ? pyramid_levels(layer_max_radius, frame_radius, layer_region) : 0;
    how.on_pyramid = levels > 0;
    if (levels == 0) {
        const DiffusionOptions s = layer_solver_settings(settings, layer_max_radius, radius, exec);
        how.solver = s.solver;
        return diffuse_planes(planes, ConstImageView::planar(radius.data(), 1, work), s, exec);
    }
    // Every level's radii are at most 2c: the solver `auto` picks for that.
    how.solver = choose_solver(2.0 * kLevelRadius, settings);
    const int W = work.width(), H = work.height();
    const std::size_t n = work.npixels();
    FrameBuffer<float> lev(n);  // every element set below
    parallel_for(exec, H, [&](long r0, long r1) {
        for (std::size_t i = std::size_t(r0) * std::size_t(W); i < std::size_t(r1) * std::size_t(W); ++i)
            lev[i] = level_of(radius[i], levels);
    }, 16);
    const std::vector<Roi> box = needed_cells(lev, work, levels, exec);
    // The cells each level is built over: its own, and the ones the next
    // level is built from.
    std::vector<Roi> req(box);
    for (int j = levels - 1; j >= 1; --j) {
        const Roi& c = req[std::size_t(j) + 1];
        if (c.empty()) continue;
        const Roi finer{2 * c.x0 - 1, 2 * c.y0 - 1, 2 * c.x1 + 1, 2 * c.y1 + 1};  // Kernel::finer_cells' reach
        req[std::size_t(j)] = unite(req[std::size_t(j)], intersect(finer, level_window(work, 1 << j)));
    }

    // Every coarse level built from the layer's planes first, then solved
    // over its box (in place when the box is the whole level); then level 0
    // (the pixels themselves), in place on the planes when it needs the whole
    // work region: its values are read back pixel by pixel, before the
    // blend writes each one.
    std::array<const float*, 4> src{};
    for (int c = 0; c < 4; ++c) src[std::size_t(c)] = planes.plane(c);
    std::vector<Grid> grid;
    grid.reserve(std::size_t(levels) + 1);  // a level is built from the one before it, in place
    grid.emplace_back(Roi{});  // level 0's kept area is never read
    for (int j = 1; j <= levels; ++j) {
        if (exec.is_cancelled()) return Status::cancelled("diffusion");
        grid.push_back(build_level(j, src.data(), radius, j == 1 ? nullptr : &grid.back(), work, req[std::size_t(j)], exec));
    }
    std::vector<FrameBuffer<float>> sol(std::size_t(levels) + 1);
    for (int j = 1; j <= levels; ++j) {
        if (exec.is_cancelled()) return Status::cancelled("diffusion");
        Grid& g = grid[std::size_t(j)];
        const Roi& b = box[std::size_t(j)];
        if (!b.empty()) {
            Status st;
            if (b == g.win) {
                st = solve_level_in_place(ImageView::planar(g.rgba.data(), 4, b), g.radius.data(), std::size_t(b.width()),
                                          1 << j, layer_max_radius, settings, exec);
                sol[std::size_t(j)] = std::move(g.rgba);
            } else {
                const std::size_t off = g.at(b.x0, b.y0);
                const float* p[4];
                for (int c = 0; c < 4; ++c) p[c] = g.plane(c) + off;
                st = solve_level(p, g.radius.data() + off, b, std::size_t(g.win.width()), 1 << j, layer_max_radius, settings,
                                 exec, sol[std::size_t(j)]);
            }
            if (!st) return st;
        }
        g.rgba = {};  // only the kept area is read from here on
        g.radius = {};
    }
    const Roi& box0 = box[0];
    const bool level0_in_place = box0 == work;
    if (!box0.empty()) {
        if (exec.is_cancelled()) return Status::cancelled("diffusion");
        // The pixels that blend level 0, over its box.
        FrameBuffer<unsigned char> used(box0.npixels());  // every element set below
        parallel_for(exec, box0.height(), [&](long r0, long r1) {
            for (int y = box0.y0 + int(r0); y < box0.y0 + int(r1); ++y) {
                // Locals: a byte store may alias anything reached through a reference.
                unsigned char* u = used.data() + std::size_t(y - box0.y0) * std::size_t(box0.width());
                const float* l = lev.data() + std::size_t(y - work.y0) * std::size_t(W) + std::size_t(box0.x0 - work.x0);
                const int cols = box0.width();
                for (int x = 0; x < cols; ++x) u[x] = l[x] < 1.0f;
            }
        }, 16);
        const std::size_t off = std::size_t(box0.y0 - work.y0) * std::size_t(W) + std::size_t(box0.x0 - work.x0);
        Status st;
        if (level0_in_place) {
            st = solve_level_in_place(planes, radius.data(), std::size_t(W), 1, layer_max_radius, settings, exec, &used);
        } else {
            FrameBuffer<float>& out = sol[0];
            const float* p[4];
            for (int c = 0; c < 4; ++c) p[c] = src[std::size_t(c)] + off;
            copy_box(p, box0, std::size_t(W), exec, out);
            st = solve_level_in_place(ImageView::planar(out.data(), 4, box0), radius.data() + off, std::size_t(W), 1,
                                      layer_max_radius, settings, exec, &used);
        }
        if (!st) return st;
    }

    // Per pixel: the two levels around its own, blended linearly in log2(R).
    std::vector<LevelReturn> ret(std::size_t(levels) + 1);
    for (int j = 1; j <= levels; ++j)
        ret[std::size_t(j)] = LevelReturn(sol[std::size_t(j)], box[std::size_t(j)], grid[std::size_t(j)], 1 << j, work);
    const std::size_t n0 = box0.npixels();
    const bool ok = parallel_for(exec, H, [&](long y0, long y1) {
        std::vector<std::vector<float>> rows(std::size_t(levels) + 1);
        std::vector<float> scratch;
        std::vector<char> used(std::size_t(levels) + 1);
        for (long yl = y0; yl < y1; ++yl) {
            const int y = work.y0 + int(yl);
            const float* lrow = lev.data() + std::size_t(yl) * std::size_t(W);
            std::fill(used.begin(), used.end(), 0);
            for (int x = 0; x < W; ++x) {
                const int j0 = std::min(int(lrow[x]), levels);
                used[std::size_t(j0)] = 1;
                if (j0 < levels && lrow[x] > float(j0)) used[std::size_t(j0) + 1] = 1;
            }
            for (int j = 1; j <= levels; ++j)
                if (used[std::size_t(j)]) ret[std::size_t(j)].vertical(int(yl), rows[std::size_t(j)], scratch);
            // Level 0 of this row, plane c (read at x before x is written).
            // s0[c] is the row's start; x + dx0 indexes it (dx0 < 0 where the
            // level-0 box starts right of the work: those x never read it).
            const float* s0[4] = {nullptr, nullptr, nullptr, nullptr};
            const std::ptrdiff_t dx0 = level0_in_place ? 0 : std::ptrdiff_t(work.x0) - std::ptrdiff_t(box0.x0);
            for (int c = 0; used[0] && c < 4; ++c)
                s0[c] = level0_in_place ? planes.plane(c) + std::size_t(yl) * std::size_t(W)
                                        : sol[0].data() + std::size_t(c) * n0 +
                                              std::size_t(y - box0.y0) * std::size_t(box0.width());
            float* const out[4] = {planes.plane(0) + std::size_t(yl) * std::size_t(W),
                                   planes.plane(1) + std::size_t(yl) * std::size_t(W),
                                   planes.plane(2) + std::size_t(yl) * std::size_t(W),
                                   planes.plane(3) + std::size_t(yl) * std::size_t(W)};
            return_row(lrow, W, levels, ret.data(), rows.data(), s0, dx0, out);
        }
    });
    return ok ? Status::ok() : Status::cancelled("diffusion");
}

}  // namespace gdof::defocus_detail
