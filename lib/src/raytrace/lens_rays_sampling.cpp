// Aperture samples: per-pixel seeds, scrambled 2D Sobol points, a pixel's
// camera samples, and the maps from the unit square to the aperture shapes
// (disc, polygon, mask image).
#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "gdof/lens_rays.h"
#include "raytrace/hash.h"

namespace gdof {

namespace {

using rt::mix64;

std::uint32_t reverse_bits(std::uint32_t x) {
    // Bits within each byte, then the bytes (one bswap instruction).
    x = ((x >> 1) & 0x55555555u) | ((x & 0x55555555u) << 1);
    x = ((x >> 2) & 0x33333333u) | ((x & 0x33333333u) << 2);
    x = ((x >> 4) & 0x0f0f0f0fu) | ((x & 0x0f0f0f0fu) << 4);
    return __builtin_bswap32(x);
}

// A hash where output bit j depends only on input bits <= j (additions and
// multiplications carry upwards only, x ^= x * even keeps bit j a function of
// the bits below it). Applied to bit-reversed values it is a nested uniform
// (Owen) scramble: each bit is flipped by a function of the more significant
// bits only.
std::uint32_t upward_hash(std::uint32_t x, std::uint32_t seed) {
    x += seed;
    x ^= x * 0x6c50b47cu;
    x ^= x * 0xb82f1e52u;
    x ^= x * 0xc7afe638u;
    x ^= x * 0x8d22f6e6u;
    return x;
}

std::uint32_t owen_scramble(std::uint32_t x, std::uint32_t seed) {
    return reverse_bits(upward_hash(reverse_bits(x), seed));
}

// Second Sobol dimension (primitive polynomial x + 1): direction numbers
// v_1 = 2^31, v_{k+1} = v_k ^ (v_k >> 1) (Pascal's triangle mod 2); here
// bit-reversed (v_1 = 1, v_{k+1} = v_k ^ (v_k << 1)), which is what the
// scramble takes, so no reversal is needed before it.
std::uint32_t sobol_dim1_reversed(std::uint32_t index) {
    std::uint32_t r = 0;
    std::uint32_t v = 1u;
    for (; index; index >>= 1, v ^= v << 1)
        if (index & 1u) r ^= v;
    return r;
}

double to_unit(std::uint32_t x) {
    // 32 bits -> [0, 1): exact in double, never 1.
    return double(x) * (1.0 / 4294967296.0);
}

}  // namespace

std::uint64_t pixel_seed(int x, int y, std::uint64_t global_seed) {
    std::uint64_t h = mix64(global_seed ^ 0x9e3779b97f4a7c15ull);
    h = mix64(h ^ std::uint64_t(std::uint32_t(x)));
    h = mix64(h ^ (std::uint64_t(std::uint32_t(y)) << 32) ^ 0x632be59bd9b4e019ull);
    return h;
}

PixelSampler::Sequence::Sequence(std::uint64_t seed)
    : order(std::uint32_t(seed) ^ std::uint32_t(seed >> 32)), x(std::uint32_t(mix64(seed + 0x1))),
      y(std::uint32_t(mix64(seed + 0x2))) {}

Vec2 PixelSampler::Sequence::at(std::uint32_t index) const {
    // Shuffle the order: an Owen scramble of the index permutes aligned
    // blocks of 2^k indices among themselves, so each prefix of 2^k samples
    // is still an aligned block of the (0,2)-sequence, a (0,k,2)-net.
    // Dimension 0 is the radical inverse reverse_bits(i) and dimension 1
    // sobol_dim1(i); owen_scramble(v, s) = reverse_bits(upward_hash(
    // reverse_bits(v), s)), so the inner reversals cancel (the same bits,
    // four bit reversals per sample instead of seven).
    const std::uint32_t i = owen_scramble(index, order);
    const std::uint32_t a = reverse_bits(upward_hash(i, x));
    const std::uint32_t b = reverse_bits(upward_hash(sobol_dim1_reversed(i), y));
    return {to_unit(a), to_unit(b)};
}

Vec2 unit_square_sample(std::uint64_t seed, std::uint32_t index) { return PixelSampler::Sequence(seed).at(index); }

void unit_square_samples(std::uint64_t seed, std::uint32_t first, std::span<Vec2> out) {
    const PixelSampler::Sequence seq(seed);
    for (std::size_t k = 0; k < out.size(); ++k) out[k] = seq.at(first + std::uint32_t(k));
}

PixelSampler::PixelSampler(int x, int y, std::uint64_t global_seed, bool jitter)
    : aperture_(pixel_seed(x, y, global_seed)),
      jitter_seq_(jitter ? mix64(pixel_seed(x, y, global_seed) ^ 0x6a09e667f3bcc909ull) : 0), jitter_(jitter) {}

CameraSample PixelSampler::sample(std::uint32_t index) const {
    CameraSample s;
    if (jitter_) {
        const Vec2 u = jitter_seq_.at(index);
        s.pixel_offset = {u.x - 0.5, u.y - 0.5};
    }
    s.aperture = aperture_.at(index);
    return s;
}

Vec2 concentric_disc(Vec2 unit) {
    const double a = 2.0 * unit.x - 1.0, b = 2.0 * unit.y - 1.0;
    if (a == 0.0 && b == 0.0) return {0.0, 0.0};
    constexpr double q = std::numbers::pi / 4.0;
    double r, phi;
    if (std::fabs(a) > std::fabs(b)) {
        r = a;
        phi = q * (b / a);
    } else {
        r = b;
        phi = 2.0 * q - q * (a / b);
    }
    return {r * std::cos(phi), r * std::sin(phi)};
}

ApertureShape ApertureShape::disc() { return ApertureShape(); }

Result<ApertureShape> aperture_shape(const Aperture& a) {
    if (Status st = validate(a); !st) return st;
    if (a.cats_eye > 0.0)
        return Status::error("aperture: cats_eye (a shape that changes across the frame) is not supported by the ray "
                             "tracer; it applies to --bokeh",
                             StatusCode::InvalidArgument, "cats_eye");
    if (a.kind == Aperture::Kind::Disc && a.squeeze == 1.0) return ApertureShape::disc();
    if (a.kind == Aperture::Kind::Polygon && a.roundness == 0.0 && a.squeeze == 1.0)
        return ApertureShape::polygon(a.blades, a.rotation_deg);
    return ApertureShape::mask(aperture_mask_image(a, 512));
}

Result<ApertureShape> ApertureShape::polygon(int blades, double rotation_deg) {
    if (blades < 3) return Status::error("aperture polygon: blades must be >= 3, got " + std::to_string(blades));
    if (!std::isfinite(rotation_deg))
        return Status::error("aperture polygon: rotation must be finite, got " + std::to_string(rotation_deg));
    ApertureShape s;
    s.kind_ = Kind::Polygon;
    s.blades_ = blades;
    s.rotation_rad_ = rotation_deg * std::numbers::pi / 180.0;
    return s;
}

Result<ApertureShape> ApertureShape::mask(const Image& image, int channel) {
    if (image.data_window().empty()) return Status::error("aperture mask: the image is empty");
    if (channel < 0) {
        channel = image.channel_index("A");
        if (channel < 0) channel = 0;
    }
    if (channel >= image.nchannels())
        return Status::error("aperture mask: channel " + std::to_string(channel) + " out of range (image has " +
                             std::to_string(image.nchannels()) + ")");
    const Roi dw = image.data_window();
    const int w = dw.width(), h = dw.height();
    ApertureShape s;
    s.kind_ = Kind::Mask;
    s.mask_w_ = w;
    s.mask_h_ = h;
    s.row_cdf_.assign(std::size_t(h) + 1, 0.0);
    s.col_cdf_.assign(std::size_t(h) * std::size_t(w + 1), 0.0);
    for (int y = 0; y < h; ++y) {
        double* row = &s.col_cdf_[std::size_t(y) * std::size_t(w + 1)];
        for (int x = 0; x < w; ++x) {
            const double v = image.sample(channel, dw.x0 + x, dw.y0 + y);
            if (!std::isfinite(v))
                return Status::error("aperture mask: non-finite value at pixel (" + std::to_string(dw.x0 + x) + ", " +
                                     std::to_string(dw.y0 + y) + ") of channel '" + image.channel(channel).name + "'");
            row[x + 1] = row[x] + std::max(0.0, v);
        }
        s.row_cdf_[std::size_t(y) + 1] = s.row_cdf_[std::size_t(y)] + row[w];
    }
    const double total = s.row_cdf_.back();
    if (!(total > 0))
        return Status::error("aperture mask: channel '" + image.channel(channel).name + "' has no positive value");
    s.mask_scale_ = 2.0 / double(std::max(w, h));
    s.mask_area_ = total * s.mask_scale_ * s.mask_scale_;  // weighted: full pixels count 1
    return s;
}

double ApertureShape::area() const {
    switch (kind_) {
        case Kind::Disc: return std::numbers::pi;
        case Kind::Polygon: return 0.5 * blades_ * std::sin(2.0 * std::numbers::pi / blades_);
        case Kind::Mask: return mask_area_;
    }
    return 0.0;
}

namespace {

// Inverts a cumulative table c[0..n] (c[0] = 0, nondecreasing) at t in
// [0, c[n]): index k with c[k] <= t < c[k+1] (skipping empty cells) and the
// fraction inside that cell.
std::pair<int, double> invert_cdf(const double* c, int n, double t) {
    int k = int(std::upper_bound(c, c + n + 1, t) - c) - 1;
    k = std::clamp(k, 0, n - 1);
    while (k < n - 1 && !(c[k + 1] > c[k])) ++k;  // t at the end of a run of empty cells
    while (k > 0 && !(c[k + 1] > c[k])) --k;
    const double width = c[k + 1] - c[k];
    const double f = width > 0 ? std::clamp((t - c[k]) / width, 0.0, std::nextafter(1.0, 0.0)) : 0.5;
    return {k, f};
}

}  // namespace

Vec2 ApertureShape::map(Vec2 unit) const {
    switch (kind_) {
        case Kind::Disc: return concentric_disc(unit);
        case Kind::Polygon: {
            // Pick the fan triangle (centre, vertex k, vertex k+1) with u, reuse
            // the remainder; uniform inside the triangle with the square root.
            const double t = unit.x * blades_;
            const int k = std::min(int(t), blades_ - 1);
            const double a = t - k;
            const double step = 2.0 * std::numbers::pi / blades_;
            const double th0 = rotation_rad_ + k * step, th1 = th0 + step;
            const double r = std::sqrt(a);
            const double b = unit.y;
            return {r * ((1.0 - b) * std::cos(th0) + b * std::cos(th1)),
                    r * ((1.0 - b) * std::sin(th0) + b * std::sin(th1))};
        }
        case Kind::Mask: {
            const double total = row_cdf_.back();
            const auto [y, fy] = invert_cdf(row_cdf_.data(), mask_h_, unit.y * total);
            const double* row = &col_cdf_[std::size_t(y) * std::size_t(mask_w_ + 1)];
            const auto [x, fx] = invert_cdf(row, mask_w_, unit.x * row[mask_w_]);
            // Pixel (x, y) of the data window, centred in [-1, 1]^2, y down -> -v.
            const double mx = (x + fx) - 0.5 * mask_w_;
            const double my = (y + fy) - 0.5 * mask_h_;
            return {mx * mask_scale_, -my * mask_scale_};
        }
    }
    return {};
}

}  // namespace gdof
