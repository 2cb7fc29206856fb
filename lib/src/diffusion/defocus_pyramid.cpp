// A layer's large blurs solved at reduced resolution (docs/diffusion.md,
// "pyramid"). A blur of radius R at full resolution is a blur of R / 2^j on
// the image averaged over 2^j x 2^j cells, so every pixel is solved on the
// level where its radius is kLevelRadius .. 2 kLevelRadius cells, and the
// result is blended per pixel between the two levels around log2(R / c).
// Every level's radii are capped at 2c, so each level costs about as much as
// a full-resolution blur of 2c px over a quarter of the pixels of the level
// before it: the cost no longer grows with the largest blur.
//
// - Variance: averaging over cells (a box of 2^j) and the cubic B-spline
//   return add 5/12 cell^2 of variance, 5/3 cell^2 of R^2 (sigma = R / 2);
//   level radii are reduced by it, so a constant blur keeps its width.
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
#include <vector>

#include "common/simd_clones.h"
#include "diffusion/defocus_internal.h"
#include "image/mask_dilate.h"

namespace gdof::defocus_detail {

namespace {

constexpr double kLevelRadius = 3.0;  // c: level j solves R / 2^j in [c, 2c)
constexpr int kMaxLevels = 16;
constexpr int kMinCells = 16;
// Variance the round trip adds, in cell^2: the 2^j box of the averaging
// (about 1/12) and the cubic B-spline of the return (1/3); as R^2 = 4 sigma^2.
constexpr double kResampleR2 = 4.0 * (1.0 / 12.0 + 1.0 / 3.0);

int floor_div(int a, int s) { return a >= 0 ? a / s : -((-a + s - 1) / s); }
int ceil_div(int a, int s) { return -floor_div(-a, s); }

// Four planes and a radius map over a window of cells (absolute cell
// coordinates of the level), row-major. Only the cells build_level()
// computes are set: the ones solved and read back.
struct Grid {
    Roi win;
    FrameBuffer<float> rgba;    // 4 planes
    FrameBuffer<float> radius;  // RMS full-resolution radius of the cell's kept pixels
    FrameBuffer<float> area;    // pixels of the work region inside the cell
    explicit Grid(Roi w) : win(w), rgba(4 * w.npixels()), radius(w.npixels()), area(w.npixels()) {}
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

// Level j of the work region's planes: each cell the average of its pixels
// whose radius is at least c 2^(j-2), a quarter of the smallest radius the
// level serves. Sharper pixels are left out as the insulators they are at
// full resolution, so a blurred background next to a sharp subject of the
// same layer takes none of the subject's colour; `area` is the fraction of
// the cell that was kept (0: an insulating cell), and `radius` the RMS of
// the kept radii (diffusivity goes with R^2; the smallest radius, tried
// first, under-blurred cells that straddle a change of blur: +5% error on
// the benchmark's Cornell box).
// Only the cells of `needed` (the ones solved and read back) are computed.
Grid build_level(const float* const planes[4], const RadiusMap& radius, const Roi& work, int j,
                 const Roi& needed, const Exec& exec) {
    const int s = 1 << j;
    Grid g(Roi{floor_div(work.x0, s), floor_div(work.y0, s), ceil_div(work.x1, s), ceil_div(work.y1, s)});
    const float keep = float(kLevelRadius * std::ldexp(1.0, j - 2));
    const Roi w = intersect(g.win, needed);  // only the cells that are solved
    const int W = work.width();
    parallel_for(exec, w.height(), [&](long y0, long y1) {
        // A row of cells at a time, its pixel rows streamed in order: each
        // cell's sums take its pixels row by row, left to right, as a cell at
        // a time would.
        const std::size_t ncell = std::size_t(w.width());
        std::vector<double> sums(5 * ncell);  // per cell: 4 colours, then R^2
        std::vector<int> kept(ncell);         // per cell: the pixels kept
        const float* rad = radius.data();
        const float* pl[4] = {planes[0], planes[1], planes[2], planes[3]};
        for (long yl = y0; yl < y1; ++yl) {
            const int Y = w.y0 + int(yl);
            const int ya = std::max(work.y0, Y * s), yb = std::min(work.y1, (Y + 1) * s);
            std::fill(sums.begin(), sums.end(), 0.0);
            std::fill(kept.begin(), kept.end(), 0);
            for (int y = ya; y < yb; ++y) {
                const std::size_t row = std::size_t(y - work.y0) * std::size_t(W);
                for (int X = w.x0; X < w.x1; ++X) {
                    const int xa = std::max(work.x0, X * s), xb = std::min(work.x1, (X + 1) * s);
                    double* c = sums.data() + 5 * std::size_t(X - w.x0);
                    int k_cell = 0;
                    for (int x = xa; x < xb; ++x) {
                        const std::size_t i = row + std::size_t(x - work.x0);
                        if (!(rad[i] >= keep)) continue;
                        ++k_cell;
                        for (int k = 0; k < 4; ++k) c[k] += double(pl[k][i]);
                        c[4] += double(rad[i]) * double(rad[i]);
                    }
                    kept[std::size_t(X - w.x0)] += k_cell;
                }
            }
            for (int X = w.x0; X < w.x1; ++X) {
                const double* c = sums.data() + 5 * std::size_t(X - w.x0);
                const int kc = kept[std::size_t(X - w.x0)];
                const std::size_t o = g.at(X, Y);
                g.area[o] = float(kc) / float(s * s);
                g.radius[o] = kc ? float(std::sqrt(c[4] / kc)) : 0.0f;
                for (int k = 0; k < 4; ++k) g.plane(k)[o] = kc ? float(c[k] / kc) : 0.0f;
            }
        }
    });
    return g;
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
        const Roi level_win{floor_div(work.x0, s), floor_div(work.y0, s), ceil_div(work.x1, s), ceil_div(work.y1, s)};
        const Roi c{floor_div(r.x0, s), floor_div(r.y0, s), ceil_div(r.x1, s), ceil_div(r.y1, s)};
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
    return diffuse_planes(planes, ConstImageView::planar(radius.data(), 1, box), s, exec);
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

// Number of coarse levels for a layer's largest radius and its whole region
// (0: the layer is solved at full resolution only).
int pyramid_levels(double layer_max_radius, const Roi& layer_region) {
    if (!(layer_max_radius > 2.0 * kLevelRadius)) return 0;
    int levels = std::min(kMaxLevels, int(std::ceil(std::log2(layer_max_radius / (2.0 * kLevelRadius)))));
    // A level keeps at least kMinCells cells across the layer's region: a
    // blur that wide is a near-constant over so small a region anyway.
    const int side = std::min(layer_region.width(), layer_region.height());
    while (levels > 0 && (side >> levels) < kMinCells) --levels;
    return levels;
}

}  // namespace

Status diffuse_pyramid(const ImageView& planes, const RadiusMap& radius, double layer_max_radius,
                       const Roi& layer_region, const DiffusionOptions& settings, const Exec& exec,
                       PyramidSolve& how) {
    const Roi work = planes.window;
    const int levels = settings.pyramid ? pyramid_levels(layer_max_radius, layer_region) : 0;
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

    // Every coarse level built from the layer's planes first, then solved
    // over its box (in place when the box is the whole level); then level 0
    // (the pixels themselves), in place on the planes when it needs the whole
    // work region: its values are read back pixel by pixel, before the
    // blend writes each one.
    std::array<const float*, 4> src{};
    for (int c = 0; c < 4; ++c) src[std::size_t(c)] = planes.plane(c);
    std::vector<Grid> grid;
    grid.emplace_back(Roi{});  // level 0's kept area is never read
    for (int j = 1; j <= levels; ++j) {
        if (exec.is_cancelled()) return Status::cancelled("diffusion");
        grid.push_back(build_level(src.data(), radius, work, j, box[std::size_t(j)], exec));
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
