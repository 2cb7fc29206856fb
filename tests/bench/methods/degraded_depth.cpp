#include "degraded_depth.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace gdof::bench {

namespace {

struct Rng {  // splitmix64
    std::uint64_t s;
    double uniform() {
        std::uint64_t z = (s += 0x9e3779b97f4a7c15ull);
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
        return double((z ^ (z >> 31)) >> 11) * (1.0 / 9007199254740992.0);
    }
    double normal() {  // Box-Muller
        const double u = std::max(uniform(), 1e-300), v = uniform();
        return std::sqrt(-2.0 * std::log(u)) * std::cos(6.283185307179586 * v);
    }
};

}  // namespace

Image degraded_depth(const Image& plate, double scale, std::uint64_t seed, DegradedDepthStats* stats) {
    Image out = plate;
    const int zc = out.channel_index("Z");
    const Roi w = out.data_window();
    const int W = w.width(), H = w.height();
    float* z = out.plane(zc);
    const std::vector<float> exact(z, z + out.npixels());
    std::vector<unsigned char> hole(out.npixels(), 0);
    Rng rng{seed};
    // Random discs until about 12% of the frame is covered.
    std::size_t covered = 0;
    while (covered < out.npixels() * 12 / 100) {
        const int cx = int(rng.uniform() * W), cy = int(rng.uniform() * H);
        const int r = int(std::lround((2 + 6 * rng.uniform()) * scale));
        for (int y = std::max(0, cy - r); y <= std::min(H - 1, cy + r); ++y)
            for (int x = std::max(0, cx - r); x <= std::min(W - 1, cx + r); ++x)
                if ((x - cx) * (x - cx) + (y - cy) * (y - cy) <= r * r) {
                    unsigned char& h = hole[std::size_t(y) * W + std::size_t(x)];
                    covered += h ? 0 : 1;
                    h = 1;
                }
    }
    // Shadows: the far side of a depth step loses half its pixels within 2 px.
    const int band = std::max(1, int(std::lround(2 * scale)));
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const float d = exact[std::size_t(y) * W + std::size_t(x)];
            if (!std::isfinite(d)) continue;
            bool far_side = false;
            for (int dx = 1; dx <= band && !far_side; ++dx)
                for (int s : {-1, 1}) {
                    const int xx = x + s * dx;
                    if (xx < 0 || xx >= W) continue;
                    const float q = exact[std::size_t(y) * W + std::size_t(xx)];
                    if (std::isfinite(q) && q * 1.1f < d) far_side = true;
                }
            if (far_side && rng.uniform() < 0.5) hole[std::size_t(y) * W + std::size_t(x)] = 1;
        }
    std::size_t holes = 0;
    for (std::size_t i = 0; i < out.npixels(); ++i) {
        const float d = exact[i];
        if (hole[i] || !std::isfinite(d)) {
            z[i] = 0.0f;  // no measurement (and no return from the sky)
            ++holes;
            continue;
        }
        const double noisy = d * (1.0 + 0.005 * rng.normal());
        z[i] = float(std::clamp(std::round(noisy * 1000.0), 1.0, 65535.0));
    }
    if (stats) stats->hole_fraction = double(holes) / double(out.npixels());
    return out;
}

}  // namespace gdof::bench
