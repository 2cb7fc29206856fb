// Square (chessboard) dilation of a byte mask against a brute-force scan of
// each pixel's neighbourhood, for small reaches (row and column ORs over
// bands of rows) and large ones (nearest-set scans), on masks of runs and
// scattered pixels, across band boundaries and for 1 and 2 threads.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "image/mask_dilate.h"

using namespace gdof;
using gdof::image_detail::dilate_square;

namespace {

std::vector<unsigned char> brute_force(const std::vector<unsigned char>& mask, int W, int H, int m) {
    std::vector<unsigned char> out(mask.size(), 0);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x)
            for (int v = std::max(0, y - m); v <= std::min(H - 1, y + m) && !out[std::size_t(y) * W + x]; ++v)
                for (int u = std::max(0, x - m); u <= std::min(W - 1, x + m); ++u)
                    if (mask[std::size_t(v) * W + u]) {
                        out[std::size_t(y) * W + x] = 1;
                        break;
                    }
    return out;
}

// Rectangles of set pixels (values other than 1 too: any non-zero is set)
// and scattered single pixels.
std::vector<unsigned char> random_mask(std::mt19937& rng, int W, int H) {
    std::vector<unsigned char> mask(std::size_t(W) * H, 0);
    const int nrect = int(rng() % 6);
    for (int k = 0; k < nrect; ++k) {
        const int x0 = int(rng() % W), y0 = int(rng() % H);
        const int x1 = std::min(W, x0 + 1 + int(rng() % 40)), y1 = std::min(H, y0 + 1 + int(rng() % 40));
        for (int y = y0; y < y1; ++y)
            for (int x = x0; x < x1; ++x) mask[std::size_t(y) * W + x] = (unsigned char)(1 + rng() % 200);
    }
    const int ndots = int(rng() % 30);
    for (int k = 0; k < ndots; ++k) mask[std::size_t(rng() % H) * W + rng() % W] = 1;
    return mask;
}

}  // namespace

TEST(dilate_square, EqualsBruteForceForSmallAndLargeReaches) {
    std::mt19937 rng(5);
    for (int trial = 0; trial < 60; ++trial) {
        const int W = 1 + int(rng() % 150), H = 1 + int(rng() % 110);  // several bands of rows
        const int m = trial % 14;                                          // 0..13: both paths
        const std::vector<unsigned char> mask = random_mask(rng, W, H);
        const std::vector<unsigned char> want = brute_force(mask, W, H, m);
        for (int threads : {1, 2}) {
            Exec exec;
            exec.nthreads = threads;
            const FrameBuffer<unsigned char> got = dilate_square(mask, W, H, m, exec);
            ASSERT_EQ(got.size(), want.size());
            for (std::size_t i = 0; i < want.size(); ++i)
                ASSERT_EQ(int(got[i]), int(want[i])) << "m " << m << ", " << W << "x" << H << ", pixel " << i % W
                                                     << ", " << i / W << ", " << threads << " thread(s)";
        }
    }
}
