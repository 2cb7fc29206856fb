#include <gtest/gtest.h>

#include <vector>

#include "gdof/deep.h"
#include "gdof/image.h"
#include "gdof/math.h"

using namespace gdof;

TEST(Roi, IntersectUniteAndEmpty) {
    Roi a{-10, -5, 10, 5}, b{5, 0, 20, 30};
    EXPECT_EQ(intersect(a, b), (Roi{5, 0, 10, 5}));
    EXPECT_EQ(unite(a, b), (Roi{-10, -5, 20, 30}));
    EXPECT_TRUE(intersect(a, Roi{50, 50, 60, 60}).empty());
    EXPECT_EQ(unite(Roi{}, b), b);
    EXPECT_EQ(a.npixels(), 200u);
}

TEST(TileGrid, CoversTheWindowOnceRowMajorWithClippedEdges) {
    const Roi w{-7, 3, 13, 14};  // 20 x 11, negative origin
    const TileGrid g(w, 8);
    EXPECT_EQ(g.nx, 3);
    EXPECT_EQ(g.ny, 2);
    ASSERT_EQ(g.count(), 6);
    EXPECT_EQ(g.tile(0), (Roi{-7, 3, 1, 11}));
    EXPECT_EQ(g.tile(1), (Roi{1, 3, 9, 11}));     // row-major: the next tile is to the right
    EXPECT_EQ(g.tile(2), (Roi{9, 3, 13, 11}));    // last column clipped
    EXPECT_EQ(g.tile(5), (Roi{9, 11, 13, 14}));   // last row and column clipped
    std::vector<int> hits(w.npixels(), 0);
    for (long t = 0; t < g.count(); ++t) {
        const Roi r = g.tile(t);
        EXPECT_FALSE(r.empty()) << t;
        EXPECT_EQ(intersect(r, w), r) << t;
        for (int y = r.y0; y < r.y1; ++y)
            for (int x = r.x0; x < r.x1; ++x) ++hits[std::size_t(y - w.y0) * std::size_t(w.width()) + std::size_t(x - w.x0)];
    }
    for (int h : hits) EXPECT_EQ(h, 1);
}

TEST(TileGrid, EmptyWindowHasNoTilesAndATileCanCoverAll) {
    EXPECT_EQ(TileGrid(Roi{4, 4, 4, 9}, 16).count(), 0);
    EXPECT_EQ(TileGrid(Roi{}, 1).count(), 0);
    const TileGrid one(Roi{0, 0, 5, 3}, 64);
    ASSERT_EQ(one.count(), 1);
    EXPECT_EQ(one.tile(0), (Roi{0, 0, 5, 3}));
    const TileGrid px(Roi{0, 0, 3, 2}, 1);
    ASSERT_EQ(px.count(), 6);
    EXPECT_EQ(px.tile(4), (Roi{1, 1, 2, 2}));
}

TEST(Image, NegativeOriginWindowsAndAddressing) {
    // Data window partly outside the display window, negative origin.
    Image img({{"R", PixelType::Half}, {"id", PixelType::UInt}}, Roi{-3, -2, 5, 4}, Roi{0, 0, 4, 4});
    EXPECT_EQ(img.width(), 8);
    EXPECT_EQ(img.height(), 6);
    ASSERT_NE(img.plane(0), nullptr);
    EXPECT_EQ(img.plane(1), nullptr);
    ASSERT_NE(img.uplane(1), nullptr);
    img.at(0, -3, -2) = 1.5f;
    img.at(0, 4, 3) = 2.5f;
    EXPECT_EQ(img.plane(0)[0], 1.5f);
    EXPECT_EQ(img.plane(0)[img.npixels() - 1], 2.5f);
    img.uplane(1)[img.offset(0, 0)] = 4000000000u;  // beyond float precision, must stay exact
    EXPECT_EQ(img.uplane(1)[img.offset(0, 0)], 4000000000u);
    EXPECT_EQ(img.sample(0, 100, 100), 0.0f);
    EXPECT_EQ(img.channel_index("id"), 1);
    EXPECT_EQ(img.channel_index("nope"), -1);
}

TEST(Image, EmptyDataWindowAllocatesNothing) {
    Image img = Image::with_channels({"R", "G"}, Roi{5, 5, 5, 9});
    EXPECT_TRUE(img.data_window().empty());
    EXPECT_EQ(img.npixels(), 0u);
    EXPECT_EQ(img.sample(0, 5, 5), 0.0f);
}

TEST(ImageView, InterleavedViewWithNegativeRowStride) {
    // A bottom-up interleaved RGBA buffer, as some OFX hosts hand out.
    const int w = 3, h = 2;
    float buf[w * h * 4];
    for (int i = 0; i < w * h * 4; ++i) buf[i] = float(i);
    Roi win{10, 20, 10 + w, 20 + h};
    // Row y=20 is the last row in memory.
    ImageView v = ImageView::interleaved(buf + (h - 1) * w * 4, 4, win, -w * 4);
    EXPECT_EQ(v.at(0, 10, 20), float((h - 1) * w * 4));
    EXPECT_EQ(v.at(3, 12, 21), float(2 * 4 + 3));
}

TEST(DeepImage, SampleOffsetsArePrefixSums) {
    DeepImage d({{"R", PixelType::Half}, {"Z", PixelType::Float}, {"ZBack", PixelType::Float}}, Roi{0, 0, 3, 1},
                Roi{0, 0, 3, 1});
    EXPECT_TRUE(d.set_sample_counts({2, 0, 3}));
    EXPECT_EQ(d.total_samples(), 5u);
    EXPECT_EQ(d.first_sample(2), 2u);
    EXPECT_EQ(d.z_channel(), 1);
    EXPECT_EQ(d.zback_channel(), 2);
    d.samples(1)[d.first_sample(2) + 2] = 7.0f;
    EXPECT_EQ(d.samples(1)[4], 7.0f);
}

TEST(DeepImage, SampleCountsOfAnotherSizeAreAnErrorAndChangeNothing) {
    DeepImage d({{"R", PixelType::Half}, {"id", PixelType::UInt}}, Roi{0, 0, 3, 1}, Roi{0, 0, 3, 1});
    ASSERT_TRUE(d.set_sample_counts({1, 2, 0}));
    d.samples(0)[2] = 4.5f;
    Status st = d.set_sample_counts({1, 1});
    ASSERT_FALSE(st);
    EXPECT_EQ(st.code(), StatusCode::InvalidArgument);
    EXPECT_NE(st.message().find("2 sample counts"), std::string::npos) << st.message();
    EXPECT_NE(st.message().find("3 pixels"), std::string::npos) << st.message();
    EXPECT_EQ(d.total_samples(), 3u);
    EXPECT_EQ(d.samples(0)[2], 4.5f);
}

TEST(DeepImage, SetChannelTypeKeepsStorageKinds) {
    DeepImage d({{"R", PixelType::Half}, {"id", PixelType::UInt}}, Roi{0, 0, 1, 1}, Roi{0, 0, 1, 1});
    EXPECT_TRUE(d.set_channel_type(0, PixelType::Float));
    EXPECT_EQ(d.channel(0).type, PixelType::Float);
    Status st = d.set_channel_type(1, PixelType::Float);
    ASSERT_FALSE(st);
    EXPECT_EQ(st.code(), StatusCode::InvalidArgument);
    EXPECT_NE(st.message().find("'id'"), std::string::npos) << st.message();
    EXPECT_EQ(d.channel(1).type, PixelType::UInt);
    EXPECT_FALSE(d.set_channel_type(0, PixelType::UInt));
}

TEST(Math, InverseOfAffineMatrix) {
    Mat44 m;
    m.m = {{{0, 1, 0, 0}, {-2, 0, 0, 0}, {0, 0, 3, 0}, {5, -6, 7, 1}}};
    auto inv = inverse(m);
    ASSERT_TRUE(inv);
    Vec3 p{1.25, -3.5, 8.0};
    Vec3 q = inv->transform_point(m.transform_point(p));
    EXPECT_NEAR(q.x, p.x, 1e-12);
    EXPECT_NEAR(q.y, p.y, 1e-12);
    EXPECT_NEAR(q.z, p.z, 1e-12);
    Mat44 singular;
    singular.m[2] = {0, 0, 0, 0};
    EXPECT_FALSE(inverse(singular));
}
