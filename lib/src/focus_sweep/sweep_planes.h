// Single-channel float planes for aligning and measuring a sweep's frames:
// the luminance they are compared on, a 2x2 pyramid, bilinear samples, box
// filters. Internal to focus_sweep.
#pragma once

#include <array>
#include <cstddef>
#include <vector>

#include "gdof/exec.h"
#include "gdof/image.h"
#include "gdof/status.h"

namespace gdof::sweep_detail {

struct Plane {
    int w = 0, h = 0;
    std::vector<float> v;
    float at(int x, int y) const { return v[std::size_t(y) * std::size_t(w) + std::size_t(x)]; }
    float& at(int x, int y) { return v[std::size_t(y) * std::size_t(w) + std::size_t(x)]; }
};

// The colour a frame is measured and composited by: its R, G, B planes, or
// its first float channel three times (grey); nullptrs when it has none.
std::array<const float*, 3> colour_planes(const Image& image);

// The square root of the luminance of R, G, B (or of the first channel),
// clamped to [0, 16]: steps weigh alike in shadows and highlights, and a
// specular highlight does not dominate. Errors name `what` at a non-finite
// pixel or when there is no float channel.
Result<Plane> luminance_plane(const Image& image, const std::string& what, const Exec& exec = {});

// Half the size (rounded down, at least 1), each pixel the mean of its 2x2
// block: pixel centres stay at (i + 0.5) * 2^level in level-0 pixels.
Plane half_size(const Plane& p, const Exec& exec = {});

// Bilinear sample at (x, y) in pixel-centre coordinates (pixel i's centre
// is i + 0.5), clamped to the edge pixels.
float bilinear(const Plane& p, double x, double y);
// The same with Catmull-Rom cubics (4 x 4 taps): a bilinear resampling
// loses detail by the sub-pixel phase, which biases an alignment of fine
// texture by up to a tenth of a pixel (0.02 with the cubic).
float bicubic(const Plane& p, double x, double y);
float bicubic(const float* plane, int w, int h, double x, double y);

// Bilinear samples of two planes of one size at one position (an image's
// two gradients): the weights computed once, no clamping inside.
inline void bilinear2(const Plane& a, const Plane& b, double x, double y, float& va, float& vb) {
    const double fx = x - 0.5, fy = y - 0.5;
    if (fx >= 0 && fy >= 0 && fx < a.w - 1 && fy < a.h - 1) {
        const int x0 = int(fx), y0 = int(fy);
        const float tx = float(fx - x0), ty = float(fy - y0);
        const std::size_t i = std::size_t(y0) * std::size_t(a.w) + std::size_t(x0), w = std::size_t(a.w);
        const float w00 = (1 - tx) * (1 - ty), w10 = tx * (1 - ty), w01 = (1 - tx) * ty, w11 = tx * ty;
        va = w00 * a.v[i] + w10 * a.v[i + 1] + w01 * a.v[i + w] + w11 * a.v[i + w + 1];
        vb = w00 * b.v[i] + w10 * b.v[i + 1] + w01 * b.v[i + w] + w11 * b.v[i + w + 1];
        return;
    }
    va = bilinear(a, x, y);
    vb = bilinear(b, x, y);
}

// A binomial [1 4 6 4 1] / 16 blur across and down (sigma 1 px; edge
// pixels repeated): what bilinear sampling cannot follow (detail near
// the Nyquist frequency) would bias an alignment by its sub-pixel phase.
Plane binomial_blur(const Plane& p, const Exec& exec = {});

// Central differences across (gx) and down (gy), edge pixels repeated.
void central_differences(const Plane& p, Plane& gx, Plane& gy, const Exec& exec = {});

// The mean over a (2 r + 1)^2 window (edge pixels repeated), in place.
void box_mean(Plane& p, int r, const Exec& exec = {});

}  // namespace gdof::sweep_detail
