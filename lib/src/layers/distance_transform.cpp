// Exact Euclidean distance transform of a binary mask (layers_internal.h).
//
// Felzenszwalb & Huttenlocher, "Distance Transforms of Sampled Functions":
// squared distances are separable. For a binary mask the column pass is the
// distance to the nearest set pixel of the column (two scans down and up a
// row at a time, so memory is read row by row); the row pass is the lower
// envelope of parabolas g(p) + (x - p)^2, with the parabolas' intersections
// compared as exact integer fractions (no division, no rounding). Rows are
// independent, so they run in parallel with the same bits.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "layers/layers_internal.h"

namespace gdof::layers_detail {

namespace {

constexpr std::int32_t kNone = std::numeric_limits<std::int32_t>::max();  // no set pixel in the column

// The row pass over one row of squared column distances f (kNone: none):
// out[q] = min_p f[p] + (q - p)^2, as a float distance (+inf if none).
struct RowPass {
    std::vector<int> v;  // parabola apexes of the envelope
    // The intersection of parabolas q and p (p < q) lies at
    // s = ((f[q] + q^2) - (f[p] + p^2)) / (2 (q - p)): numerator and
    // denominator kept apart.
    struct Frac {
        std::int64_t num, den;  // den > 0
    };
    std::vector<Frac> z;  // z[k]: where parabola v[k] starts to be the lowest

    void run(const std::int32_t* f, int m, float* out) {
        v.resize(std::size_t(m));
        z.resize(std::size_t(m));
        int k = -1;
        auto meet = [&](int q, int p) {
            const std::int64_t a = std::int64_t(f[q]) + std::int64_t(q) * q;
            const std::int64_t b = std::int64_t(f[p]) + std::int64_t(p) * p;
            return Frac{a - b, 2 * std::int64_t(q - p)};
        };
        // s <= t for fractions with positive denominators.
        auto le = [](const Frac& s, const Frac& t) { return s.num * t.den <= t.num * s.den; };
        for (int q = 0; q < m; ++q) {
            if (f[q] == kNone) continue;
            if (k < 0) {
                v[0] = q;
                k = 0;
                continue;
            }
            Frac s = meet(q, v[std::size_t(k)]);
            while (k > 0 && le(s, z[std::size_t(k)])) {
                --k;
                s = meet(q, v[std::size_t(k)]);
            }
            ++k;
            v[std::size_t(k)] = q;
            z[std::size_t(k)] = s;
        }
        if (k < 0) {
            std::fill(out, out + m, std::numeric_limits<float>::infinity());
            return;
        }
        int j = 0;
        for (int q = 0; q < m; ++q) {
            // Move on while the next parabola starts at or before q.
            while (j < k && z[std::size_t(j) + 1].num <= std::int64_t(q) * z[std::size_t(j) + 1].den) ++j;
            const int p = v[std::size_t(j)];
            const std::int64_t d2 = std::int64_t(q - p) * (q - p) + f[p];
            // Below 2^24 the float is exact and its float square root the same
            // as the double one rounded (double has more than 2 x 24 + 2 bits).
            out[q] = d2 < (std::int64_t(1) << 24) ? std::sqrt(float(d2)) : float(std::sqrt(double(d2)));
        }
    }
};

}  // namespace

void distance_transform(std::span<const unsigned char> mask, int width, int height, FrameBuffer<float>& out,
                        const Exec& exec) {
    const std::size_t n = std::size_t(width) * std::size_t(height);
    const std::size_t W = std::size_t(width);
    out.resize(n);  // every element written by the row pass
    if (n == 0) return;
    // Column pass, in blocks of columns: vertical distances row by row,
    // down then up, then squared (every element written).
    FrameBuffer<std::int32_t> g(n);
    constexpr long kCols = 256;
    parallel_for(exec, (long(W) + kCols - 1) / kCols, [&](long b0, long b1) {
        const std::size_t xa = std::size_t(b0 * kCols), xb = std::min(W, std::size_t(b1 * kCols));
        for (std::size_t x = xa; x < xb; ++x) g[x] = mask[x] ? 0 : kNone;
        for (int y = 1; y < height; ++y) {
            const std::size_t r = std::size_t(y) * W;
            for (std::size_t x = xa; x < xb; ++x) {
                const std::int32_t up = g[r - W + x];
                g[r + x] = mask[r + x] ? 0 : (up == kNone ? kNone : up + 1);
            }
        }
        for (int y = height - 1; y >= 0; --y) {
            const std::size_t r = std::size_t(y) * W;
            for (std::size_t x = xa; x < xb; ++x) {
                std::int32_t& d = g[r + x];
                if (y + 1 < height) {
                    const std::int32_t down = g[r + W + x];  // already final, not yet squared
                    if (down != kNone && down + 1 < d) d = down + 1;
                }
            }
            if (y + 1 < height) {  // the row below is final: square it
                const std::size_t rb = r + W;
                for (std::size_t x = xa; x < xb; ++x)
                    if (g[rb + x] != kNone) g[rb + x] *= g[rb + x];
            }
        }
        for (std::size_t x = xa; x < xb; ++x)
            if (g[x] != kNone) g[x] *= g[x];
    });
    // Row pass.
    parallel_for(exec, height, [&](long y0, long y1) {
        RowPass pass;
        for (long y = y0; y < y1; ++y) pass.run(g.data() + std::size_t(y) * W, width, out.data() + std::size_t(y) * W);
    }, 16);
}

}  // namespace gdof::layers_detail
