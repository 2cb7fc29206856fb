#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "gdof/fill.h"

using namespace gdof;

TEST(fill, ConstantStaysConstantAndKnownPixelsAreKept) {
    const int W = 37, H = 21;
    std::vector<float> v(W * H, 0.0f), w(W * H, 0.0f);
    for (int y = 5; y < 12; ++y)
        for (int x = 20; x < 30; ++x) {
            v[y * W + x] = 3.25f;
            w[y * W + x] = 1.0f;
        }
    v[0] = -7.0f;  // garbage where the weight is 0 must be overwritten
    const Roi win{0, 0, W, H};
    for (FillGrids grids : {FillGrids::Single, FillGrids::Spun}) {
        std::vector<float> f = v;
        ASSERT_TRUE(push_pull_fill(ImageView::planar(f.data(), 1, win), ConstImageView::planar(w.data(), 1, win), Exec{},
                                   grids));
        for (float x : f) EXPECT_FLOAT_EQ(x, 3.25f);
    }
}

// What a fill continues behind a hidden strip follows the picture when it
// moves (a pan; a foreground moving over a background). A step from 0 to 1
// hidden by a 26 px strip centred on it, moved by 0..31 px: where the fill
// puts the step (the strip's end minus the fill's sum along a row) should sit
// at the strip's middle, whatever the offset, as the picture is symmetric
// there. One pyramid puts it on its own cell boundaries: 5 px either side
// of the middle, as the offset moves; four offset grids (Spun) keep it
// within 2 px (1.5).
TEST(fill, SpunGridsKeepAHiddenEdgeWhereThePictureMovesIt) {
    const int W = 160, H = 40, half = 13;
    const Roi win{0, 0, W, H};
    for (FillGrids grids : {FillGrids::Single, FillGrids::Spun}) {
        double lo = 1e9, hi = -1e9;
        for (int shift = 0; shift < 32; ++shift) {
            const int edge = 60 + shift;
            std::vector<float> v(W * H), w(W * H);
            for (int y = 0; y < H; ++y)
                for (int x = 0; x < W; ++x) {
                    const bool hidden = x >= edge - half && x < edge + half;
                    v[y * W + x] = hidden ? 0.0f : (x < edge ? 0.0f : 1.0f);
                    w[y * W + x] = hidden ? 0.0f : 1.0f;
                }
            ASSERT_TRUE(push_pull_fill(ImageView::planar(v.data(), 1, win), ConstImageView::planar(w.data(), 1, win),
                                       Exec{}, grids));
            for (int y : {0, H / 2, H - 1}) {
                double sum = 0.0;
                for (int x = edge - half; x < edge + half; ++x) sum += v[y * W + x];
                const double at = double(edge + half) - sum - double(edge);  // 0: the strip's middle
                lo = std::min(lo, at);
                hi = std::max(hi, at);
            }
        }
        std::printf("grids %d: the filled step %.2f .. %.2f px from the strip's middle\n", int(grids), lo, hi);
        if (grids == FillGrids::Spun) {
            EXPECT_LT(std::max(-lo, hi), 2.0);
        } else {
            EXPECT_GT(hi - lo, 4.0);  // the effect the spins remove
        }
    }
}

TEST(fill, ExtrapolationIsSmoothAndBetweenTheKnownValues) {
    // Two known blocks, 1 on the left and 5 on the right: the fill stays in
    // [1, 5], is monotonic in x along the middle row, and keeps the blocks.
    const int W = 64, H = 16;
    std::vector<float> v(W * H, 0.0f), w(W * H, 0.0f);
    for (int y = 0; y < H; ++y) {
        for (int x = 0; x < 8; ++x) {
            v[y * W + x] = 1.0f;
            w[y * W + x] = 1.0f;
        }
        for (int x = 56; x < 64; ++x) {
            v[y * W + x] = 5.0f;
            w[y * W + x] = 1.0f;
        }
    }
    const Roi win{0, 0, W, H};
    ASSERT_TRUE(push_pull_fill(ImageView::planar(v.data(), 1, win), ConstImageView::planar(w.data(), 1, win)));
    for (int x = 0; x < W; ++x) {
        const float a = v[8 * W + x];
        EXPECT_GE(a, 1.0f - 1e-5f);
        EXPECT_LE(a, 5.0f + 1e-5f);
        if (x > 0) {
            EXPECT_GE(a, v[8 * W + x - 1] - 1e-5f) << x;
        }
    }
    EXPECT_EQ(v[8 * W + 3], 1.0f);
    EXPECT_EQ(v[8 * W + 60], 5.0f);
    EXPECT_GT(v[8 * W + 40], v[8 * W + 20]);
}

TEST(fill, NoWeightMeansNothingToFill) {
    std::vector<float> v(6, 2.0f), w(6, 0.0f);
    const Roi win{0, 0, 3, 2};
    EXPECT_FALSE(push_pull_fill(ImageView::planar(v.data(), 1, win), ConstImageView::planar(w.data(), 1, win)));
    for (float x : v) EXPECT_EQ(x, 2.0f);
}

namespace {

// Two planes with a known block in the middle of a W x H window.
struct FillCase {
    static constexpr int W = 23, H = 11;
    Roi win{5, -3, 5 + W, -3 + H};
    std::vector<float> planes = std::vector<float>(2 * std::size_t(W) * H, 0.0f), weight = std::vector<float>(std::size_t(W) * H, 0.0f);
    FillCase() {
        for (int y = 3; y < 8; ++y)
            for (int x = 6; x < 15; ++x) {
                const std::size_t i = std::size_t(y) * W + std::size_t(x);
                planes[i] = float(x) * 0.25f;
                planes[std::size_t(W) * H + i] = float(y) - 3.5f;
                weight[i] = 0.5f + 0.05f * float(x - 6);
            }
    }
    ImageView view() { return ImageView::planar(planes.data(), 2, win); }
    ConstImageView weight_view() const { return ConstImageView::planar(weight.data(), 1, win); }
};

}  // namespace

TEST(fill, InterleavedAndCroppedViewsFillLikePlanarOnes) {
    FillCase ref;
    ASSERT_TRUE(push_pull_fill(ref.view(), ref.weight_view()));

    // The same planes interleaved (x stride 2) give the same bits.
    FillCase il;
    std::vector<float> inter(2 * il.weight.size());
    for (std::size_t i = 0; i < il.weight.size(); ++i)
        for (std::size_t c = 0; c < 2; ++c) inter[2 * i + c] = il.planes[c * il.weight.size() + i];
    const ImageView iv = ImageView::interleaved(inter.data(), 2, il.win, 2 * FillCase::W);
    ASSERT_TRUE(push_pull_fill(iv, il.weight_view()));
    for (int c = 0; c < 2; ++c)
        for (int y = il.win.y0; y < il.win.y1; ++y)
            for (int x = il.win.x0; x < il.win.x1; ++x) ASSERT_EQ(iv.at(c, x, y), ref.view().at(c, x, y)) << c << " " << x << "," << y;

    // A window cropped out of a larger buffer: the same bits inside, the
    // pixels around it untouched.
    const Roi big{0, -10, 40, 20};
    std::vector<float> bigp(2 * big.npixels(), 42.0f), bigw(big.npixels(), 0.0f);
    const ImageView bv = ImageView::planar(bigp.data(), 2, big);
    const ImageView bw = ImageView::planar(bigw.data(), 1, big);
    FillCase src;
    for (int c = 0; c < 2; ++c)
        for (int y = src.win.y0; y < src.win.y1; ++y)
            for (int x = src.win.x0; x < src.win.x1; ++x) {
                bv.at(c, x, y) = src.view().at(c, x, y);
                if (c == 0) bw.at(0, x, y) = src.weight_view().at(0, x, y);
            }
    ASSERT_TRUE(push_pull_fill(bv.cropped(src.win), bw.cropped(src.win)));
    for (int c = 0; c < 2; ++c)
        for (int y = big.y0; y < big.y1; ++y)
            for (int x = big.x0; x < big.x1; ++x)
                ASSERT_EQ(bv.at(c, x, y), src.win.contains(x, y) ? ref.view().at(c, x, y) : 42.0f) << c << " " << x << "," << y;
}

TEST(fill, AWeightOfAnotherShapeFillsNothing) {
    FillCase f;
    const std::vector<float> before = f.planes;
    const Roi other{f.win.x0, f.win.y0, f.win.x1 - 1, f.win.y1};
    EXPECT_FALSE(push_pull_fill(f.view(), ConstImageView::planar(f.weight.data(), 1, other)));
    EXPECT_FALSE(push_pull_fill(f.view(), ConstImageView{f.weight.data(), 2, f.win, 0, 1, FillCase::W}));
    EXPECT_FALSE(push_pull_fill(f.view(), ConstImageView{nullptr, 1, f.win, 0, 1, FillCase::W}));
    EXPECT_EQ(f.planes, before);
    EXPECT_TRUE(push_pull_fill(f.view(), f.weight_view()));  // the same call with the right weight fills
    EXPECT_NE(f.planes, before);
}

// A fill is local: a pixel next to known pixels takes their values, not an
// average over a coarse cell that reaches a bright spot far away. A dark
// ceiling (0.001) with a lamp (20) in it, unknown above row 32 (a hole as
// tall as a pyramid cell, so every level up to 32 px holds nothing of it):
// 60 px beside the lamp, the first unknown row takes the ceiling's value and
// the second stays within 5x of it. Bilinear taps that ignored the coarse
// pixels' own weights gave these rows 0.085 and 0.13 (85x and 130x), a
// ghost of the lamp over a layer's hidden part.
TEST(fill, APixelNextToKnownOnesTakesTheirValueNotAFarHighlights) {
    const int W = 128, H = 96;
    std::vector<float> v(W * H, 0.0f), w(W * H, 0.0f);
    for (int y = 32; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const bool lamp = y >= 38 && y < 54 && x >= 90 && x < 110;
            v[y * W + x] = lamp ? 20.0f : 0.001f;
            w[y * W + x] = 1.0f;
        }
    const Roi win{0, 0, W, H};
    ASSERT_TRUE(push_pull_fill(ImageView::planar(v.data(), 1, win), ConstImageView::planar(w.data(), 1, win)));
    for (int x = 20; x < 40; ++x) {
        EXPECT_NEAR(v[31 * W + x], 0.001f, 0.0002f) << "x " << x;
        EXPECT_LT(v[30 * W + x], 0.005f) << "x " << x;
    }
}

TEST(fill, OnlyTheWantedPixelsAreFilledWithTheWholeFillsBits) {
    // Scattered known pixels (partial weights) in two planes; a band of
    // wanted pixels and a few lone ones (their coarse taps are all the fill
    // computes). Each wanted unknown pixel gets exactly the whole fill's
    // value although the unknown pixels held NaN instead of -1 (unknown values
    // are never read: callers leave them unset), every other unknown pixel
    // keeps what it held, known pixels keep theirs; a mask of the wrong size
    // is refused.
    const int W = 83, H = 47;
    const std::size_t n = std::size_t(W) * H;
    std::vector<float> v(2 * n, -1.0f), w(n, 0.0f);
    std::vector<unsigned char> wanted(n, 0);
    unsigned s = 7;
    auto next = [&] { return (s = s * 1103515245u + 12345u) >> 8 & 0xffff; };
    for (std::size_t i = 0; i < n; ++i) {
        if (next() % 9 == 0) {
            w[i] = 0.25f + float(next() % 4) * 0.25f;
            v[i] = float(next() % 100);
            v[n + i] = float(next() % 50) - 25.0f;
        }
        const int x = int(i % W), y = int(i / W);
        wanted[i] = std::abs(x - 2 * y) < 9 || (x % 29 == 3 && y % 17 == 5) ? 1 : 0;
    }
    const Roi win{0, 0, W, H};
    for (FillGrids grids : {FillGrids::Single, FillGrids::Spun}) {
        SCOPED_TRACE(grids == FillGrids::Spun ? "spun" : "single");
        std::vector<float> whole = v, part = v;
        for (int c = 0; c < 2; ++c)
            for (std::size_t i = 0; i < n; ++i)
                if (!(w[i] > 0.0f)) part[std::size_t(c) * n + i] = std::nanf("");
        ASSERT_TRUE(push_pull_fill(ImageView::planar(whole.data(), 2, win), ConstImageView::planar(w.data(), 1, win),
                                   Exec{}, grids));
        ASSERT_TRUE(push_pull_fill(ImageView::planar(part.data(), 2, win), ConstImageView::planar(w.data(), 1, win),
                                   std::span<const unsigned char>(wanted), Exec{}, grids));
        std::size_t filled = 0;
        for (int c = 0; c < 2; ++c)
            for (std::size_t i = 0; i < n; ++i) {
                const std::size_t k = std::size_t(c) * n + i;
                if (w[i] > 0.0f) {
                    EXPECT_EQ(part[k], v[k]) << "known " << i;
                } else if (wanted[i]) {
                    EXPECT_EQ(part[k], whole[k]) << "wanted " << i;
                    ++filled;
                } else {
                    EXPECT_TRUE(std::isnan(part[k])) << "not wanted " << i;
                }
            }
        EXPECT_GT(filled, 500u);
    }
    std::vector<float> part = v;
    std::vector<unsigned char> short_mask(n - 1, 1);
    EXPECT_FALSE(push_pull_fill(ImageView::planar(part.data(), 2, win), ConstImageView::planar(w.data(), 1, win),
                                std::span<const unsigned char>(short_mask)));
}
