// Square dilation of a byte mask (mask_dilate.h).
#include "image/mask_dilate.h"

#include <algorithm>
#include <vector>

namespace gdof::image_detail {

namespace {

// A small reach (a coverage rim, the pyramid's reach): per band of rows,
// each row ORed over 2m + 1 columns, then each output row the OR of 2m + 1
// of those rows. Byte ORs over whole rows, which the compiler vectorises,
// and the band's rows stay in cache; the m rows at a band's ends are done
// twice, once per band.
constexpr int kSmallReach = 24;  // beyond it the scans below cost less (4K: equal near 32)
constexpr int kBandRows = 32;

void dilate_small(std::span<const unsigned char> mask, int W, int H, int m, unsigned char* out, const Exec& exec) {
    parallel_for(exec, (H + kBandRows - 1) / kBandRows, [&, W, H, m, out](long b0, long b1) {
        // Locals, not captures by reference: a byte store may alias anything,
        // and a bound read through a reference would stop vectorisation.
        const std::size_t w = std::size_t(W);
        std::vector<unsigned char> pad(w + 2 * std::size_t(m), 0), rows((kBandRows + 2 * std::size_t(m)) * w);
        for (long b = b0; b < b1; ++b) {
            const int y0 = int(b) * kBandRows, y1 = std::min(H, y0 + kBandRows);
            const int ya = std::max(0, y0 - m), yb = std::min(H, y1 + m);
            for (int y = ya; y < yb; ++y) {
                std::copy_n(mask.data() + std::size_t(y) * w, w, pad.data() + m);
                unsigned char* r = rows.data() + std::size_t(y - ya) * w;
                std::copy_n(pad.data(), w, r);
                for (int d = 1; d <= 2 * m; ++d) {
                    const unsigned char* p = pad.data() + d;
                    for (std::size_t x = 0; x < w; ++x) r[x] |= p[x];
                }
            }
            for (int y = y0; y < y1; ++y) {
                const int lo = std::max(ya, y - m), hi = std::min(yb - 1, y + m);
                unsigned char* o = out + std::size_t(y) * w;
                std::copy_n(rows.data() + std::size_t(lo - ya) * w, w, o);
                for (int yy = lo + 1; yy <= hi; ++yy) {
                    const unsigned char* r = rows.data() + std::size_t(yy - ya) * w;
                    for (std::size_t x = 0; x < w; ++x) o[x] |= r[x];
                }
                for (std::size_t x = 0; x < w; ++x) o[x] = o[x] != 0;
            }
        }
    });
}

}  // namespace

// Every element of `rows` and `out` is written by the first (forward,
// downward) scan of its pass, so neither is zeroed first.
FrameBuffer<unsigned char> dilate_square(std::span<const unsigned char> mask, int W, int H, int m, const Exec& exec) {
    if (m >= 0 && m <= kSmallReach) {
        FrameBuffer<unsigned char> out(mask.size());  // every element written
        dilate_small(mask, W, H, m, out.data(), exec);
        return out;
    }
    FrameBuffer<unsigned char> rows(mask.size()), out(mask.size());
    parallel_for(exec, H, [&](long r0, long r1) {
        for (long y = r0; y < r1; ++y) {
            const unsigned char* in = mask.data() + std::size_t(y) * std::size_t(W);
            unsigned char* o = rows.data() + std::size_t(y) * std::size_t(W);
            int last = -1 - m;  // nearest set pixel at or left of x
            for (int x = 0; x < W; ++x) {
                if (in[x]) last = x;
                o[x] = x - last <= m ? 1 : 0;
            }
            last = W + m;
            for (int x = W - 1; x >= 0; --x) {
                if (in[x]) last = x;
                if (last - x <= m) o[x] = 1;
            }
        }
    }, 16);
    // Columns in blocks, rows walked in order (memory read row by row).
    constexpr long kCols = 256;
    parallel_for(exec, (W + kCols - 1) / kCols, [&](long b0, long b1) {
        const int xa = int(b0 * kCols), xb = std::min(W, int(b1 * kCols));
        std::vector<int> last(std::size_t(xb - xa), -1 - m);
        for (int y = 0; y < H; ++y)
            for (int x = xa; x < xb; ++x) {
                const std::size_t i = std::size_t(y) * std::size_t(W) + std::size_t(x);
                if (rows[i]) last[std::size_t(x - xa)] = y;
                out[i] = y - last[std::size_t(x - xa)] <= m ? 1 : 0;
            }
        std::fill(last.begin(), last.end(), H + m);
        for (int y = H - 1; y >= 0; --y)
            for (int x = xa; x < xb; ++x) {
                const std::size_t i = std::size_t(y) * std::size_t(W) + std::size_t(x);
                if (rows[i]) last[std::size_t(x - xa)] = y;
                if (last[std::size_t(x - xa)] - y <= m) out[i] = 1;
            }
    });
    return out;
}

}  // namespace gdof::image_detail
