// layers_from_parts: multipart files (a part per layer) and single-part
// multilayer images ("fg.R" ...), written and read back through the I/O layer.
#include <gtest/gtest.h>

#include <cmath>

#include "gdof/io/image_io.h"
#include "gdof/layers.h"
#include "test_support.h"

using namespace gdof;

namespace {

const Roi kDisplay{0, 0, 40, 30};

bool in_disc(int x, int y) { return (x - 12) * (x - 12) + (y - 14) * (y - 14) <= 36; }

// Foreground part: an opaque disc (RGBA) with a position pass P at depth ~2.
Image fg_part() {
    Image img = Image::with_channels({"R", "G", "B", "A", "P.x", "P.y", "P.z"}, kDisplay);
    img.name = "fg";
    for (int y = 0; y < 30; ++y)
        for (int x = 0; x < 40; ++x) {
            if (!in_disc(x, y)) continue;
            img.at(0, x, y) = 0.8f;
            img.at(1, x, y) = 0.1f;
            img.at(2, x, y) = 0.1f;
            img.at(3, x, y) = 1.0f;
            img.at(4, x, y) = 0.01f * float(x);
            img.at(5, x, y) = 0.01f * float(y);
            img.at(6, x, y) = 2.0f + 0.01f * float(x);
        }
    return img;
}

// Background part: a textured wall at depth 10 (RGBA + Z), window offset.
Image bg_part() {
    Image img = Image::with_channels({"R", "G", "B", "A", "Z"}, Roi{-2, -1, 42, 30});
    img.set_display_window(kDisplay);
    img.name = "bg";
    const Roi w = img.data_window();
    for (int y = w.y0; y < w.y1; ++y)
        for (int x = w.x0; x < w.x1; ++x) {
            img.at(0, x, y) = 0.2f + 0.01f * float((x + y) % 7);
            img.at(1, x, y) = 0.5f;
            img.at(2, x, y) = 0.3f;
            img.at(3, x, y) = 1.0f;
            img.at(4, x, y) = 10.0f;
        }
    return img;
}

}  // namespace

TEST(layers_parts, MultipartFileGivesLayersFrontToBack) {
    test::ScratchDir dir;
    ImageSet set;
    set.parts.emplace_back(bg_part());  // stored back first: ordering must come from depth
    set.parts.emplace_back(fg_part());
    const std::string path = dir.file("parts.exr");
    ASSERT_TRUE(io::write_image(path, set).is_ok());
    auto in = io::read_image(path);
    ASSERT_TRUE(in) << in.message();
    ASSERT_EQ(in->size(), 2u);

    auto r = layers_from_parts(*in, PositionSource{});
    ASSERT_TRUE(r) << r.message();
    ASSERT_EQ(r->size(), 2u);
    const Layer& fg = (*r)[0];
    const Layer& bg = (*r)[1];
    EXPECT_EQ(fg.name, "fg");
    EXPECT_EQ(bg.name, "bg");
    // fg: window = the disc's box, Z from P (no camera attributes: P.z), P carried.
    EXPECT_EQ(fg.image.data_window(), (Roi{6, 8, 19, 21}));
    EXPECT_EQ(fg.image.display_window(), kDisplay);
    ASSERT_GE(fg.image.channel_index("P.x"), 0);
    const int fz = fg.image.channel_index("Z");
    ASSERT_EQ(fz, 4);
    EXPECT_FLOAT_EQ(fg.image.at(fz, 12, 14), 2.12f);
    EXPECT_FLOAT_EQ(fg.image.at(fg.image.channel_index("P.y"), 12, 14), 0.14f);
    EXPECT_FLOAT_EQ(fg.image.at(0, 12, 14), 0.8f);
    EXPECT_EQ(fg.image.at(3, 12, 14), 1.0f);
    EXPECT_EQ(fg.image.at(3, 6, 8), 0.0f);  // box corner, outside the disc
    EXPECT_TRUE(std::isnan(fg.image.at(fz, 6, 8)));
    EXPECT_NEAR(fg.depth_near, 2.06, 1e-6);
    EXPECT_NEAR(fg.depth_far, 2.18, 1e-6);
    // bg: the whole window, Z = 10, colour kept.
    EXPECT_EQ(bg.image.data_window(), (Roi{-2, -1, 42, 30}));
    EXPECT_EQ(bg.image.at(4, 12, 14), 10.0f);
    EXPECT_EQ(bg.image.channel_index("P.x"), -1);
    Image src = bg_part();
    EXPECT_EQ(bg.image.at(0, 5, 3), src.at(0, 5, 3));

    // Composite = fg over bg.
    Image comp = composite_layers({&fg.image, &bg.image}, kDisplay).value();
    EXPECT_FLOAT_EQ(comp.at(0, 12, 14), 0.8f);
    EXPECT_FLOAT_EQ(comp.at(0, 30, 3), src.at(0, 30, 3));
}

TEST(layers_parts, CameraAttributesGiveDepthFromPositions) {
    ImageSet set;
    Image fg = fg_part();
    CameraDesc desc;
    desc.position = {0, 0, -3};  // camera 3 units behind the origin, looking down +z
    desc.look_at = {0, 0, 1};
    desc.display_window = kDisplay;
    auto cam = Camera::create(desc);
    ASSERT_TRUE(cam) << cam.message();
    cam->to_metadata(fg.metadata);
    set.parts.emplace_back(std::move(fg));
    auto r = layers_from_parts(set, PositionSource{});
    ASSERT_TRUE(r) << r.message();
    ASSERT_EQ(r->size(), 1u);
    EXPECT_NEAR((*r)[0].image.at(4, 12, 14), 5.12, 1e-5);
}

TEST(layers_parts, SinglePartMultilayer) {
    test::ScratchDir dir;
    const Image fgp = fg_part(), bgp = bg_part();
    // One part: bg.* first, then fg.* with a depth channel, plus a normals
    // layer (RGB without alpha) that is not a layer.
    Image img = Image::with_channels({"bg.R", "bg.G", "bg.B", "bg.A", "bg.Z", "fg.R", "fg.G", "fg.B", "fg.A", "fg.Z",
                                      "N.R", "N.G", "N.B"},
                                     kDisplay);
    for (int y = 0; y < 30; ++y)
        for (int x = 0; x < 40; ++x) {
            for (int c = 0; c < 5; ++c) img.at(c, x, y) = bgp.at(c, x, y);
            for (int c = 0; c < 4; ++c) img.at(5 + c, x, y) = fgp.at(c, x, y);
            img.at(9, x, y) = in_disc(x, y) ? 0.5f : 0.0f;  // stored as inverse depth 1/2
            img.at(10, x, y) = 1.0f;
        }
    ImageSet set;
    set.parts.emplace_back(std::move(img));
    const std::string path = dir.file("multilayer.exr");
    ASSERT_TRUE(io::write_image(path, set).is_ok());
    auto in = io::read_image(path);
    ASSERT_TRUE(in) << in.message();

    PositionSource src;
    src.depth_decode.encoding = DepthEncoding::Inverse;
    src.depth_decode.scale = 1.0;
    auto r = layers_from_parts(*in, PositionSource{});
    ASSERT_TRUE(r) << r.message();
    ASSERT_EQ(r->size(), 2u);
    // fg.Z stores 0.5 (metric 0.5) < bg 10: fg in front.
    EXPECT_EQ((*r)[0].name, "fg");
    EXPECT_EQ((*r)[1].name, "bg");
    EXPECT_EQ((*r)[0].image.at(4, 12, 14), 0.5f);
    EXPECT_EQ((*r)[0].image.data_window(), (Roi{6, 8, 19, 21}));
    EXPECT_EQ((*r)[1].image.at(4, 12, 14), 10.0f);
    // Inverse decoding: fg 1/0.5 = 2, bg 1/10 = 0.1: now bg is in front.
    auto inv = layers_from_parts(*in, src);
    ASSERT_TRUE(inv) << inv.message();
    ASSERT_EQ(inv->size(), 2u);
    EXPECT_EQ((*inv)[0].name, "bg");
    EXPECT_FLOAT_EQ((*inv)[0].image.at(4, 12, 14), 0.1f);
    EXPECT_FLOAT_EQ((*inv)[1].image.at(4, 12, 14), 2.0f);
}

TEST(layers_parts, NoLayerIsAnErrorSayingWhatWasLookedFor) {
    ImageSet set;
    Image plain = Image::with_channels({"R", "G", "B", "A"}, kDisplay);
    set.parts.emplace_back(std::move(plain));
    auto r = layers_from_parts(set, PositionSource{});
    ASSERT_FALSE(r);
    EXPECT_NE(r.message().find("R, G, B, A"), std::string::npos) << r.message();
    EXPECT_NE(r.message().find("P.x"), std::string::npos) << r.message();
    EXPECT_NE(r.message().find("Z"), std::string::npos) << r.message();
    PositionSource named;
    named.depth_channel = "dist";
    auto n = layers_from_parts(set, named);
    ASSERT_FALSE(n);
    EXPECT_NE(n.message().find("'dist'"), std::string::npos) << n.message();
}
