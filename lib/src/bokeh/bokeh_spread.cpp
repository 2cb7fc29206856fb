// spread_planes: every pixel scattered over its aperture, level by level of
// the radius pyramid (bokeh.h), then the levels upsampled into the finest and
// the whole normalised by the spread weight. Sources are taken in bands of
// rows, even bands then odd ones, so concurrent bands never write the same
// row and the sums do not depend on the thread count.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "bokeh/bokeh_internal.h"
#include "common/format_number.h"

namespace gdof {

namespace {

using bokeh_detail::level_of;
using Prepared = BokehFilter::Prepared;

// One pyramid level: the sources spread there and what they write.
struct Level {
    int k = 0, w = 0, h = 0;  // grid 2^k coarser than the planes
    int nc = 0;               // channels incl. the weight (last)
    // Sources (k >= 1; level 0 reads the planes): per coarse cell the summed
    // channels (weight = pixel count), and the block's centre and radius
    // weighted by each pixel's brightness (1 + the sum of its channels), so a
    // highlight in a block stays where it was: offsets inside the block
    // (full-resolution pixels) and radii, summed with those weights.
    std::vector<float> value;  // [c][cell]
    std::vector<float> weight, off_x, off_y, radius_sum;
    float max_radius = 0.0f;   // largest source radius (full-resolution pixels)
    // Accumulator: [c][row][w + 1] (the extra column takes span ends).
    std::vector<float> acc;
    std::size_t stride() const { return std::size_t(w) + 1; }
    float* row(int c, int y) { return acc.data() + (std::size_t(c) * std::size_t(h) + std::size_t(y)) * stride(); }
};

// A source on its level's grid: centre (edge coordinates: cell i is [i, i+1)),
// radius in that grid's pixels, channel values.
struct Source {
    double cx, cy, r;
    float val[8];
    double ou = 0.0, ov = 0.0;  // cat's eye: the second disc's centre in (u, v)
    bool cats_eye = false;
};

constexpr int kMaxChannels = 8;

// Row y of a span [a, b) into difference rows (coverage anti-aliased at both ends).
inline void add_span(Level& L, int y, const float* val, double a, double b) {
    a = std::max(a, 0.0);
    b = std::min(b, double(L.w));
    if (!(b > a)) return;
    const int ia = int(a), ib = std::min(int(b), L.w - 1);
    if (ia >= ib) {
        const float len = float(b - a);
        for (int c = 0; c < L.nc; ++c) {
            float* d = L.row(c, y);
            d[ia] += val[c] * len;
            d[ia + 1] -= val[c] * len;
        }
        return;
    }
    const float ca = float(double(ia + 1) - a), cb = float(b - double(ib));
    for (int c = 0; c < L.nc; ++c) {
        float* d = L.row(c, y);
        const float v = val[c];
        d[ia] += v * ca;
        d[ia + 1] += v * (1.0f - ca);
        d[ib] += v * (cb - 1.0f);
        d[ib + 1] -= v * cb;
    }
}

struct RowSpan {
    int y;
    double height, a, b;  // height: the part of the row's height covered
};

// The shape's edges over the strip v in [v0, v1] for a cat's-eye source:
// the profile's row cut by the displaced disc, sampled at four heights. The
// cut shape is moved back by half the displacement (the middle of the two
// discs), so its centre stays on its source: neighbours' shapes then overlap
// evenly and the spread weight stays close to 1 (no drift of light
// outward, which the normalisation would turn into a brightness error).
bool cats_eye_strip(const ApertureProfile& prof, const Source& s, double v0, double v1, double& height, double& left,
                    double& right) {
    const double su = 0.5 * s.ou, sv = 0.5 * s.ov;
    v0 += sv;
    v1 += sv;
    const double lo = std::max({v0, -1.0, s.ov - 1.0}), hi = std::min({v1, 1.0, s.ov + 1.0});
    if (!(hi > lo)) return false;
    constexpr int M = 4;
    double sl = 0, sr = 0;
    int n = 0;
    for (int m = 0; m < M; ++m) {
        const double v = lo + (m + 0.5) / M * (hi - lo);
        double l, r;
        if (!prof.row(v, l, r)) continue;
        const double dv = v - s.ov, half = std::sqrt(std::max(0.0, 1.0 - dv * dv));
        l = std::max(l, s.ou - half);
        r = std::min(r, s.ou + half);
        if (!(r > l)) continue;
        sl += l;
        sr += r;
        ++n;
    }
    if (n == 0) return false;
    height = (hi - lo) * n / M;
    left = sl / n - su;
    right = sr / n - su;
    return true;
}

// The rows of one shape, relative to its source's cell, kept while the next
// sources have the same radius and sub-pixel position (a constant or slowly
// varying blur: most neighbours), so the profile is looked up once per shape.
struct ShapeRows {
    bool valid = false;
    double r = 0, fx = 0, fy = 0, area = 0;
    std::vector<RowSpan> rows;  // y relative to floor(cy), a / b relative to floor(cx)
};

// Radii are quantised to 1/64 px for the shape (invisible, and neighbours
// share their rows).
constexpr double kRadiusStep = 1.0 / 64.0;

void shape_rows(const Prepared& P, const Source& s, double r, double fx, double fy, ShapeRows& out) {
    const ApertureProfile& prof = *P.profile;
    out.rows.clear();
    out.area = 0.0;
    out.r = r, out.fx = fx, out.fy = fy;
    out.valid = !s.cats_eye;
    const int y0 = int(std::floor(fy - r)), y1 = int(std::floor(fy + r));
    for (int y = y0; y <= y1; ++y) {
        // Row y covers [y, y + 1): v = (cy - y') / r, v up.
        const double v0 = (fy - y - 1.0) / r, v1 = (fy - y) / r;
        double height, left, right;
        const bool hit = s.cats_eye ? cats_eye_strip(prof, s, v0, v1, height, left, right)
                                    : prof.strip(v0, v1, height, left, right);
        if (!hit) continue;
        const double h = height * r;  // of the row's unit height
        const RowSpan rs{y, h, fx + r * left, fx + r * right};
        out.area += h * (rs.b - rs.a);
        out.rows.push_back(rs);
    }
}

// Source s's shape, `shape` (relative to its cell), into L's difference rows.
void scatter_rows(Level& L, const Source& s, const ShapeRows& shape) {
    if (!(shape.area > 0.0)) return;
    const double xb = std::floor(s.cx), yb = std::floor(s.cy);
    float val[kMaxChannels];
    const int yi = int(yb);
    for (const RowSpan& rs : shape.rows) {
        const int y = yi + rs.y;
        if (y < 0 || y >= L.h) continue;
        const double f = rs.height / shape.area;
        for (int c = 0; c < L.nc; ++c) val[c] = float(double(s.val[c]) * f);
        add_span(L, y, val, xb + rs.a, xb + rs.b);
    }
}

// A point (radius ~ 0): all of it into its own cell.
bool scatter_point(Level& L, const Source& s, double r) {
    if (r > 1e-4) return false;
    const int x = std::clamp(int(std::floor(s.cx)), 0, L.w - 1), y = std::clamp(int(std::floor(s.cy)), 0, L.h - 1);
    add_span(L, y, s.val, double(x), double(x) + 1.0);
    return true;
}

void scatter_spans(Level& L, const Prepared& P, const Source& s, ShapeRows& memo) {
    const double r = std::round(s.r / kRadiusStep) * kRadiusStep;
    if (scatter_point(L, s, r)) return;
    const double fx = s.cx - std::floor(s.cx), fy = s.cy - std::floor(s.cy);
    if (s.cats_eye || !memo.valid || memo.r != r || memo.fx != fx || memo.fy != fy) shape_rows(P, s, r, fx, fy, memo);
    scatter_rows(L, s, memo);
}

// Level 0's sources sit at pixel centres (sub-pixel position 0.5, 0.5):
// their shapes depend only on the quantised radius, so they are made once
// for every radius up to the level's largest, shared by all bands.
std::vector<ShapeRows> centred_shapes(const Prepared& P, double max_radius, const Exec& exec) {
    const int q_max = int(std::ceil(max_radius / kRadiusStep)) + 1;
    std::vector<ShapeRows> shapes(static_cast<std::size_t>(q_max) + 1);
    parallel_for(exec, long(shapes.size()), [&](long b, long e) {
        const Source s{};
        for (long q = b; q < e; ++q) shape_rows(P, s, double(q) * kRadiusStep, 0.5, 0.5, shapes[std::size_t(q)]);
    }, 16);
    return shapes;
}

void scatter_kernel(Level& L, const Prepared& P, const Source& s, int colour_channels) {
    const int q = std::clamp(int(std::lround(s.r * Prepared::kKernelSteps)), 0, int(P.kernels.size()) - 1);
    const ApertureKernel& K = P.kernels[std::size_t(q)];
    const int n = 2 * K.half + 1;
    const int xc = int(std::floor(s.cx)), yc = int(std::floor(s.cy));
    const int dx0 = std::max(-K.half, -xc), dx1 = std::min(K.half, L.w - 1 - xc);
    if (dx1 < dx0) return;
    for (int dy = -K.half; dy <= K.half; ++dy) {
        const int y = yc + dy;
        if (y < 0 || y >= L.h) continue;
        for (int c = 0; c < L.nc; ++c) {
            const int kc = c < colour_channels ? c : K.channels - 1;
            const float* kr = K.plane(kc) + std::size_t(dy + K.half) * std::size_t(n) + std::size_t(K.half);
            float* d = L.row(c, y) + xc;
            const float v = s.val[c];
            if (v == 0.0f) continue;
            for (int dx = dx0; dx <= dx1; ++dx) d[dx] += v * kr[dx];
        }
    }
}

void set_cats_eye(const CatsEyeVignette& vignette, double full_x, double full_y, Source& s) {
    const CatsEyeCut cut = vignette.at(full_x, full_y);
    if (!(cut.d > 0.0)) return;
    s.cats_eye = true;
    s.ou = cut.d * cut.ex;
    s.ov = cut.d * cut.ey;
}

}  // namespace

Status spread_planes(const ImageView& planes, const ConstImageView& radius, const BokehFilter& filter, const Roi& frame_in,
                     const Exec& exec) {
    const Roi win = planes.window;
    if (radius.nchannels < 1 || !(radius.window == win))
        return Status::error("bokeh: the radius map (" + std::to_string(radius.nchannels) + " channel(s) over " +
                                 to_string(radius.window) + ") does not match the planes (" + to_string(win) + ")",
                             StatusCode::InvalidArgument);
    if (planes.nchannels < 1 || planes.nchannels >= kMaxChannels)
        return Status::error("bokeh: expected 1 to " + std::to_string(kMaxChannels - 1) + " planes, got " +
                                 std::to_string(planes.nchannels),
                             StatusCode::InvalidArgument);
    if (win.empty()) return Status::ok();
    const Prepared& P = filter.prepared();
    const int W = win.width(), H = win.height();
    const std::size_t npix = win.npixels();
    const int nch = planes.nchannels, nc = nch + 1;
    const int colour_channels = P.aperture.colour() ? std::min(3, nch) : 0;
    const int T = P.level_radius;

    // Radii and their levels.
    std::vector<float> R(npix);
    std::vector<unsigned char> lvl(npix);
    int top = 0;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const float r = radius.at(0, win.x0 + x, win.y0 + y);
            if (!std::isfinite(r) || r < 0.0f)
                return Status::error("bokeh: radius " + format_number(r, 6) + " at pixel (" + std::to_string(win.x0 + x) +
                                         ", " + std::to_string(win.y0 + y) + "); expected finite and >= 0",
                                     StatusCode::InvalidArgument);
            const std::size_t i = std::size_t(y) * std::size_t(W) + std::size_t(x);
            R[i] = r;
            lvl[i] = (unsigned char)std::min(level_of(r, T), 30);
            top = std::max(top, int(lvl[i]));
        }
    const Roi fr = frame_in.empty() ? win : frame_in;
    const CatsEyeVignette vignette(P.aperture.cats_eye, fr);

    std::vector<Level> levels(std::size_t(top) + 1);
    for (int k = 0; k <= top; ++k) {
        Level& L = levels[std::size_t(k)];
        L.k = k;
        L.w = (W + (1 << k) - 1) >> k;
        L.h = (H + (1 << k) - 1) >> k;
        L.nc = nc;
    }

    // Level sources (k >= 1): block sums of the pixels at that level.
    for (int k = 1; k <= top; ++k) {
        Level& L = levels[std::size_t(k)];
        const std::size_t cells = std::size_t(L.w) * std::size_t(L.h);
        L.value.assign(cells * std::size_t(nc), 0.0f);
        L.weight.assign(cells, 0.0f);
        L.off_x.assign(cells, 0.0f);
        L.off_y.assign(cells, 0.0f);
        L.radius_sum.assign(cells, 0.0f);
        const int B = 1 << k;
        bool ok = parallel_for(exec, L.h, [&](long b, long e) {
            for (int by = int(b); by < int(e); ++by)
                for (int y = by * B; y < std::min(H, (by + 1) * B); ++y)
                    for (int x = 0; x < W; ++x) {
                        const std::size_t i = std::size_t(y) * std::size_t(W) + std::size_t(x);
                        if (lvl[i] != k) continue;
                        const std::size_t cell = std::size_t(by) * std::size_t(L.w) + std::size_t(x >> k);
                        float w = 1.0f;
                        for (int c = 0; c < nch; ++c) {
                            const float v = planes.at(c, win.x0 + x, win.y0 + y);
                            L.value[std::size_t(c) * cells + cell] += v;
                            w += std::abs(v);
                        }
                        L.value[std::size_t(nch) * cells + cell] += 1.0f;
                        L.weight[cell] += w;
                        L.off_x[cell] += w * (float(x - ((x >> k) << k)) + 0.5f);
                        L.off_y[cell] += w * (float(y - by * B) + 0.5f);
                        L.radius_sum[cell] += w * R[i];
                    }
        });
        if (!ok) return Status::cancelled("bokeh");
    }
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const std::size_t i = std::size_t(y) * std::size_t(W) + std::size_t(x);
            levels[lvl[i]].max_radius = std::max(levels[lvl[i]].max_radius, R[i]);
        }

    const bool any_cats_eye = P.aperture.cats_eye > 0.0;
    const std::vector<ShapeRows> centred =
        P.spans && !any_cats_eye ? centred_shapes(P, levels[0].max_radius, exec) : std::vector<ShapeRows>{};

    // Scatter, level by level, in bands of source rows: even bands, then odd.
    // Spans: every level's sources write full-resolution spans into level 0
    // (a block only gathers the sources, so a disc keeps its sharp edge);
    // kernels: each level into its own grid, upsampled afterwards.
    levels[0].acc.assign(std::size_t(nc) * std::size_t(H) * levels[0].stride(), 0.0f);
    for (int k = 0; k <= top; ++k) {
        Level& L = levels[std::size_t(k)];
        Level& A = P.spans ? levels[0] : L;  // where its sources write
        if (!P.spans && k > 0) A.acc.assign(std::size_t(nc) * std::size_t(L.h) * L.stride(), 0.0f);
        // Bands (in the level's rows) tall enough that sources two bands
        // apart never write the same row.
        const int reach = P.spans ? int(std::ceil(L.max_radius)) + 2 : P.kernel_reach + 1;
        const int band_rows = std::max(64, 2 * reach + 2);
        const int band = P.spans ? std::max(1, (band_rows + (1 << k) - 1) >> k) : band_rows;
        const int nbands = (L.h + band - 1) / band;
        const double scale = P.spans ? 1.0 : 1.0 / double(1 << k);
        const std::size_t cells = std::size_t(L.w) * std::size_t(L.h);
        auto run_band = [&](int bi) {
            Source s;
            ShapeRows rows;
            for (int y = bi * band; y < std::min(L.h, (bi + 1) * band); ++y)
                for (int x = 0; x < L.w; ++x) {
                    double full_x, full_y;
                    if (k == 0) {
                        const std::size_t i = std::size_t(y) * std::size_t(W) + std::size_t(x);
                        if (lvl[i] != 0) continue;
                        for (int c = 0; c < nch; ++c) s.val[c] = planes.at(c, win.x0 + x, win.y0 + y);
                        s.val[nch] = 1.0f;
                        s.cx = x + 0.5;
                        s.cy = y + 0.5;
                        s.r = R[i];
                        full_x = s.cx;
                        full_y = s.cy;
                    } else {
                        const std::size_t cell = std::size_t(y) * std::size_t(L.w) + std::size_t(x);
                        const float w = L.weight[cell];
                        if (!(w > 0.0f)) continue;
                        for (int c = 0; c < nc; ++c) s.val[c] = L.value[std::size_t(c) * cells + cell];
                        full_x = double(x << k) + double(L.off_x[cell]) / w;
                        full_y = double(y << k) + double(L.off_y[cell]) / w;
                        s.cx = full_x * scale;
                        s.cy = full_y * scale;
                        s.r = double(L.radius_sum[cell]) / w * scale;
                    }
                    s.cats_eye = false;
                    set_cats_eye(vignette, win.x0 + full_x, win.y0 + full_y, s);
                    if (P.spans && k == 0 && !centred.empty()) {
                        const long q = std::lround(s.r / kRadiusStep);
                        if (!scatter_point(A, s, double(q) * kRadiusStep)) scatter_rows(A, s, centred[std::size_t(q)]);
                    } else if (P.spans) {
                        scatter_spans(A, P, s, rows);
                    } else {
                        scatter_kernel(A, P, s, colour_channels);
                    }
                }
        };
        for (int parity = 0; parity < 2; ++parity) {
            const int count = (nbands - parity + 1) / 2;
            bool ok = parallel_for(exec, count, [&](long b, long e) {
                for (long j = b; j < e; ++j) run_band(int(2 * j + parity));
            });
            if (!ok) return Status::cancelled("bokeh");
        }
        L.value = {};
        L.weight = {};
        L.off_x = {};
        L.off_y = {};
        L.radius_sum = {};
        if (P.spans && k == top) {  // difference rows -> the spans themselves
            Level& Z = levels[0];
            bool ok = parallel_for(exec, long(nc) * Z.h, [&](long b, long e) {
                for (long j = b; j < e; ++j) {
                    float* d = Z.row(int(j / Z.h), int(j % Z.h));
                    double sum = 0.0;
                    for (int x = 0; x < Z.w; ++x) d[x] = float(sum += d[x]);
                }
            });
            if (!ok) return Status::cancelled("bokeh");
        }
    }

    // Kernels: coarse levels into finer ones, bilinear, energy per cell / 4.
    for (int k = P.spans ? 0 : top; k >= 1; --k) {
        Level& C = levels[std::size_t(k)];
        Level& Fn = levels[std::size_t(k) - 1];
        bool ok = parallel_for(exec, long(nc) * Fn.h, [&](long b, long e) {
            for (long j = b; j < e; ++j) {
                const int c = int(j / Fn.h), y = int(j % Fn.h);
                const double gy = (y + 0.5) * 0.5 - 0.5;
                const int y0 = int(std::floor(gy));
                const float fy = float(gy - y0);
                const float* r0 = C.row(c, std::clamp(y0, 0, C.h - 1));
                const float* r1 = C.row(c, std::clamp(y0 + 1, 0, C.h - 1));
                float* d = Fn.row(c, y);
                for (int x = 0; x < Fn.w; ++x) {
                    const double gx = (x + 0.5) * 0.5 - 0.5;
                    const int x0 = int(std::floor(gx));
                    const float fx = float(gx - x0);
                    const int xa = std::clamp(x0, 0, C.w - 1), xb = std::clamp(x0 + 1, 0, C.w - 1);
                    const float top_v = r0[xa] + fx * (r0[xb] - r0[xa]);
                    const float bot_v = r1[xa] + fx * (r1[xb] - r1[xa]);
                    d[x] += 0.25f * (top_v + fy * (bot_v - top_v));
                }
            }
        });
        if (!ok) return Status::cancelled("bokeh");
        C.acc = {};
    }

    // Normalise by the spread weight and write back.
    Level& L0 = levels[0];
    bool ok = parallel_for(exec, H, [&](long b, long e) {
        for (int y = int(b); y < int(e); ++y) {
            const float* wrow = L0.row(nch, y);
            for (int c = 0; c < nch; ++c) {
                const float* src = L0.row(c, y);
                for (int x = 0; x < W; ++x)
                    planes.at(c, win.x0 + x, win.y0 + y) = wrow[x] > 1e-6f ? src[x] / wrow[x] : 0.0f;
            }
        }
    });
    if (!ok) return Status::cancelled("bokeh");
    return Status::ok();
}

}  // namespace gdof
