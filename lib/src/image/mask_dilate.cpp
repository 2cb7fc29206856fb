// Square dilation of a byte mask (mask_dilate.h).
#include "image/mask_dilate.h"

#include <algorithm>

namespace gdof::image_detail {

// Every element of `rows` and `out` is written by the first (forward,
// downward) scan of its pass, so neither is zeroed first.
FrameBuffer<unsigned char> dilate_square(std::span<const unsigned char> mask, int W, int H, int m, const Exec& exec) {
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
