// The splat pyramid: each splat is a quadratic B-spline on its level (or
// bilinear on level 0 for a source that does not move), each level is upsampled bilinearly into the
// next finer one (mass kept: a coarse cell's mass goes to 4 finer cells with
// weights summing to 1). A splat on level k >= 1 thus becomes a smooth kernel
// of variance 4^k / 2 - 1/4 px^2 per axis wherever it falls (1/4 on level 0),
// at a cost independent of its size: the prefilter that turns N discrete
// aperture samples into one smooth shape.
#include <algorithm>
#include <cmath>

#include "psf_field/vibrate_internal.h"

namespace gdof::vibrate_detail {

SplatPyramid::SplatPyramid(const Roi& window, int levels) : window_(window) {
    levels = std::max(1, levels);
    for (int k = 0; k < levels; ++k) {
        nx_.push_back((window.width() >> k) + 1);
        ny_.push_back((window.height() >> k) + 1);
        cells_.emplace_back(std::size_t(nx_.back() + 2) * std::size_t(ny_.back() + 2) * kChannels, 0.0f);
        box_.push_back(Roi{});
    }
    out_.assign(window.npixels() * kChannels, 0.0f);
}

void SplatPyramid::clear() {
    for (int k = 0; k <= top_used_; ++k) {
        const Roi b = box_[std::size_t(k)];
        const std::size_t stride = std::size_t(nx_[k] + 2);
        for (int j = b.y0; j < b.y1; ++j)
            std::fill_n(cells_[std::size_t(k)].data() + (std::size_t(j) * stride + std::size_t(b.x0)) * kChannels,
                        std::size_t(b.width()) * kChannels, 0.0f);
        box_[std::size_t(k)] = Roi{};
    }
    top_used_ = 0;
}

void SplatPyramid::splat_level(int k, double px, double py, float w, const float* m, bool quad) {
    const double s = double(1 << k);
    const double X = (px - window_.x0) / s - 0.5, Y = (py - window_.y0) / s - 0.5;
    // Bilinear for a source that does not move (it lands exactly on itself);
    // else the quadratic B-spline's three weights per axis, whose variance
    // (1/4 cell^2) does not depend on where the splat falls.
    const double bx = quad ? std::floor(X + 0.5) - 1.0 : std::floor(X);
    const double by = quad ? std::floor(Y + 0.5) - 1.0 : std::floor(Y);
    if (!(bx >= -3.0 && by >= -3.0 && bx <= nx_[k] && by <= ny_[k])) return;  // also NaN
    const int i0 = int(bx), j0 = int(by), taps = quad ? 3 : 2;
    float wx[3], wy[3];
    if (quad) {
        const float tx = float(X - (bx + 1.0)), ty = float(Y - (by + 1.0));  // in [-1/2, 1/2)
        wx[0] = 0.5f * (0.5f - tx) * (0.5f - tx), wx[1] = 0.75f - tx * tx, wx[2] = 0.5f * (0.5f + tx) * (0.5f + tx);
        wy[0] = 0.5f * (0.5f - ty) * (0.5f - ty), wy[1] = 0.75f - ty * ty, wy[2] = 0.5f * (0.5f + ty) * (0.5f + ty);
    } else {
        const float fx = float(X - bx), fy = float(Y - by);
        wx[0] = 1.0f - fx, wx[1] = fx, wy[0] = 1.0f - fy, wy[1] = fy;
    }
    const int stride = nx_[k] + 2;
    float* cells = cells_[std::size_t(k)].data();
    top_used_ = std::max(top_used_, k);
    // The cells written, stored indices (border included), clipped to the level.
    Roi& b = box_[std::size_t(k)];
    b = unite(b, intersect(Roi{i0 + 1, j0 + 1, i0 + 1 + taps, j0 + 1 + taps}, Roi{0, 0, nx_[k] + 2, ny_[k] + 2}));
    for (int dj = 0; dj < taps; ++dj) {
        const int j = j0 + dj;
        if (j < -1 || j > ny_[k]) continue;
        for (int di = 0; di < taps; ++di) {
            const int i = i0 + di;
            if (i < -1 || i > nx_[k]) continue;
            const float ww = w * wx[di] * wy[dj];
            float* c = cells + (std::size_t(j + 1) * std::size_t(stride) + std::size_t(i + 1)) * kChannels;
            for (int ch = 0; ch < kChannels; ++ch) c[ch] += ww * m[ch];
        }
    }
}

void SplatPyramid::splat(double px, double py, float level, const float* m) {
    if (level < 0.0f) {  // a sharp source
        splat_level(0, px, py, 1.0f, m, false);
        return;
    }
    const int top = int(cells_.size()) - 1;
    const float l = std::min(level, float(top));
    const int k0 = std::min(int(l), top);
    const float f = l - float(k0);
    if (f < 1.0f) splat_level(k0, px, py, 1.0f - f, m, true);
    if (f > 0.0f && k0 + 1 <= top) splat_level(k0 + 1, px, py, f, m, true);
}

const float* SplatPyramid::resolve(Roi& box) {
    // Coarse to fine: fine cell i' (level k-1) lies at coarse coordinate
    // i'/2 - 1/4: 3/4 of the nearer coarse cell, 1/4 of the next; / 4 keeps mass.
    for (int k = top_used_; k >= 1; --k) {  // levels above hold nothing
        const int cw = nx_[k] + 2, ch = ny_[k] + 2;
        const int fw = nx_[k - 1] + 2, fh = ny_[k - 1] + 2;
        const float* coarse = cells_[std::size_t(k)].data();
        float* fine = cells_[std::size_t(k - 1)].data();
        // Coarse stored cell c (index c - 1) reaches fine indices 2(c-1) - 1 ..
        // 2(c-1) + 2, stored 2(c-1) .. 2(c-1) + 3.
        const Roi cb = box_[std::size_t(k)];
        if (cb.empty()) continue;
        const Roi fb = intersect(Roi{2 * (cb.x0 - 1), 2 * (cb.y0 - 1), 2 * (cb.x1 - 1) + 2, 2 * (cb.y1 - 1) + 2},
                                 Roi{0, 0, fw, fh});
        box_[std::size_t(k - 1)] = unite(box_[std::size_t(k - 1)], fb);
        for (int fj = fb.y0; fj < fb.y1; ++fj) {
            const int j = fj - 1;  // fine index with border
            const int jm = (j >= 0 ? j / 2 : -1);  // floor(j / 2) for j >= -1
            const int jn = (j & 1) ? jm + 1 : jm - 1;
            const int cj[2] = {jm + 1, jn + 1};  // with the coarse border
            const float wj[2] = {0.75f, 0.25f};
            for (int fi = fb.x0; fi < fb.x1; ++fi) {
                const int i = fi - 1;
                const int im = (i >= 0 ? i / 2 : -1);
                const int in = (i & 1) ? im + 1 : im - 1;
                const int ci[2] = {im + 1, in + 1};
                const float wi[2] = {0.75f, 0.25f};
                float* f = fine + (std::size_t(fj) * std::size_t(fw) + std::size_t(fi)) * kChannels;
                for (int b = 0; b < 2; ++b) {
                    if (cj[b] < 0 || cj[b] >= ch) continue;
                    for (int a = 0; a < 2; ++a) {
                        if (ci[a] < 0 || ci[a] >= cw) continue;
                        const float w = wj[b] * wi[a] * 0.25f;
                        const float* c = coarse + (std::size_t(cj[b]) * std::size_t(cw) + std::size_t(ci[a])) * kChannels;
                        for (int q = 0; q < kChannels; ++q) f[q] += w * c[q];
                    }
                }
            }
        }
    }
    // Level 0's written cells as window pixels (stored index - 1).
    const int W = window_.width(), stride = nx_[0] + 2;
    const Roi b0 = box_[0];
    box = intersect(Roi{b0.x0 - 1, b0.y0 - 1, b0.x1 - 1, b0.y1 - 1}, Roi{0, 0, W, window_.height()});
    const float* c0 = cells_[0].data();
    for (int y = box.y0; y < box.y1; ++y)
        std::copy_n(c0 + (std::size_t(y + 1) * std::size_t(stride) + std::size_t(box.x0 + 1)) * kChannels,
                    std::size_t(box.width()) * kChannels,
                    out_.data() + (std::size_t(y) * std::size_t(W) + std::size_t(box.x0)) * kChannels);
    return out_.data();
}

}  // namespace gdof::vibrate_detail
