// defocus(): whole inputs (flat RGBA + depth, deep, multipart) through the
// layer builders and the pipeline into one flat part with the input's
// display window, metadata, colour types and carried-over channels.
#include <gtest/gtest.h>

#include <cmath>

#include "defocus_test_helpers.h"
#include "gdof/defocus.h"

using namespace gdof;
using namespace gdof::test;

namespace {

const Roi kDisplay{0, 0, 96, 64};

// Flat part: R, G, B, A (half), Z (float, 2 on the left third, 10 elsewhere),
// N.x (half), id (uint), on a data window with a negative origin.
Image flat_input(const Roi& window = Roi{-8, -4, 90, 60}) {
    Image img(std::vector<ChannelSpec>{{"R", PixelType::Half},
                                       {"G", PixelType::Half},
                                       {"B", PixelType::Half},
                                       {"A", PixelType::Half},
                                       {"Z", PixelType::Float},
                                       {"N.x", PixelType::Half},
                                       {"id", PixelType::UInt}},
              window, kDisplay);
    for (int y = window.y0; y < window.y1; ++y)
        for (int x = window.x0; x < window.x1; ++x) {
            for (int c = 0; c < 3; ++c) img.at(c, x, y) = texture(x, y, c);
            img.at(3, x, y) = 1.0f;
            img.at(4, x, y) = x < 32 ? 2.0f : 10.0f;
            img.at(5, x, y) = 0.25f * float(x % 4);
            img.uplane(6)[img.offset(x, y)] = x < 32 ? 7u : 9u;
        }
    img.metadata.set_string("gdof:test", "kept");
    img.name = "beauty";
    return img;
}

// Blur `r` px for depths below 5 (the left third), sharp beyond.
BlurField near_blur(double r) {
    auto f = BlurField::parse(R"({"blurfield": {"kind": "region", "shape": "box", "mode": "blur", "blur": )" +
                              std::to_string(r) + R"(, "min": [-1000, -1000, 0], "max": [1000, 1000, 5]}})");
    EXPECT_TRUE(f) << f.message();
    return f.value();
}

ImageSet one(Image img) {
    ImageSet s;
    s.parts.emplace_back(std::move(img));
    return s;
}

}  // namespace

TEST(defocus_input, FlatWithDepthKeepsTypesWindowsMetadataAndChannels) {
    const Image in = flat_input();
    DefocusStats stats;
    auto r = defocus(one(in), near_blur(4.0), test_camera(kDisplay), {}, &stats);
    ASSERT_TRUE(r) << r.message();
    ASSERT_EQ(r->size(), 1u);
    ASSERT_FALSE(r->is_deep(0));
    const Image& out = r->flat(0);
    EXPECT_EQ(out.display_window(), kDisplay);
    EXPECT_EQ(out.metadata.get_string("gdof:test").value_or(""), "kept");
    EXPECT_EQ(out.name, "beauty");
    ASSERT_EQ(out.nchannels(), 7);
    const char* names[] = {"R", "G", "B", "A", "Z", "N.x", "id"};
    const PixelType types[] = {PixelType::Half, PixelType::Half, PixelType::Half, PixelType::Half,
                               PixelType::Float, PixelType::Half, PixelType::UInt};
    for (int c = 0; c < 7; ++c) {
        EXPECT_EQ(out.channel(c).name, names[c]);
        EXPECT_EQ(out.channel(c).type, types[c]) << names[c];
    }
    // The data window: the input's, grown by the spread of the blurred (near)
    // part only, clipped to the frame (display window ∪ input data window).
    const int m = defocus_margin(4.0);
    const Roi near_part{in.data_window().x0, in.data_window().y0, 32, in.data_window().y1};
    EXPECT_EQ(out.data_window(), intersect(unite(in.data_window(), near_part.grown(m)), unite(kDisplay, in.data_window())));
    // Carried channels: unchanged on the input's window, zero elsewhere.
    const Roi ow = out.data_window();
    for (int y = ow.y0; y < ow.y1; ++y)
        for (int x = ow.x0; x < ow.x1; ++x) {
            const bool inside = in.data_window().contains(x, y);
            ASSERT_EQ(out.at(4, x, y), inside ? in.at(4, x, y) : 0.0f);
            ASSERT_EQ(out.at(5, x, y), inside ? in.at(5, x, y) : 0.0f);
            ASSERT_EQ(out.uplane(6)[out.offset(x, y)], inside ? in.uplane(6)[in.offset(x, y)] : 0u);
        }
    // The sharp far part is untouched (away from the near part's spread).
    for (int y = 0; y < 50; ++y)
        for (int x = 32 + 2 * m; x < 90; ++x)
            for (int c = 0; c < 4; ++c) ASSERT_EQ(out.at(c, x, y), in.at(c, x, y)) << x << "," << y;
    // The near part is blurred: it differs from the input.
    double diff = 0;
    for (int y = 10; y < 50; ++y)
        for (int x = 5; x < 25; ++x) diff = std::max(diff, double(std::abs(out.at(0, x, y) - in.at(0, x, y))));
    EXPECT_GT(diff, 0.01);
    EXPECT_GE(stats.layers, 2);
    EXPECT_GT(stats.pixels_diffused, 0u);
    EXPECT_GT(stats.max_radius_px, 3.99);
}

TEST(defocus_input, ZeroBlurReproducesAnOpaqueFlatInput) {
    const Image in = flat_input(kDisplay);
    auto r = defocus(one(in), BlurField(), test_camera(kDisplay), {});
    ASSERT_TRUE(r) << r.message();
    const Image& out = r->flat(0);
    EXPECT_EQ(out.data_window(), in.data_window());
    for (int c = 0; c < 4; ++c)
        for (std::size_t i = 0; i < in.npixels(); ++i) ASSERT_EQ(out.plane(c)[i], in.plane(c)[i]) << c << " " << i;
}

TEST(defocus_input, DeepInput) {
    // Per pixel: a half-transparent red sample at depth 2 over an opaque blue one at 10 (left half only).
    DeepImage d(std::vector<ChannelSpec>{{"R", PixelType::Half}, {"G", PixelType::Half}, {"B", PixelType::Half},
                                         {"A", PixelType::Half}, {"Z", PixelType::Float}},
                kDisplay, kDisplay);
    std::vector<std::uint32_t> counts(kDisplay.npixels());
    for (int y = 0; y < kDisplay.y1; ++y)
        for (int x = 0; x < kDisplay.x1; ++x) counts[d.pixel_index(x, y)] = x < 48 ? 2u : 1u;
    EXPECT_TRUE(d.set_sample_counts(counts));
    for (int y = 0; y < kDisplay.y1; ++y)
        for (int x = 0; x < kDisplay.x1; ++x) {
            std::size_t k = d.first_sample(d.pixel_index(x, y));
            if (x < 48) {
                d.samples(0)[k] = 0.5f, d.samples(3)[k] = 0.5f, d.samples(4)[k] = 2.0f;
                ++k;
            }
            d.samples(2)[k] = 1.0f, d.samples(3)[k] = 1.0f, d.samples(4)[k] = 10.0f;
        }
    d.metadata.set_string("gdof:test", "deep");
    ImageSet set;
    set.parts.emplace_back(d);
    // Zero blur: the flattened image (red over blue on the left).
    auto flat = defocus(set, BlurField(), test_camera(kDisplay), {});
    ASSERT_TRUE(flat) << flat.message();
    const Image& f = flat->flat(0);
    EXPECT_EQ(f.channel(0).type, PixelType::Half);
    EXPECT_EQ(f.metadata.get_string("gdof:test").value_or(""), "deep");
    EXPECT_FLOAT_EQ(f.at(0, 10, 10), 0.5f);
    EXPECT_FLOAT_EQ(f.at(2, 10, 10), 0.5f);
    EXPECT_FLOAT_EQ(f.at(3, 10, 10), 1.0f);
    EXPECT_FLOAT_EQ(f.at(2, 80, 10), 1.0f);
    // Blurring the front: opaque everywhere on the display (the back is opaque and sharp), red spreads right.
    auto blurred = defocus(set, near_blur(6.0), test_camera(kDisplay), {});
    ASSERT_TRUE(blurred) << blurred.message();
    const Image& b = blurred->flat(0);
    for (int y = 0; y < kDisplay.y1; ++y)
        for (int x = 0; x < kDisplay.x1; ++x) ASSERT_NEAR(b.at(3, x, y), 1.0f, 1e-4) << x << "," << y;
    EXPECT_GT(b.at(0, 50, 30), 0.02f);  // beyond the front layer's silhouette (x < 48)
    EXPECT_LT(b.at(0, 50, 30), 0.45f);
}

TEST(defocus_input, MultipartLayers) {
    Image fg(std::vector<ChannelSpec>{{"R"}, {"G"}, {"B"}, {"A"}, {"Z"}}, Roi{20, 10, 50, 40}, kDisplay);
    for (int y = 10; y < 40; ++y)
        for (int x = 20; x < 50; ++x) {
            fg.at(0, x, y) = 1, fg.at(3, x, y) = 1, fg.at(4, x, y) = 2;
        }
    fg.name = "fg";
    Image bg(std::vector<ChannelSpec>{{"R"}, {"G"}, {"B"}, {"A"}, {"Z"}}, kDisplay, kDisplay);
    for (int y = 0; y < kDisplay.y1; ++y)
        for (int x = 0; x < kDisplay.x1; ++x) {
            bg.at(2, x, y) = 1, bg.at(3, x, y) = 1, bg.at(4, x, y) = 10;
        }
    bg.name = "bg";
    ImageSet set;
    set.parts.emplace_back(bg);  // any order: layers are sorted by depth
    set.parts.emplace_back(fg);
    auto r = defocus(set, near_blur(4.0), test_camera(kDisplay), {});
    ASSERT_TRUE(r) << r.message();
    const Image& o = r->flat(0);
    EXPECT_NEAR(o.at(0, 35, 25), 1.0, 1e-3);  // fg interior
    EXPECT_NEAR(o.at(2, 35, 25), 0.0, 1e-3);
    EXPECT_GT(o.at(0, 51, 25), 0.02);          // fg spread beyond its silhouette
    EXPECT_GT(o.at(2, 51, 25), 0.02);          // over the blue background
    EXPECT_EQ(o.at(2, 80, 50), 1.0f);          // far background untouched
    EXPECT_NEAR(o.at(3, 51, 25), 1.0, 1e-4);
}

TEST(defocus_input, SubRegionOfAWholeInput) {
    const Image in = flat_input();
    DefocusOptions s;
    s.roi = Roi{20, 10, 50, 40};
    auto sub = defocus(one(in), near_blur(6.0), test_camera(kDisplay), s);
    auto full = defocus(one(in), near_blur(6.0), test_camera(kDisplay), {});
    ASSERT_TRUE(sub) << sub.message();
    ASSERT_TRUE(full) << full.message();
    EXPECT_EQ(sub->flat(0).data_window(), s.roi);
    EXPECT_LT(max_abs_diff(sub->flat(0), full->flat(0), s.roi), 1e-4);
    EXPECT_EQ(sub->flat(0).at(4, 25, 15), in.at(4, 25, 15));  // Z carried onto the sub-region
}

TEST(defocus_input, BadInputsAreClearErrors) {
    const Camera cam = test_camera(kDisplay);
    auto r = defocus(ImageSet{}, BlurField(), cam, {});
    ASSERT_FALSE(r);
    EXPECT_NE(r.message().find("no image parts"), std::string::npos) << r.message();

    Image no_z = Image::with_channels({"R", "G", "B", "A"}, kDisplay);
    r = defocus(one(no_z), BlurField(), cam, {});
    ASSERT_FALSE(r);
    EXPECT_NE(r.message().find("no depth channel 'Z'"), std::string::npos) << r.message();

    Image no_rgb = Image::with_channels({"Y", "Z"}, kDisplay);
    r = defocus(one(no_rgb), BlurField(), cam, {});
    ASSERT_FALSE(r);
    EXPECT_NE(r.message().find("no R, G, B"), std::string::npos) << r.message();

    DefocusOptions s;
    s.source.depth_channel = "depth.V";
    r = defocus(one(flat_input()), BlurField(), cam, s);
    ASSERT_FALSE(r);
    EXPECT_NE(r.message().find("depth.V"), std::string::npos) << r.message();

    DeepImage d(std::vector<ChannelSpec>{{"R"}, {"G"}, {"B"}, {"A"}}, kDisplay, kDisplay);
    EXPECT_TRUE(d.set_sample_counts(std::vector<std::uint32_t>(kDisplay.npixels(), 1u)));
    ImageSet ds;
    ds.parts.emplace_back(d);
    r = defocus(ds, BlurField(), cam, {});
    ASSERT_FALSE(r);
    EXPECT_NE(r.message().find("depth"), std::string::npos) << r.message();

    // An absurd blur names the value.
    r = defocus(one(flat_input()), near_blur(9000.0), cam, {});
    ASSERT_FALSE(r);
    EXPECT_NE(r.message().find("9000"), std::string::npos) << r.message();
}
