// Display-referred formats through OIIO: sRGB in -> linear float, linear out
// -> sRGB 8/16-bit, alpha handling, formats without alpha.
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <cmath>
#include <filesystem>

#include "gdof/io/image_io.h"
#include "test_support.h"

using namespace gdof;
using namespace gdof::test;

namespace {

// Writes an 8-bit PNG directly with OIIO (straight alpha as PNG stores it).
void write_png8(const std::string& path, int nch, const std::vector<unsigned char>& px, int w, int h) {
    auto out = OIIO::ImageOutput::create(path);
    ASSERT_TRUE(out);
    OIIO::ImageSpec spec(w, h, nch, OIIO::TypeUInt8);
    if (nch == 4) {
        spec.alpha_channel = 3;
        spec.attribute("oiio:UnassociatedAlpha", 1);
    }
    ASSERT_TRUE(out->open(path, spec));
    ASSERT_TRUE(out->write_image(OIIO::TypeUInt8, px.data()));
    ASSERT_TRUE(out->close());
}

std::vector<unsigned char> read_raw8(const std::string& path, int& nch) {
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);
    auto in = OIIO::ImageInput::open(path, &config);
    EXPECT_TRUE(in) << OIIO::geterror();
    if (!in) return {};
    nch = in->spec().nchannels;
    std::vector<unsigned char> px(std::size_t(in->spec().image_pixels()) * std::size_t(nch));
    EXPECT_TRUE(in->read_image(0, 0, 0, nch, OIIO::TypeUInt8, px.data()));
    in->close();
    return px;
}

double srgb_to_linear(double v) { return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4); }

}  // namespace

TEST(io_png, EightBitSrgbReadsLinearAndWritesBackExactly) {
    ScratchDir dir;
    const int w = 256, h = 2;
    std::vector<unsigned char> px(std::size_t(w * h * 3));
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < 3; ++c) px[std::size_t((y * w + x) * 3 + c)] = (unsigned char)((x + c * 85 * y) % 256);
    const std::string in = dir.file("ramp.png");
    write_png8(in, 3, px, w, h);

    auto img = io::read_flat(in);
    ASSERT_TRUE(img) << img.message();
    ASSERT_EQ(img->nchannels(), 3);
    EXPECT_EQ(img->storage.format, "png");
    // 128/255 -> 0.2158605 (IEC 61966-2-1).
    EXPECT_NEAR(img->at(0, 128, 0), 0.2158605, 1e-6);
    for (int x = 0; x < w; ++x) EXPECT_NEAR(img->at(0, x, 0), srgb_to_linear(x / 255.0), 2e-6) << x;
    EXPECT_EQ(*img->metadata.get_string("oiio:ColorSpace"), "linear");

    // linearize off: the encoded values.
    io::ReadOptions raw;
    raw.linearize = false;
    auto enc = io::read_flat(in, raw);
    ASSERT_TRUE(enc);
    EXPECT_FLOAT_EQ(enc->at(0, 128, 0), 128.0f / 255.0f);

    const std::string out = dir.file("back.png");
    Status st = io::write_flat(out, img.value());
    ASSERT_TRUE(st) << st.message();
    int nch = 0;
    auto back = read_raw8(out, nch);
    ASSERT_EQ(nch, 3);
    EXPECT_EQ(back, px);

    // A re-read of the written file does not convert twice.
    auto again = io::read_flat(out);
    ASSERT_TRUE(again);
    EXPECT_NEAR(again->at(0, 128, 0), 0.2158605, 1e-6);
}

TEST(io_png, StraightAlphaIsPremultipliedInLinearAndRestoredOnWrite) {
    ScratchDir dir;
    std::vector<unsigned char> px = {200, 100, 50, 128, 255, 255, 255, 0, 10, 20, 30, 255, 64, 128, 192, 64};
    const std::string in = dir.file("rgba.png");
    write_png8(in, 4, px, 4, 1);
    auto img = io::read_flat(in);
    ASSERT_TRUE(img) << img.message();
    ASSERT_EQ(img->nchannels(), 4);
    const double a = 128 / 255.0;
    EXPECT_NEAR(img->at(0, 0, 0), srgb_to_linear(200 / 255.0) * a, 2e-6);
    EXPECT_NEAR(img->at(3, 0, 0), a, 1e-7);
    EXPECT_EQ(img->at(0, 1, 0), 0.0f);  // zero alpha -> zero colour (premultiplied)
    ASSERT_TRUE(io::write_flat(dir.file("rgba_back.png"), img.value()));
    int nch = 0;
    auto back = read_raw8(dir.file("rgba_back.png"), nch);
    ASSERT_EQ(nch, 4);
    for (std::size_t i = 0; i < px.size(); ++i) {
        if (i / 4 == 1 && i % 4 != 3) continue;  // colour under zero alpha is lost, as premultiplied
        EXPECT_NEAR(int(back[i]), int(px[i]), 0) << "byte " << i;
    }
}

TEST(io_png, SixteenBitAndGreyAreNotColourConverted) {
    ScratchDir dir;
    const std::string in = dir.file("depth16.png");
    {
        auto out = OIIO::ImageOutput::create(in);
        OIIO::ImageSpec spec(3, 1, 1, OIIO::TypeUInt16);
        std::vector<std::uint16_t> v = {0, 5000, 65535};
        ASSERT_TRUE(out->open(in, spec));
        ASSERT_TRUE(out->write_image(OIIO::TypeUInt16, v.data()));
        ASSERT_TRUE(out->close());
    }
    auto img = io::read_flat(in);
    ASSERT_TRUE(img) << img.message();
    ASSERT_EQ(img->nchannels(), 1);
    EXPECT_NEAR(img->at(0, 1, 0) * 65535.0, 5000.0, 1e-3);
    // Written back as 16-bit (the source depth is remembered).
    ASSERT_TRUE(io::write_flat(dir.file("depth_back.png"), img.value()));
    auto in2 = OIIO::ImageInput::open(dir.file("depth_back.png"));
    ASSERT_TRUE(in2);
    EXPECT_EQ(in2->spec().format, OIIO::TypeUInt16);
    std::vector<std::uint16_t> v(3);
    ASSERT_TRUE(in2->read_image(0, 0, 0, 1, OIIO::TypeUInt16, v.data()));
    EXPECT_EQ(v, (std::vector<std::uint16_t>{0, 5000, 65535}));
    in2->close();
}

TEST(io_png, JpegDropsAlphaTiffKeepsIt) {
    ScratchDir dir;
    Image img = Image::with_channels({"R", "G", "B", "A", "Z"}, {0, 0, 8, 8});
    for (int c = 0; c < 5; ++c)
        for (std::size_t i = 0; i < img.npixels(); ++i) img.plane(c)[i] = c == 3 ? 1.0f : 0.25f;
    ASSERT_TRUE(io::write_flat(dir.file("x.jpg"), img));
    auto j = OIIO::ImageInput::open(dir.file("x.jpg"));
    ASSERT_TRUE(j);
    EXPECT_EQ(j->spec().nchannels, 3);
    j->close();
    ASSERT_TRUE(io::write_flat(dir.file("x.tif"), img));
    auto t = io::read_flat(dir.file("x.tif"));
    ASSERT_TRUE(t) << t.message();
    EXPECT_EQ(t->nchannels(), 4);
    EXPECT_NEAR(t->at(0, 3, 3), 0.25f, 2e-3);  // 8-bit sRGB quantisation
    // Explicit output colour space "linear": values written as they are.
    io::WriteOptions wo;
    wo.colorspace = "linear";
    ASSERT_TRUE(io::write_flat(dir.file("lin.png"), img, wo));
    int nch = 0;
    auto raw = read_raw8(dir.file("lin.png"), nch);
    ASSERT_FALSE(raw.empty());
    EXPECT_EQ(int(raw[0]), 64);  // 0.25 * 255 = 63.75
    // Unknown colour space is an error naming it.
    wo.colorspace = "NoSuchSpace";
    Status st = io::write_flat(dir.file("bad.png"), img, wo);
    ASSERT_FALSE(st);
    EXPECT_NE(st.message().find("NoSuchSpace"), std::string::npos) << st.message();
    EXPECT_FALSE(std::filesystem::exists(dir.file("bad.png")));
}

TEST(io_png, DisplayWindowIsWhatAPngShows) {
    // PNG has no data window: the display window's pixels are written, zero
    // outside the data window.
    ScratchDir dir;
    Image img = Image::with_channels({"R", "G", "B"}, {-2, -2, 3, 3});
    img.set_display_window({0, 0, 4, 4});
    for (int c = 0; c < 3; ++c)
        for (std::size_t i = 0; i < img.npixels(); ++i) img.plane(c)[i] = 1.0f;
    ASSERT_TRUE(io::write_flat(dir.file("win.png"), img));
    int nch = 0;
    auto raw = read_raw8(dir.file("win.png"), nch);
    ASSERT_EQ(raw.size(), 4u * 4u * 3u);
    EXPECT_EQ(int(raw[0]), 255);                        // (0,0) inside the data window
    EXPECT_EQ(int(raw[(3 * 4 + 3) * 3]), 0);            // (3,3) outside it
}

TEST(io_png, RealLightfieldViewRoundTrip) {
    GDOF_REQUIRE_SHARED(path, "lightfield/lytro_2067/2067_05_05.png");
    ScratchDir dir;
    auto img = io::read_flat(path);
    ASSERT_TRUE(img) << img.message();
    EXPECT_EQ(img->width(), 552);
    EXPECT_EQ(img->height(), 383);
    ASSERT_TRUE(io::write_flat(dir.file("view.png"), img.value()));
    int n0 = 0, n1 = 0;
    auto a = read_raw8(path, n0);
    auto b = read_raw8(dir.file("view.png"), n1);
    ASSERT_EQ(n0, n1);
    EXPECT_EQ(a, b);  // sRGB -> linear float -> sRGB is lossless at 8 bits
}
