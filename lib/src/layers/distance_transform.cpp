// Exact Euclidean distance transform of a binary mask (layers_internal.h).
//
// Felzenszwalb & Huttenlocher, "Distance Transforms of Sampled Functions":
// squared distances are separable. For a binary mask the column pass is the
// distance to the nearest set pixel of the column (two scans down and up a
// row at a time, so memory is read row by row); the row pass is the lower
// envelope of parabolas g(p) + (x - p)^2, with the parabolas' intersections
// compared as exact integer fractions (no division, no rounding). Rows are
// independent, so they run in parallel with the same bits.
//
// Inside a run of set pixels only the run's two ends matter to the rest of
// the row (a pixel beyond the run is nearer to the end than to any pixel
// inside), and the run's own pixels are at 0: the envelope skips the inner
// ones, which are most of a big slice's mask. With a bound, columns count
// only up to it, so fewer parabolas enter the envelope.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "layers/layers_internal.h"

namespace gdof::layers_detail {

namespace {

// The row pass over one row of column distances g (`none`: no set pixel in
// the column): out[q] = sqrt(min_p g[p]^2 + (q - p)^2), +inf if none or
// above `bound`.
template <typename G>
struct RowPass {
    std::vector<int> v;  // parabola apexes of the envelope
    // The intersection of parabolas q and p (p < q) lies at
    // s = ((f[q] + q^2) - (f[p] + p^2)) / (2 (q - p)), f = g^2: numerator
    // and denominator kept apart.
    struct Frac {
        std::int64_t num, den;  // den > 0
    };
    std::vector<Frac> z;  // z[k]: where parabola v[k] starts to be the lowest

    void run(const G* g, int m, G none, double bound, float* out) {
        v.resize(std::size_t(m));
        z.resize(std::size_t(m));
        int k = -1;
        auto f = [&](int p) { return std::int64_t(g[p]) * std::int64_t(g[p]); };
        auto meet = [&](int q, int p) {
            const std::int64_t a = f(q) + std::int64_t(q) * q;
            const std::int64_t b = f(p) + std::int64_t(p) * p;
            return Frac{a - b, 2 * std::int64_t(q - p)};
        };
        // s <= t for fractions with positive denominators.
        auto le = [](const Frac& s, const Frac& t) { return s.num * t.den <= t.num * s.den; };
        for (int q = 0; q < m; ++q) {
            if (g[q] == none) continue;
            if (g[q] == 0 && q > 0 && g[q - 1] == 0 && q + 1 < m && g[q + 1] == 0) continue;  // inside a run
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
            if (g[q] == 0) {  // a set pixel (j moves on lazily: the envelope's starts only grow)
                out[q] = 0.0f;
                continue;
            }
            // Move on while the next parabola starts at or before q.
            while (j < k && z[std::size_t(j) + 1].num <= std::int64_t(q) * z[std::size_t(j) + 1].den) ++j;
            const int p = v[std::size_t(j)];
            const std::int64_t d2 = std::int64_t(q - p) * (q - p) + f(p);
            // Below 2^24 the float is exact and its float square root the same
            // as the double one rounded (double has more than 2 x 24 + 2 bits).
            const float d = d2 < (std::int64_t(1) << 24) ? std::sqrt(float(d2)) : float(std::sqrt(double(d2)));
            out[q] = double(d) <= bound ? d : std::numeric_limits<float>::infinity();
        }
    }
};

// Column distances in G (16 bits where the height allows: half the memory
// traffic of 32), then the row pass.
template <typename G>
void transform(std::span<const unsigned char> mask, int width, int height, FrameBuffer<float>& out, const Exec& exec,
               double bound) {
    const std::size_t n = std::size_t(width) * std::size_t(height);
    const std::size_t W = std::size_t(width);
    constexpr G none = std::numeric_limits<G>::max();
    // A column distance above `cap` cannot give a distance within the bound:
    // it counts as no set pixel in the column.
    const bool bounded = bound >= 0.0 && bound < 16384.0;
    const G cap = bounded ? G(std::ceil(bound) + 1) : G(none - 1);
    // Column pass, in blocks of columns: vertical distances row by row,
    // down then up (every element written).
    FrameBuffer<G> g(n);
    constexpr long kCols = 256;
    parallel_for(exec, (long(W) + kCols - 1) / kCols, [&](long b0, long b1) {
        const std::size_t xa = std::size_t(b0 * kCols), xb = std::min(W, std::size_t(b1 * kCols));
        for (std::size_t x = xa; x < xb; ++x) g[x] = mask[x] ? G(0) : none;
        for (int y = 1; y < height; ++y) {
            const std::size_t r = std::size_t(y) * W;
            for (std::size_t x = xa; x < xb; ++x) {
                const G up = g[r - W + x];
                g[r + x] = mask[r + x] ? G(0) : (up >= cap ? none : G(up + 1));
            }
        }
        for (int y = height - 2; y >= 0; --y) {
            const std::size_t r = std::size_t(y) * W;
            for (std::size_t x = xa; x < xb; ++x) {
                const G down = g[r + W + x];  // already final
                if (down < cap && G(down + 1) < g[r + x]) g[r + x] = G(down + 1);
            }
        }
    });
    const double row_bound = bounded ? bound : std::numeric_limits<double>::infinity();
    parallel_for(exec, height, [&](long y0, long y1) {
        RowPass<G> pass;
        for (long y = y0; y < y1; ++y)
            pass.run(g.data() + std::size_t(y) * W, width, none, row_bound, out.data() + std::size_t(y) * W);
    }, 16);
}

}  // namespace

void distance_transform(std::span<const unsigned char> mask, int width, int height, FrameBuffer<float>& out,
                        const Exec& exec, double bound) {
    out.resize(std::size_t(width) * std::size_t(height));  // every element written by the row pass
    if (out.empty()) return;
    if (height < 65535)
        transform<std::uint16_t>(mask, width, height, out, exec, bound);
    else
        transform<std::int32_t>(mask, width, height, out, exec, bound);
}

}  // namespace gdof::layers_detail
