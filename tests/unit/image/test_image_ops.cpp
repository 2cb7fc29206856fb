#include <gtest/gtest.h>

#include "gdof/image_ops.h"

using namespace gdof;

TEST(image_ops, SelectRenameAndConstantChannels) {
    Image src({{"R", PixelType::Half}, {"blur", PixelType::Float}, {"id", PixelType::UInt}}, Roi{-2, 3, 2, 5},
              Roi{0, 0, 4, 4});
    src.metadata.set_string("note", "kept");
    for (int y = 3; y < 5; ++y)
        for (int x = -2; x < 2; ++x) {
            src.at(0, x, y) = float(x);
            src.at(1, x, y) = float(y) * 2.f;
            src.uplane(2)[src.offset(x, y)] = 4000000001u;
        }
    auto out = select_channels(src, {"Y=blur", "R", "A=0.5", "id"});
    ASSERT_TRUE(out) << out.message();
    ASSERT_EQ(out->nchannels(), 4);
    EXPECT_EQ(out->channel(0).name, "Y");
    EXPECT_EQ(out->channel(0).type, PixelType::Float);
    EXPECT_EQ(out->channel(1).type, PixelType::Half);
    EXPECT_EQ(out->channel(3).type, PixelType::UInt);
    EXPECT_EQ(out->data_window(), src.data_window());
    EXPECT_EQ(out->display_window(), src.display_window());
    EXPECT_EQ(out->metadata.get_string("note"), "kept");
    EXPECT_EQ(out->at(0, 1, 4), 8.f);
    EXPECT_EQ(out->at(1, -2, 3), -2.f);
    EXPECT_EQ(out->at(2, 0, 3), 0.5f);
    EXPECT_EQ(out->uplane(3)[out->offset(1, 4)], 4000000001u);
}

TEST(image_ops, ErrorsNameTheChannel) {
    Image src = Image::with_channels({"R", "G"}, Roi{0, 0, 2, 2});
    auto r = select_channels(src, {"R", "Zdepth"});
    ASSERT_FALSE(r);
    EXPECT_NE(r.message().find("'Zdepth'"), std::string::npos) << r.message();
    EXPECT_FALSE(select_channels(src, {"R", "R"}));
    EXPECT_FALSE(select_channels(src, {"=R"}));
    EXPECT_FALSE(split_list("R,,G"));
    EXPECT_EQ(split_list("R,G,B")->size(), 3u);
}

TEST(image_ops, MultiplyScalesFloatChannelsOnly) {
    Image img({{"R", PixelType::Float}, {"G", PixelType::Float}, {"id", PixelType::UInt}}, Roi{0, 0, 2, 1});
    img.at(0, 0, 0) = 2.f;
    img.at(1, 1, 0) = 3.f;
    img.uplane(2)[0] = 7;
    ASSERT_TRUE(multiply_channels(img, {0.5}));
    EXPECT_EQ(img.at(0, 0, 0), 1.f);
    EXPECT_EQ(img.at(1, 1, 0), 1.5f);
    EXPECT_EQ(img.uplane(2)[0], 7u);
    ASSERT_TRUE(multiply_channels(img, {2, 4, 1}));
    EXPECT_EQ(img.at(1, 1, 0), 6.f);
    EXPECT_FALSE(multiply_channels(img, {1, 2}));
    EXPECT_FALSE(multiply_channels(img, {NAN}));
}
