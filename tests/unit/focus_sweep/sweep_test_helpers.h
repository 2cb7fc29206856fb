// A focus sweep made analytically, for the focus_sweep tests: vertical strips
// of texture at known depths (sums of sinusoids, whose Gaussian blur is
// exact: each amplitude times exp(-2 pi^2 sigma^2 f^2), and whose integral
// over a pixel is the sinc of its frequency), one strip without
// texture, each frame focused at its own distance (blur sigma proportional
// to the difference of inverse depths, as a thin lens's) and seen through a
// known similarity (the camera's drift and the lens's breathing).
#pragma once

#include <cmath>
#include <random>
#include <vector>

#include "gdof/focus_sweep.h"
#include "gdof/image.h"

namespace sweep_test {

struct Wave {
    double fx, fy, amp, phase;
};

struct Sweep {
    int width = 320, height = 180;
    std::vector<double> strip_depth{1.0, 1.4, 2.0, 3.0, 5.0, 2.5};  // left to right; the last has no texture
    std::size_t flat_strip = 5;
    std::vector<double> focus;      // per frame
    double sigma_per_dioptre = 4.0;  // blur sigma (px) per unit of |1/z - 1/focus|
    std::vector<gdof::Similarity> scene_from_frame;  // per frame: frame pixel -> scene (= middle frame) pixel
    std::vector<Wave> waves;

    int strip_at(double x) const {
        const int s = int(std::floor(x / (double(width) / double(strip_depth.size()))));
        return std::clamp(s, 0, int(strip_depth.size()) - 1);
    }
    // Distance (px) from scene x to the nearest strip boundary.
    double boundary_distance(double x) const {
        const double w = double(width) / double(strip_depth.size());
        const double f = x / w - std::floor(x / w);
        return std::min(f, 1.0 - f) * w;
    }
    double base(int strip, int c) const { return 0.25 + 0.08 * double((strip * 3 + c * 5) % 7); }
    // Strip s's colour at scene position (x, y), blurred by sigma and
    // integrated over a pixel's square (`pixel`: the sinc of each wave).
    double strip_colour(int s, double x, double y, int c, double sigma, bool pixel) const {
        double v = base(s, c);
        if (std::size_t(s) == flat_strip) return v;
        auto sinc = [](double t) { return std::abs(t) < 1e-12 ? 1.0 : std::sin(M_PI * t) / (M_PI * t); };
        for (const Wave& w : waves) {
            const double f2 = w.fx * w.fx + w.fy * w.fy;
            const double box = pixel ? sinc(w.fx) * sinc(w.fy) : 1.0;
            v += (0.6 + 0.2 * c) * w.amp * box * std::exp(-2.0 * M_PI * M_PI * sigma * sigma * f2) *
                 std::sin(2.0 * M_PI * (w.fx * x + w.fy * y) + w.phase + 1.3 * s);
        }
        return v;
    }
    // The sharp scene at (x, y), as a pixel there records it.
    double colour(double x, double y, int c, double sigma) const {
        return strip_colour(strip_at(x), x, y, c, sigma, true);
    }
    double sigma(int strip, std::size_t frame) const {
        return sigma_per_dioptre * std::abs(1.0 / strip_depth[std::size_t(strip)] - 1.0 / focus[frame]);
    }
    // Strip s's colour (all three channels) at (x, y) from per-wave factors.
    void strip_rgb(int s, double x, double y, const std::vector<double>& factor, double out[3]) const {
        double t = 0;
        if (std::size_t(s) != flat_strip)
            for (std::size_t j = 0; j < waves.size(); ++j)
                t += factor[j] * std::sin(2.0 * M_PI * (waves[j].fx * x + waves[j].fy * y) + waves[j].phase + 1.3 * s);
        for (int c = 0; c < 3; ++c) out[c] = base(s, c) + (0.6 + 0.2 * c) * t;
    }
    gdof::Image frame(std::size_t k) const {
        // Per strip and wave: amplitude x pixel integral x blur (strip_colour's factors).
        std::vector<std::vector<double>> factor(strip_depth.size());
        auto sinc = [](double t) { return std::abs(t) < 1e-12 ? 1.0 : std::sin(M_PI * t) / (M_PI * t); };
        for (std::size_t st = 0; st < strip_depth.size(); ++st)
            for (const Wave& w : waves) {
                const double sg = sigma(int(st), k);
                factor[st].push_back(w.amp * sinc(w.fx) * sinc(w.fy) *
                                     std::exp(-2.0 * M_PI * M_PI * sg * sg * (w.fx * w.fx + w.fy * w.fy)));
            }
        gdof::Image img = gdof::Image::with_channels({"R", "G", "B"}, gdof::Roi{0, 0, width, height});
        for (int y = 0; y < height; ++y)
            for (int x = 0; x < width; ++x) {
                double sx, sy;
                scene_from_frame[k].apply(x + 0.5, y + 0.5, sx, sy);
                // A pixel straddling a strip boundary records both strips by
                // their share of its width (the camera integrates over it).
                const int s0 = strip_at(sx - 0.5), s1 = strip_at(sx + 0.5);
                double share1 = 0;
                if (s1 != s0) {
                    const double edge = double(s1) * double(width) / double(strip_depth.size());
                    share1 = std::clamp(sx + 0.5 - edge, 0.0, 1.0);
                }
                double c0[3], c1[3] = {0, 0, 0};
                strip_rgb(s0, sx, sy, factor[std::size_t(s0)], c0);
                if (share1 > 0) strip_rgb(s1, sx, sy, factor[std::size_t(s1)], c1);
                for (int c = 0; c < 3; ++c) img.at(c, x, y) = float((1 - share1) * c0[c] + share1 * c1[c]);
            }
        return img;
    }
};

// `n` frames focused evenly in dioptres from 0.9 m to 6 m; frame k drifts by
// (k - mid) steps of 0.3% scale, 0.04 degrees and (0.7, -0.4) px about the centre.
inline Sweep make_sweep(std::size_t n = 9, unsigned seed = 7) {
    Sweep s;
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (int i = 0; i < 40; ++i) {
        // A photograph's spectrum: amplitude falling as 1/f.
        const double f = 0.03 + 0.27 * u(rng), a = 2.0 * M_PI * u(rng);
        s.waves.push_back({f * std::cos(a), f * std::sin(a), (0.002 + 0.002 * u(rng)) / f, 2.0 * M_PI * u(rng)});
    }
    const double d0 = 1.0 / 0.9, d1 = 1.0 / 6.0;
    const std::size_t mid = (n - 1) / 2;
    for (std::size_t k = 0; k < n; ++k) {
        s.focus.push_back(1.0 / (d0 + (d1 - d0) * double(k) / double(n - 1)));
        const double j = double(k) - double(mid);
        const double sc = 1.0 + 0.003 * j, th = 0.04 * j * M_PI / 180.0;
        gdof::Similarity m;
        m.a = sc * std::cos(th);
        m.b = sc * std::sin(th);
        // About the centre c: m(p) = A (p - c) + c + t.
        const double cx = 0.5 * s.width, cy = 0.5 * s.height, tx = 0.7 * j, ty = -0.4 * j;
        m.tx = cx + tx - (m.a * cx - m.b * cy);
        m.ty = cy + ty - (m.b * cx + m.a * cy);
        s.scene_from_frame.push_back(m);
    }
    return s;
}

}  // namespace sweep_test
