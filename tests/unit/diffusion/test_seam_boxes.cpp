// Seams far apart are spread over boxes of their own (defocus_seams.cpp).
// A layer with three pieces of seam, two side by side and one below: with
// a spread that reaches one pixel (a 3x3 box blur, zero outside its
// planes), continuing the seams over a small margin (each piece in its own
// box) must give the same bits as over a margin wide enough that one box
// holds all three (what the seams were spread over before), and the small
// margin's spreads must run over three disjoint boxes, each holding its
// piece grown by the margin.
#include <gtest/gtest.h>

#include <utility>
#include <vector>

#include "diffusion/defocus_internal.h"

using namespace gdof;
using namespace gdof::defocus_detail;

namespace {

constexpr int kW = 96, kH = 96;
const Roi kWin{0, 0, kW, kH};
// The three pieces: top left, top right (the same rows), bottom right.
const Roi kPieces[3] = {{10, 10, 16, 16}, {70, 12, 76, 18}, {72, 70, 78, 76}};

bool in_seam(int x, int y) {
    for (const Roi& p : kPieces)
        if (p.contains(x, y)) return true;
    return false;
}

Layer seam_layer() {
    Layer L;
    L.image = Image::with_channels({"R", "G", "B", "A", "Z"}, kWin);
    L.seam.assign(kWin.npixels(), 0);
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            L.image.at(0, x, y) = 0.2f + 0.006f * float(x);
            L.image.at(1, x, y) = 0.7f - 0.005f * float(y);
            L.image.at(2, x, y) = in_seam(x, y) ? 0.9f : 0.1f;
            L.image.at(3, x, y) = 1.0f;
            L.image.at(4, x, y) = 3.0f;
            if (in_seam(x, y)) {
                L.seam[std::size_t(y) * kW + std::size_t(x)] = 1;
                L.seam_box = unite(L.seam_box, Roi{x, y, x + 1, y + 1});
            }
        }
    return L;
}

// The layer's own spread, as the defocus would hand it over: some colour
// and a coverage between 0.5 and 1.
DiffusedLayer spread_layer() {
    DiffusedLayer d;
    d.work = kWin;
    d.rgba = Image::with_channels({"R", "G", "B", "A"}, kWin);
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            const float a = 0.5f + 0.5f * float((x * 7 + y * 3) % 11) / 10.0f;
            d.rgba.at(0, x, y) = a * (0.3f + 0.004f * float(x));
            d.rgba.at(1, x, y) = a * (0.5f + 0.003f * float(y));
            d.rgba.at(2, x, y) = a * 0.4f;
            d.rgba.at(3, x, y) = a;
        }
    return d;
}

// A 3x3 box blur of the four planes, zero outside their window; the
// windows it was called on.
SpreadSeams box_blur(std::vector<Roi>& calls) {
    return [&calls](const ImageView& planes, const RadiusMap&, const Exec&) {
        calls.push_back(planes.window);
        const Roi w = planes.window;
        for (int c = 0; c < 4; ++c) {
            std::vector<float> src(w.npixels());
            for (int y = w.y0; y < w.y1; ++y)
                for (int x = w.x0; x < w.x1; ++x) src[std::size_t(y - w.y0) * w.width() + (x - w.x0)] = planes.at(c, x, y);
            for (int y = w.y0; y < w.y1; ++y)
                for (int x = w.x0; x < w.x1; ++x) {
                    float s = 0.0f;
                    for (int dy = -1; dy <= 1; ++dy)
                        for (int dx = -1; dx <= 1; ++dx)
                            if (w.contains(x + dx, y + dy))
                                s += src[std::size_t(y + dy - w.y0) * w.width() + (x + dx - w.x0)];
                    planes.at(c, x, y) = s / 9.0f;
                }
        }
        return Status::ok();
    };
}

}  // namespace

TEST(seam_boxes, PiecesFarApartAreSpreadInBoxesOfTheirOwnWithTheSameBits) {
    const Layer L = seam_layer();
    const RadiusMap radius(kWin.npixels(), 2.0f);
    constexpr int kSmall = 4, kWide = 40;

    std::vector<Roi> small_calls, wide_calls;
    DiffusedLayer by_piece = spread_layer(), whole = spread_layer();
    ASSERT_TRUE(continue_across_seams(L, radius, kWin, kSmall, box_blur(small_calls), by_piece, Exec{}));
    ASSERT_TRUE(continue_across_seams(L, radius, kWin, kWide, box_blur(wide_calls), whole, Exec{}));

    // The wide margin: one box, the pieces' box grown, within the layer.
    ASSERT_EQ(wide_calls.size(), 1u);
    EXPECT_EQ(wide_calls[0], intersect(L.seam_box.grown(kWide), kWin));
    // The small one: a box per piece, each its piece grown, disjoint.
    ASSERT_EQ(small_calls.size(), 3u);
    for (const Roi& p : kPieces) {
        int holding = 0;
        for (const Roi& b : small_calls) holding += b == intersect(p.grown(kSmall), kWin) ? 1 : 0;
        EXPECT_EQ(holding, 1) << "piece " << p.x0 << "," << p.y0;
    }
    for (std::size_t i = 0; i < small_calls.size(); ++i)
        for (std::size_t j = i + 1; j < small_calls.size(); ++j)
            EXPECT_TRUE(intersect(small_calls[i], small_calls[j]).empty()) << i << " " << j;

    // The same bits everywhere, and the seams did change the colour.
    int changed = 0;
    const DiffusedLayer before = spread_layer();
    for (int c = 0; c < 4; ++c)
        for (int y = 0; y < kH; ++y)
            for (int x = 0; x < kW; ++x) {
                ASSERT_EQ(by_piece.rgba.at(c, x, y), whole.rgba.at(c, x, y)) << c << " at " << x << "," << y;
                changed += by_piece.rgba.at(c, x, y) != before.rgba.at(c, x, y) ? 1 : 0;
            }
    EXPECT_GT(changed, 3 * 36) << "the seams' colour is continued from the layer's other pixels";
}

// Pieces with at most twice the margin between them share a box: their
// grown boxes would overlap, and a pixel between them would take each
// piece's correction over the other's. Pieces 0 and 1 have 54 empty
// columns between them, pieces 1 and 2 52 empty rows.
TEST(seam_boxes, PiecesWithinTwiceTheMarginShareABox) {
    const Layer L = seam_layer();
    const RadiusMap radius(kWin.npixels(), 2.0f);
    std::vector<Roi> wide_calls;
    DiffusedLayer whole = spread_layer();
    ASSERT_TRUE(continue_across_seams(L, radius, kWin, 40, box_blur(wide_calls), whole, Exec{}));
    for (const auto& [margin, boxes] : {std::pair{26, 2u}, std::pair{25, 3u}, std::pair{27, 1u}}) {
        std::vector<Roi> calls;
        DiffusedLayer d = spread_layer();
        ASSERT_TRUE(continue_across_seams(L, radius, kWin, margin, box_blur(calls), d, Exec{}));
        EXPECT_EQ(calls.size(), boxes) << "margin " << margin;
        for (std::size_t i = 0; i < calls.size(); ++i)
            for (std::size_t j = i + 1; j < calls.size(); ++j)
                EXPECT_TRUE(intersect(calls[i], calls[j]).empty()) << "margin " << margin;
        for (int c = 0; c < 4; ++c)
            for (int y = 0; y < kH; ++y)
                for (int x = 0; x < kW; ++x)
                    ASSERT_EQ(d.rgba.at(c, x, y), whole.rgba.at(c, x, y)) << "margin " << margin << " at " << x << "," << y;
    }
}

// Specks of seam scattered far apart (a noisy surface): more pieces than
// boxes are worth spreading one by one go over the one box around them all,
// with the same bits.
TEST(seam_boxes, ScatteredSpecksShareOneBox) {
    Layer L = seam_layer();
    std::fill(L.seam.begin(), L.seam.end(), 0);
    L.seam_box = Roi{};
    int specks = 0;
    for (int y = 2; y < kH; y += 12)
        for (int x = 2; x < kW; x += 12) {
            L.seam[std::size_t(y) * kW + std::size_t(x)] = 1;
            L.seam_box = unite(L.seam_box, Roi{x, y, x + 1, y + 1});
            ++specks;
        }
    ASSERT_GT(specks, 32);
    const RadiusMap radius(kWin.npixels(), 2.0f);
    std::vector<Roi> few_calls, one_calls;
    DiffusedLayer few = spread_layer(), one = spread_layer();
    ASSERT_TRUE(continue_across_seams(L, radius, kWin, 2, box_blur(few_calls), few, Exec{}));
    ASSERT_TRUE(continue_across_seams(L, radius, kWin, 6, box_blur(one_calls), one, Exec{}));
    EXPECT_EQ(few_calls.size(), 1u) << "64 specks 11 px apart, margin 2";
    EXPECT_EQ(one_calls.size(), 1u) << "margin 6: they touch";
    for (int c = 0; c < 4; ++c)
        for (int y = 0; y < kH; ++y)
            for (int x = 0; x < kW; ++x) ASSERT_EQ(few.rgba.at(c, x, y), one.rgba.at(c, x, y)) << x << "," << y;
}
