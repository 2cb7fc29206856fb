// The aperture samples of vibrate_layers: one set per render, the same for
// every pixel, shifted by a counter-based hash of the seed, so the set
// depends on nothing but (aperture, n, seed).
#include <cmath>
#include <numbers>

#include "gdof/psf_field.h"

namespace gdof {

namespace {

// splitmix64: a well-mixed 64-bit value from a counter.
std::uint64_t mix(std::uint64_t x) {
    x += 0x9e3779b97f4a7c15ull;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
    return x ^ (x >> 31);
}

double uniform(std::uint64_t seed, std::uint64_t index, int which) {
    const std::uint64_t h = mix(seed * 0x100000001b3ull + index * 2 + std::uint64_t(which));
    return double(h >> 11) * (1.0 / 9007199254740992.0);  // [0, 1)
}

}  // namespace

Result<std::vector<ApertureSample>> aperture_samples(const Aperture& aperture, int n, std::uint64_t seed, double* spacing) {
    if (n < 1 || n > 65536) return Status::error("samples must be 1 to 65536, got " + std::to_string(n), StatusCode::InvalidArgument, "samples");
    if (Status st = validate(aperture); !st) return st;
    if (aperture.position_dependent())
        return Status::error("cats_eye: the shape varies across the frame; sample the aperture without it (vibrate_layers "
                             "maps each sample onto the cut shape per source)",
                             StatusCode::InvalidArgument, "cats_eye");
    std::vector<ApertureSample> out;
    // The shape's area in (u, v) units, from its mask (pi for the disc).
    const bool disc = aperture.kind == Aperture::Kind::Disc && aperture.squeeze == 1.0;
    double area = std::numbers::pi;
    if (!disc) {
        const Image mask = aperture_mask_image(aperture, 256);
        area = 0.0;
        for (std::size_t i = 0; i < mask.npixels(); ++i) area += double(mask.plane(0)[i]);
        area *= 4.0 / double(mask.npixels());
        if (!(area > 0.0)) return Status::error("the aperture has no area", StatusCode::InvalidArgument, "aperture");
    }
    // A square lattice shifted by a seeded offset, its points inside the
    // shape kept: the most even spread there is, so a Gaussian prefilter of
    // 0.7 spacings leaves a ripple of well under 1% (a spiral or jittered
    // strata leave 10 to 30%, which does not shrink as the count grows). The
    // spacing is searched around sqrt(area / n) for the count nearest n.
    const double ox = uniform(seed, 0, 0), oy = uniform(seed, 0, 1);
    auto lattice = [&](double d, std::vector<ApertureSample>* keep) {
        int count = 0;
        const int m = int(std::ceil(2.0 / d)) + 1;
        for (int j = -m; j <= m; ++j)
            for (int i = -m; i <= m; ++i) {
                const double u = (i + ox - 0.5) * d, v = (j + oy - 0.5) * d;
                if (std::abs(u) > 1.0 || std::abs(v) > 1.0) continue;
                if (disc ? u * u + v * v <= 1.0 : aperture_contains(aperture, u, v)) {
                    ++count;
                    if (keep) keep->push_back({u, v});
                }
            }
        return count;
    };
    const double d0 = std::sqrt(area / double(n));
    double best = d0;
    int best_miss = std::abs(lattice(d0, nullptr) - n);
    for (int k = 1; k <= 48 && best_miss > 0; ++k) {
        const double d = d0 * (1.0 + (k % 2 ? 1.0 : -1.0) * 0.004 * ((k + 1) / 2));
        const int miss = std::abs(lattice(d, nullptr) - n);
        if (miss < best_miss) best = d, best_miss = miss;
    }
    lattice(best, &out);
    if (out.empty()) return Status::error("no aperture sample fell inside the aperture", StatusCode::InvalidArgument, "aperture");
    if (spacing) *spacing = best;
    return out;
}

}  // namespace gdof
