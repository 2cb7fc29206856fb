// ImageView helpers (planar, channels, cropped, row_major, const views) and
// Image::channels_view over the contiguous float planes.
#include <gtest/gtest.h>

#include <numeric>
#include <vector>

#include "gdof/image.h"

using namespace gdof;

TEST(ImageView, PlanarViewAddressesPlanesBackToBack) {
    const Roi win{-2, 3, 2, 6};  // 4 x 3, negative origin
    std::vector<float> buf(2 * win.npixels());
    std::iota(buf.begin(), buf.end(), 0.0f);
    const ImageView v = ImageView::planar(buf.data(), 2, win);
    EXPECT_EQ(v.width(), 4);
    EXPECT_EQ(v.height(), 3);
    EXPECT_EQ(v.npixels(), 12u);
    EXPECT_TRUE(v.row_major());
    EXPECT_EQ(v.at(0, -2, 3), 0.0f);
    EXPECT_EQ(v.at(0, 1, 5), 11.0f);
    EXPECT_EQ(v.at(1, -2, 3), 12.0f);  // the second plane follows the first
    EXPECT_EQ(v.at(1, 0, 4), 12.0f + 4 + 2);
    EXPECT_EQ(v.plane(1), buf.data() + 12);
}

TEST(ImageView, ChannelRangeAndConstView) {
    std::vector<float> buf(3 * 6, 0.0f);
    const Roi win{0, 0, 3, 2};
    const ImageView v = ImageView::planar(buf.data(), 3, win);
    const ImageView last_two = v.channels(1, 2);
    EXPECT_EQ(last_two.nchannels, 2);
    last_two.at(1, 2, 1) = 7.0f;  // channel 2 of the whole view
    EXPECT_EQ(v.at(2, 2, 1), 7.0f);
    const ConstImageView c = v;  // a mutable view reads as a const one
    EXPECT_EQ(c.at(2, 2, 1), 7.0f);
    EXPECT_EQ(c.base, v.base);
    EXPECT_EQ(c.cstride, v.cstride);
}

TEST(ImageView, CroppedViewSharesMemoryAndIsNotRowMajor) {
    const Roi win{10, 20, 16, 24};  // 6 x 4
    std::vector<float> buf(win.npixels());
    std::iota(buf.begin(), buf.end(), 0.0f);
    const ImageView v = ImageView::planar(buf.data(), 1, win);
    const ImageView sub = v.cropped(Roi{12, 21, 15, 23});
    EXPECT_EQ(sub.window, (Roi{12, 21, 15, 23}));
    EXPECT_FALSE(sub.row_major());  // its rows are 6 apart, not 3
    EXPECT_EQ(sub.at(0, 12, 21), v.at(0, 12, 21));
    EXPECT_EQ(sub.at(0, 14, 22), v.at(0, 14, 22));
    sub.at(0, 14, 22) = -1.0f;
    EXPECT_EQ(buf[2 * 6 + 4], -1.0f);
    // Clipped to the window; disjoint gives an empty view.
    EXPECT_EQ(v.cropped(Roi{0, 0, 12, 22}).window, (Roi{10, 20, 12, 22}));
    EXPECT_TRUE(v.cropped(Roi{0, 0, 5, 5}).window.empty());
    EXPECT_TRUE(v.cropped(Roi{0, 0, 5, 5}).valid());
}

TEST(ImageView, InterleavedViewIsNotRowMajor) {
    std::vector<float> buf(4 * 6);
    const ImageView v = ImageView::interleaved(buf.data(), 4, Roi{0, 0, 3, 2}, 12);
    EXPECT_FALSE(v.row_major());
    EXPECT_TRUE(ImageView::interleaved(buf.data(), 1, Roi{0, 0, 3, 2}, 3).row_major());
    EXPECT_TRUE(ImageView{}.row_major());  // empty
    EXPECT_TRUE(ImageView{}.valid());
    EXPECT_FALSE((ImageView{nullptr, 1, Roi{0, 0, 1, 1}, 1, 1, 1}.valid()));
}

TEST(Image, ChannelsViewSpansTheFloatPlanes) {
    Image img({{"R", PixelType::Half}, {"G", PixelType::Float}, {"Z", PixelType::Float}}, Roi{-1, -1, 3, 2});
    for (int c = 0; c < 3; ++c)
        for (int y = -1; y < 2; ++y)
            for (int x = -1; x < 3; ++x) img.at(c, x, y) = float(100 * c + 10 * y + x);
    const ImageView v = img.channels_view();
    ASSERT_TRUE(v.valid());
    EXPECT_EQ(v.nchannels, 3);
    EXPECT_EQ(v.window, img.data_window());
    EXPECT_TRUE(v.row_major());
    for (int c = 0; c < 3; ++c) {
        EXPECT_EQ(v.plane(c), img.plane(c));
        for (int y = -1; y < 2; ++y)
            for (int x = -1; x < 3; ++x) EXPECT_EQ(v.at(c, x, y), img.at(c, x, y));
    }
    const Image& cimg = img;
    EXPECT_EQ(cimg.channels_view().base, img.plane(0));
}

TEST(Image, ChannelsViewNeedsFloatChannelsOnly) {
    Image img({{"R", PixelType::Float}, {"id", PixelType::UInt}}, Roi{0, 0, 2, 2});
    const ImageView v = img.channels_view();
    EXPECT_FALSE(v.valid());
    EXPECT_EQ(v.nchannels, 0);
    // The float channel's own view is still there.
    EXPECT_TRUE(img.channel_view(0).valid());
    // An empty window has no pixels to address: valid, nothing allocated.
    Image empty = Image::with_channels({"R", "G"}, Roi{4, 4, 4, 8});
    EXPECT_TRUE(empty.channels_view().valid());
    EXPECT_EQ(empty.plane(0), nullptr);
}

TEST(Image, AddAndRemoveChannelsKeepTheOtherPlanes) {
    Image img({{"A", PixelType::Float}, {"id", PixelType::UInt}, {"B", PixelType::Half}}, Roi{0, 0, 3, 2});
    for (int i = 0; i < 6; ++i) {
        img.plane(0)[i] = float(i);
        img.uplane(1)[i] = 4000000000u + std::uint32_t(i);
        img.plane(2)[i] = float(10 + i);
    }
    const int c = img.add_channel({"C", PixelType::Float});
    const int u = img.add_channel({"id2", PixelType::UInt});
    EXPECT_EQ(c, 3);
    EXPECT_EQ(u, 4);
    for (int i = 0; i < 6; ++i) {
        EXPECT_EQ(img.plane(0)[i], float(i));
        EXPECT_EQ(img.uplane(1)[i], 4000000000u + std::uint32_t(i));
        EXPECT_EQ(img.plane(2)[i], float(10 + i));
        EXPECT_EQ(img.plane(c)[i], 0.0f);  // zero-filled
        EXPECT_EQ(img.uplane(u)[i], 0u);
    }
    img.plane(c)[5] = 9.5f;
    img.remove_channel(0);  // a float plane before the others
    ASSERT_EQ(img.nchannels(), 4);
    EXPECT_EQ(img.channel(0).name, "id");
    EXPECT_EQ(img.plane(0), nullptr);
    for (int i = 0; i < 6; ++i) {
        EXPECT_EQ(img.uplane(0)[i], 4000000000u + std::uint32_t(i));
        EXPECT_EQ(img.plane(1)[i], float(10 + i));
    }
    EXPECT_EQ(img.at(2, 2, 1), 9.5f);
    img.remove_channel(0);                     // id: B, C, id2 remain
    EXPECT_FALSE(img.channels_view().valid());  // id2 is uint
    img.remove_channel(2);                     // id2: all float now
    const ImageView v = img.channels_view();
    ASSERT_TRUE(v.valid());
    EXPECT_EQ(v.nchannels, 2);
    EXPECT_EQ(v.at(1, 2, 1), 9.5f);
    EXPECT_EQ(v.at(0, 0, 0), 10.0f);
}

TEST(Image, SetChannelTypeKeepsStorageKindsAndNamesTheChannel) {
    Image img({{"R", PixelType::Float}, {"id", PixelType::UInt}}, Roi{0, 0, 1, 1});
    EXPECT_TRUE(img.set_channel_type(0, PixelType::Half));
    EXPECT_EQ(img.channel(0).type, PixelType::Half);
    EXPECT_TRUE(img.set_channel_type(0, PixelType::Float));
    Status st = img.set_channel_type(0, PixelType::UInt);
    ASSERT_FALSE(st);
    EXPECT_EQ(st.code(), StatusCode::InvalidArgument);
    EXPECT_NE(st.message().find("'R'"), std::string::npos) << st.message();
    EXPECT_EQ(img.channel(0).type, PixelType::Float);  // unchanged
    st = img.set_channel_type(1, PixelType::Half);
    ASSERT_FALSE(st);
    EXPECT_NE(st.message().find("'id'"), std::string::npos) << st.message();
    EXPECT_EQ(img.channel(1).type, PixelType::UInt);
}
