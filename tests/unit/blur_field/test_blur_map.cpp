// The blur field over whole images: from P, from Z + camera, per deep sample.
#include <gtest/gtest.h>

#include <cmath>
#include <span>
#include <vector>

#include "gdof/blur_map.h"

using namespace gdof;

namespace {

Camera test_camera() {
    CameraDesc d;
    d.position = {0.5, 1.0, -2.0};
    d.look_at = {0.0, 0.8, 5.0};
    d.focal_length_mm = 40;
    d.display_window = {0, 0, 48, 32};
    auto c = Camera::create(d);
    EXPECT_TRUE(c) << c.message();
    return c.value();
}

// An image with Z and P for a slanted surface, data window offset from the display window.
Image test_image(const Camera& cam) {
    Image img = Image::with_channels({"R", "Z", "P.x", "P.y", "P.z"}, Roi{-4, 2, 40, 30});
    img.set_display_window(cam.display_window());
    for (int y = 2; y < 30; ++y)
        for (int x = -4; x < 40; ++x) {
            double depth = 1.0 + 0.3 * x + 0.1 * y + (x < 0 ? 50.0 : 0.0);
            Vec3 p = cam.unproject(x + 0.5, y + 0.5, depth);
            img.at(1, x, y) = float(depth);
            img.at(2, x, y) = float(p.x);
            img.at(3, x, y) = float(p.y);
            img.at(4, x, y) = float(p.z);
        }
    cam.to_metadata(img.metadata);
    return img;
}

// A row-major buffer over the image's data window as the blur map's output.
ImageView plane_of(std::vector<float>& v, const Image& img) { return ImageView::planar(v.data(), 1, img.data_window()); }

PositionSource source(const std::string& position, const std::string& depth) {
    PositionSource s;
    s.position_channels = position;
    s.depth_channel = depth;
    return s;
}

}  // namespace

TEST(blur_map, PositionsAndDepthGiveTheThinLensCoC) {
    const Camera cam = test_camera();
    const Image img = test_image(cam);
    ThinLens lens;
    lens.focal_length_mm = 40;
    lens.f_number = 2.0;
    lens.focus_distance = 4.0;
    lens.image_width_px = 48;
    auto field = BlurField::from_thin_lens(lens);
    ASSERT_TRUE(field) << field.message();
    std::vector<float> from_p(img.npixels()), from_z(img.npixels());
    ASSERT_TRUE(evaluate_blur_map(*field, cam, img, {}, plane_of(from_p, img)));
    Image z_only = img;  // same surface without the position pass
    z_only.remove_channel(4);
    z_only.remove_channel(3);
    z_only.remove_channel(2);
    ASSERT_TRUE(evaluate_blur_map(*field, cam, z_only, {}, plane_of(from_z, z_only)));
    for (int y = 2; y < 30; ++y)
        for (int x = -4; x < 40; ++x) {
            const std::size_t i = img.offset(x, y);
            const double expected = lens.coc_radius_px(img.at(1, x, y));
            EXPECT_NEAR(from_z[i], expected, 1e-4 * (1 + expected)) << x << "," << y;
            EXPECT_NEAR(from_p[i], expected, 1e-3 * (1 + expected)) << x << "," << y;
        }
}

TEST(blur_map, InverseDepthIsDecodedBeforeEvaluation) {
    const Camera cam = test_camera();
    Image img = test_image(cam);
    img.remove_channel(4);
    img.remove_channel(3);
    img.remove_channel(2);
    for (float& z : std::span<float>(img.plane(1), img.npixels())) z = 2.0f / z;  // stored as 2/Z
    ThinLens lens;
    lens.focal_length_mm = 40;
    lens.focus_distance = 3.0;
    lens.image_width_px = 48;
    auto field = BlurField::from_thin_lens(lens);
    ASSERT_TRUE(field);
    PositionSource src;
    src.depth_decode.encoding = DepthEncoding::Inverse;
    src.depth_decode.scale = 2.0;
    std::vector<float> out(img.npixels());
    ASSERT_TRUE(evaluate_blur_map(*field, cam, img, src, plane_of(out, img)));
    for (std::size_t i = 0; i < out.size(); ++i) {
        const double expected = lens.coc_radius_px(2.0 / double(img.plane(1)[i]));
        EXPECT_NEAR(out[i], expected, 1e-4 * (1 + expected));
    }
    src.depth_decode.encoding = DepthEncoding::NearFarLinear;  // near/far not given
    Status st = evaluate_blur_map(*field, cam, img, src, plane_of(out, img));
    ASSERT_FALSE(st);
    EXPECT_NE(st.message().find("'Z'"), std::string::npos) << st.message();
}

TEST(blur_map, ThreadCountDoesNotChangeTheResult) {
    const Camera cam = test_camera();
    const Image img = test_image(cam);
    auto field = BlurField::parse(R"({"blurfield": {"kind": "focal_planes", "depths": [3, 9], "max_blur": 8, "slope": 4}})");
    ASSERT_TRUE(field) << field.message();
    std::vector<float> a(img.npixels()), b(img.npixels());
    Exec one, many;
    one.nthreads = 1;
    many.nthreads = 4;
    ASSERT_TRUE(evaluate_blur_map(*field, cam, img, {}, plane_of(a, img), one));
    ASSERT_TRUE(evaluate_blur_map(*field, cam, img, {}, plane_of(b, img), many));
    EXPECT_EQ(a, b);
}

TEST(blur_map, DeepSamplesMatchTheFlatEvaluationAtTheirDepths) {
    const Camera cam = test_camera();
    const Image img = test_image(cam);
    auto field = BlurField::parse(R"({"blurfield": {"kind": "focal_planes", "depths": [3, 9], "max_blur": 8, "slope": 4}})");
    ASSERT_TRUE(field);
    DeepImage deep({{"A", PixelType::Half}, {"Z", PixelType::Float}}, img.data_window(), img.display_window());
    std::vector<std::uint32_t> counts(deep.npixels());
    for (std::size_t i = 0; i < counts.size(); ++i) counts[i] = std::uint32_t(i % 3);  // 0, 1 or 2 samples
    EXPECT_TRUE(deep.set_sample_counts(counts));
    for (int y = 2; y < 30; ++y)
        for (int x = -4; x < 40; ++x) {
            const std::size_t p = deep.pixel_index(x, y);
            for (std::uint32_t k = 0; k < deep.sample_count(p); ++k)
                deep.samples(1)[deep.first_sample(p) + k] = img.at(1, x, y) * float(1 + k);
        }
    std::vector<float> out(deep.total_samples());
    ASSERT_TRUE(evaluate_blur_deep(*field, cam, deep, -1, out));
    for (int y = 2; y < 30; ++y)
        for (int x = -4; x < 40; ++x) {
            const std::size_t p = deep.pixel_index(x, y);
            for (std::uint32_t k = 0; k < deep.sample_count(p); ++k) {
                const std::size_t s = deep.first_sample(p) + k;
                EXPECT_FLOAT_EQ(out[s], field->evaluate_pixel(cam, x + 0.5, y + 0.5, deep.samples(1)[s]));
            }
        }
}

TEST(blur_map, NamedChannelsThatAreMissingAreErrors) {
    const Camera cam = test_camera();
    Image img = test_image(cam);
    BlurField zero;
    std::vector<float> out(img.npixels());
    Status st = evaluate_blur_map(zero, cam, img, source("Pw", ""), plane_of(out, img));
    ASSERT_FALSE(st);
    EXPECT_NE(st.message().find("Pw.x"), std::string::npos) << st.message();
    st = evaluate_blur_map(zero, cam, img, source("P.x,P.y,nope", ""), plane_of(out, img));
    ASSERT_FALSE(st);
    EXPECT_NE(st.message().find("'nope'"), std::string::npos) << st.message();
    Image flat = Image::with_channels({"R", "G", "B"}, img.data_window());
    st = evaluate_blur_map(zero, cam, flat, {}, plane_of(out, flat));
    ASSERT_FALSE(st);
    EXPECT_NE(st.message().find("'Z'"), std::string::npos) << st.message();
    st = evaluate_blur_map(zero, cam, flat, source("", "depth"), plane_of(out, flat));
    ASSERT_FALSE(st);
    EXPECT_NE(st.message().find("'depth'"), std::string::npos) << st.message();
}

TEST(blur_map, OutputIntoAnImageChannelOrAStridedBufferIsTheSame) {
    const Camera cam = test_camera();
    Image img = test_image(cam);
    auto field = BlurField::parse(R"({"blurfield": {"kind": "focal_planes", "depths": [3, 9], "max_blur": 8, "slope": 4}})");
    ASSERT_TRUE(field) << field.message();
    std::vector<float> ref(img.npixels());
    ASSERT_TRUE(evaluate_blur_map(*field, cam, img, {}, plane_of(ref, img)));
    // Into the image's own channel.
    const int bc = img.add_channel({"blur", PixelType::Float});
    ASSERT_TRUE(evaluate_blur_map(*field, cam, img, {}, img.channel_view(bc)));
    EXPECT_EQ(std::vector<float>(img.plane(bc), img.plane(bc) + img.npixels()), ref);
    // Into channel 1 of an interleaved two-channel buffer: the other channel untouched.
    const Roi win = img.data_window();
    std::vector<float> inter(2 * win.npixels(), -3.0f);
    const ImageView iv = ImageView::interleaved(inter.data(), 2, win, 2 * win.width());
    ASSERT_TRUE(evaluate_blur_map(*field, cam, img, {}, iv.channels(1, 1)));
    for (int y = win.y0; y < win.y1; ++y)
        for (int x = win.x0; x < win.x1; ++x) {
            ASSERT_EQ(iv.at(1, x, y), ref[img.offset(x, y)]) << x << "," << y;
            ASSERT_EQ(iv.at(0, x, y), -3.0f);
        }
}

TEST(blur_map, AnOutputOfAnotherSizeIsAnErrorNamingBothShapes) {
    const Camera cam = test_camera();
    const Image img = test_image(cam);
    BlurField zero;
    const Roi win = img.data_window();
    std::vector<float> out(2 * img.npixels(), 5.0f);
    Status st = evaluate_blur_map(zero, cam, img, {}, ImageView::planar(out.data(), 1, Roi{0, 0, win.width(), win.height()}));
    ASSERT_FALSE(st);
    EXPECT_EQ(st.code(), StatusCode::InvalidArgument);
    EXPECT_NE(st.message().find(to_string(win)), std::string::npos) << st.message();
    EXPECT_NE(st.message().find("[0,44)x[0,28)"), std::string::npos) << st.message();
    st = evaluate_blur_map(zero, cam, img, {}, ImageView::planar(out.data(), 2, win));
    ASSERT_FALSE(st);
    EXPECT_NE(st.message().find("2 channels"), std::string::npos) << st.message();
    st = evaluate_blur_map(zero, cam, img, {}, ImageView{nullptr, 1, win, 0, 1, win.width()});
    ASSERT_FALSE(st);
    EXPECT_NE(st.message().find("without pixels"), std::string::npos) << st.message();
    for (float v : out) ASSERT_EQ(v, 5.0f);  // nothing written

    DeepImage deep({{"Z", PixelType::Float}}, Roi{0, 0, 2, 1}, Roi{0, 0, 2, 1});
    ASSERT_TRUE(deep.set_sample_counts({2, 1}));
    std::vector<float> short_out(2, 5.0f);
    st = evaluate_blur_deep(zero, cam, deep, -1, short_out);
    ASSERT_FALSE(st);
    EXPECT_EQ(st.code(), StatusCode::InvalidArgument);
    EXPECT_NE(st.message().find("2 values"), std::string::npos) << st.message();
    EXPECT_NE(st.message().find("(3)"), std::string::npos) << st.message();
    EXPECT_EQ(short_out, std::vector<float>(2, 5.0f));
}

TEST(blur_map, ResolveCameraAppliesOverridesAndNamesWhatIsMissing) {
    Metadata none;
    auto r = resolve_camera(none, Roi{0, 0, 10, 10});
    ASSERT_FALSE(r);
    EXPECT_NE(r.message().find("worldToCamera"), std::string::npos);
    LensOverrides ov;
    ov.focal_length_mm = 35;
    ov.f_number = 4;
    ov.focus_distance = 3;
    ov.sensor_width_mm = 24;
    auto c = resolve_camera(none, Roi{0, 0, 10, 10}, ov);
    ASSERT_TRUE(c) << c.message();
    auto tl = c->thin_lens();
    ASSERT_TRUE(tl) << tl.message();
    EXPECT_DOUBLE_EQ(tl->f_number, 4);
    EXPECT_DOUBLE_EQ(tl->sensor_width_mm, 24);
    // Overrides win over the file's lens attributes.
    Metadata md;
    c->to_metadata(md);
    LensOverrides f8;
    f8.f_number = 8;
    auto c2 = resolve_camera(md, Roi{0, 0, 10, 10}, f8);
    ASSERT_TRUE(c2);
    EXPECT_DOUBLE_EQ(c2->thin_lens()->f_number, 8);
    EXPECT_DOUBLE_EQ(c2->thin_lens()->focus_distance, 3);
}
