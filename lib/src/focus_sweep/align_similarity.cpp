// estimate_similarity and warp_similarity (focus_sweep.h): Gauss-Newton on
// a 2x2 pyramid of the frames' luminance (sweep_planes.h), coarse to fine,
// for a similarity and a brightness gain and offset, with Huber weights so
// that what moved in the scene or changed in blur counts less.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

#include "focus_sweep/align_internal.h"
#include "gdof/focus_sweep.h"

namespace gdof {

using namespace sweep_detail;

double Similarity::scale() const { return std::hypot(a, b); }
double Similarity::rotation_degrees() const { return std::atan2(b, a) * 180.0 / 3.14159265358979323846; }

Similarity Similarity::after(const Similarity& first) const {
    // As complex affine maps z -> A z + B: this(first(z)) = A2 (A1 z + B1) + B2.
    Similarity s;
    s.a = a * first.a - b * first.b;
    s.b = a * first.b + b * first.a;
    s.tx = a * first.tx - b * first.ty + tx;
    s.ty = b * first.tx + a * first.ty + ty;
    return s;
}

double Similarity::largest_shift(int width, int height) const {
    double worst = 0;
    for (int cy = 0; cy < 2; ++cy)
        for (int cx = 0; cx < 2; ++cx) {
            const double x = cx * width, y = cy * height;
            double xo, yo;
            apply(x, y, xo, yo);
            worst = std::max(worst, std::hypot(xo - x, yo - y));
        }
    return worst;
}

namespace {

constexpr int kParams = 6;  // a, b, tx, ty (centred), gain, offset
constexpr double kHuber = 0.04;  // in sqrt(luminance): beyond it a residual is down-weighted
// A level of more pixels than this is fitted on every s-th row and column
// (s the smallest that brings it under): six parameters need far fewer
// equations than a 1080p frame has pixels, and the time goes with them.
constexpr double kFitPixels = 400000;

int fit_stride(const Plane& p) {
    int s = 1;
    while (double(p.w) * double(p.h) / double(s * s) > kFitPixels) ++s;
    return s;
}

// Solves the 6x6 system n x = r (Gaussian elimination, partial pivoting);
// false when singular.
bool solve6(std::array<double, 36> n, std::array<double, 6> r, std::array<double, 6>& x) {
    for (int c = 0; c < kParams; ++c) {
        int piv = c;
        for (int i = c + 1; i < kParams; ++i)
            if (std::abs(n[i * 6 + c]) > std::abs(n[piv * 6 + c])) piv = i;
        if (!(std::abs(n[piv * 6 + c]) > 1e-12)) return false;
        for (int j = 0; j < kParams; ++j) std::swap(n[c * 6 + j], n[piv * 6 + j]);
        std::swap(r[c], r[piv]);
        for (int i = c + 1; i < kParams; ++i) {
            const double f = n[i * 6 + c] / n[c * 6 + c];
            for (int j = c; j < kParams; ++j) n[i * 6 + j] -= f * n[c * 6 + j];
            r[i] -= f * r[c];
        }
    }
    for (int c = kParams - 1; c >= 0; --c) {
        double s = r[c];
        for (int j = c + 1; j < kParams; ++j) s -= n[c * 6 + j] * x[j];
        x[c] = s / n[c * 6 + c];
    }
    return true;
}

// The parameters in a level's centred coordinates: x' = cx + a u - b v + tx
// with u = x - cx (cx, cy the level's centre).
struct Params {
    double a = 1, b = 0, tx = 0, ty = 0, gain = 1, offset = 0;
};

Similarity to_absolute(const Params& p, double cx, double cy, double level_scale) {
    Similarity s;
    s.a = p.a;
    s.b = p.b;
    s.tx = (cx + p.tx - p.a * cx + p.b * cy) * level_scale;
    s.ty = (cy + p.ty - p.b * cx - p.a * cy) * level_scale;
    return s;
}

Params from_absolute(const Similarity& s, double cx, double cy, double level_scale, double gain, double offset) {
    Params p;
    p.a = s.a;
    p.b = s.b;
    p.tx = s.tx / level_scale - cx + s.a * cx - s.b * cy;
    p.ty = s.ty / level_scale - cy + s.b * cx + s.a * cy;
    p.gain = gain;
    p.offset = offset;
    return p;
}

// RMS of fixed - (gain moving(map) + offset) over the fixed pixels whose
// mapped position lies inside the moving frame (with a 1 px margin), on the
// fit's rows and columns (fit_stride); per row sums added in row order (the
// same bits for any thread count).
double rms_residual(const Plane& moving, const Plane& fixed, const Params& p, const Exec& exec) {
    const double cx = 0.5 * fixed.w, cy = 0.5 * fixed.h;
    const int stride = fit_stride(fixed);
    const int nrows = (fixed.h + stride - 1) / stride;
    std::vector<double> sums(static_cast<std::size_t>(nrows), 0.0);
    std::vector<std::size_t> counts(static_cast<std::size_t>(nrows), 0);
    parallel_for(exec, nrows, [&](long r0, long r1) {
        for (long row = r0; row < r1; ++row) {
            const int y = int(row) * stride;
            for (int x = 0; x < fixed.w; x += stride) {
                const double u = x + 0.5 - cx, v = y + 0.5 - cy;
                const double xm = cx + p.a * u - p.b * v + p.tx, ym = cy + p.b * u + p.a * v + p.ty;
                if (!(xm >= 1 && ym >= 1 && xm <= moving.w - 1 && ym <= moving.h - 1)) continue;  // NaN too
                const double r = p.gain * bicubic(moving, xm, ym) + p.offset - fixed.at(x, y);
                sums[std::size_t(row)] += r * r;
                ++counts[std::size_t(row)];
            }
        }
    });
    double sum = 0;
    std::size_t n = 0;
    for (std::size_t y = 0; y < sums.size(); ++y) sum += sums[y], n += counts[y];
    return n ? std::sqrt(sum / double(n)) : 0.0;
}

// The moving frame's gradients are sampled bilinearly (the Jacobian need not
// be exact: Gauss-Newton still converges to the minimum of the residual,
// which is sampled with cubics).
bool refine_level(const Plane& moving, const Plane& gx, const Plane& gy, const Plane& fixed, Params& p, int iterations,
                  const Exec& exec) {
    const double cx = 0.5 * fixed.w, cy = 0.5 * fixed.h;
    const double half_diagonal = 0.5 * std::hypot(double(fixed.w), double(fixed.h));
    const int stride = fit_stride(fixed);
    const int nrows = (fixed.h + stride - 1) / stride;
    for (int it = 0; it < iterations; ++it) {
        // Per row partial sums, added in row order: the same bits for any thread count.
        std::vector<std::array<double, 42>> rows(static_cast<std::size_t>(nrows));
        const bool done = parallel_for(exec, nrows, [&](long r0, long r1) {
            for (long row = r0; row < r1; ++row) {
                const long y = row * stride;
                std::array<double, 42> acc{};
                for (int x = 0; x < fixed.w; x += stride) {
                    const double u = x + 0.5 - cx, v = y + 0.5 - cy;
                    const double xm = cx + p.a * u - p.b * v + p.tx, ym = cy + p.b * u + p.a * v + p.ty;
                    if (!(xm >= 1 && ym >= 1 && xm <= moving.w - 1 && ym <= moving.h - 1)) continue;  // NaN too
                    const double m = bicubic(moving, xm, ym);
                    float sx, sy;
                    bilinear2(gx, gy, xm, ym, sx, sy);
                    const double mx = p.gain * sx, my = p.gain * sy;
                    const double r = p.gain * m + p.offset - fixed.at(x, int(y));
                    const double w = std::abs(r) <= kHuber ? 1.0 : kHuber / std::abs(r);
                    const double j[kParams] = {mx * u + my * v, -mx * v + my * u, mx, my, m, 1.0};
                    for (int i = 0; i < kParams; ++i) {
                        for (int k = i; k < kParams; ++k) acc[std::size_t(i * 6 + k)] += w * j[i] * j[k];
                        acc[std::size_t(36 + i)] -= w * j[i] * r;
                    }
                }
                rows[std::size_t(row)] = acc;
            }
        });
        if (!done) return false;
        std::array<double, 36> n{};
        std::array<double, 6> rhs{};
        for (const auto& acc : rows) {
            for (int i = 0; i < 36; ++i) n[std::size_t(i)] += acc[std::size_t(i)];
            for (int i = 0; i < 6; ++i) rhs[std::size_t(i)] += acc[std::size_t(36 + i)];
        }
        for (int i = 0; i < kParams; ++i) {
            for (int k = 0; k < i; ++k) n[std::size_t(i * 6 + k)] = n[std::size_t(k * 6 + i)];
            n[std::size_t(i * 6 + i)] *= 1.0 + 1e-6;  // a touch of damping
        }
        std::array<double, 6> d{};
        if (!solve6(n, rhs, d)) break;
        p.a += d[0];
        p.b += d[1];
        p.tx += d[2];
        p.ty += d[3];
        p.gain += d[4];
        p.offset += d[5];
        // Converged when no corner moves by a hundredth of a pixel.
        if ((std::abs(d[0]) + std::abs(d[1])) * half_diagonal + std::abs(d[2]) + std::abs(d[3]) < 0.01) break;
    }
    return true;
}

}  // namespace

namespace sweep_detail {

Status check_align_options(const AlignOptions& options) {
    if (!(options.max_scale > 1.0) || !(options.max_shift > 0.0) || options.iterations < 1)
        return Status::error("align: max_scale must be > 1, max_shift > 0 and iterations >= 1", StatusCode::InvalidArgument);
    return Status::ok();
}

Result<AlignPyramid> make_align_pyramid(const Image& frame, const std::string& what, const Exec& exec) {
    auto l = luminance_plane(frame, what, exec);
    if (!l) return l.status();
    AlignPyramid a;
    a.raw = std::move(l).value();
    // Levels down to about 32 px on the short side.
    Plane level = a.raw;
    for (;;) {
        a.level.push_back(binomial_blur(level, exec));
        Plane gx, gy;
        central_differences(a.level.back(), gx, gy, exec);
        a.gx.push_back(std::move(gx));
        a.gy.push_back(std::move(gy));
        if (std::min(level.w, level.h) < 64) break;
        level = half_size(level, exec);
    }
    if (exec.is_cancelled()) return Status::cancelled("align");
    return a;
}

Result<SimilarityFit> fit_similarity(const AlignPyramid& moving, const AlignPyramid& fixed, int width, int height,
                                     const AlignOptions& options, const Similarity& initial, const Exec& exec) {
    const int top = int(std::min(moving.level.size(), fixed.level.size())) - 1;
    double gain = 1, offset = 0;
    Similarity s = initial;
    for (int L = top; L >= 0; --L) {
        const std::size_t l = std::size_t(L);
        const double scale = double(1 << L);
        const double cx = 0.5 * fixed.level[l].w, cy = 0.5 * fixed.level[l].h;
        Params p = from_absolute(s, cx, cy, scale, gain, offset);
        if (!refine_level(moving.level[l], moving.gx[l], moving.gy[l], fixed.level[l], p, options.iterations, exec))
            return Status::cancelled("align");
        s = to_absolute(p, cx, cy, scale);
        gain = p.gain;
        offset = p.offset;
    }
    SimilarityFit fit;
    fit.map = s;
    fit.gain = gain;
    fit.offset = offset;
    {
        const double cx = 0.5 * fixed.raw.w, cy = 0.5 * fixed.raw.h;
        fit.residual_before = rms_residual(moving.raw, fixed.raw, Params{}, exec);
        fit.residual_after = rms_residual(moving.raw, fixed.raw, from_absolute(s, cx, cy, 1.0, gain, offset), exec);
    }
    const double sc = s.scale();
    const double shift = s.largest_shift(width, height);
    if (!std::isfinite(sc) || !(sc <= options.max_scale) || !(sc >= 1.0 / options.max_scale) || !std::isfinite(shift) ||
        !(shift <= options.max_shift * width)) {
        char b[200];
        std::snprintf(b, sizeof b, "align: no plausible match (scale %.4g, shift up to %.4g px; limits %.3g and %.3g px)", sc,
                      shift, options.max_scale, options.max_shift * width);
        return Status::error(b, StatusCode::Failed);
    }
    return fit;
}

}  // namespace sweep_detail

Result<SimilarityFit> estimate_similarity(const Image& moving, const Image& fixed, const AlignOptions& options,
                                          const Similarity& initial, const Exec& exec) {
    if (moving.data_window() != fixed.data_window())
        return Status::error("align: the frames differ in size (" + to_string(moving.data_window()) + " and " +
                                 to_string(fixed.data_window()) + ")",
                             StatusCode::InvalidArgument);
    if (Status st = check_align_options(options); !st) return st;
    auto pm = make_align_pyramid(moving, "align: moving frame", exec);
    if (!pm) return pm.status();
    auto pf = make_align_pyramid(fixed, "align: fixed frame", exec);
    if (!pf) return pf.status();
    return fit_similarity(pm.value(), pf.value(), fixed.width(), fixed.height(), options, initial, exec);
}

Image warp_similarity(const Image& source, const Similarity& map, const Exec& exec) {
    Image out(source.channels(), source.data_window(), source.display_window());
    out.metadata = source.metadata;
    out.name = source.name;
    out.view = source.view;
    out.storage = source.storage;
    for (int c = 0; c < source.nchannels(); ++c) {
        const float* in = source.plane(c);
        float* o = out.plane(c);
        if (!in || !o) continue;
        const int W = source.width();
        parallel_for(exec, source.height(), [&](long y0, long y1) {
            for (long y = y0; y < y1; ++y)
                for (int x = 0; x < W; ++x) {
                    double xs, ys;
                    map.apply(x + 0.5, double(y) + 0.5, xs, ys);
                    o[std::size_t(y) * std::size_t(W) + std::size_t(x)] = bicubic(in, W, source.height(), xs, ys);
                }
        });
    }
    return out;
}

}  // namespace gdof
