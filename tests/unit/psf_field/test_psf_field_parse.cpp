// The PSF field's JSON (docs/psf_field.md): every kind parses, displacements
// match their formulas at hand-picked points, and bad files are errors that
// name the key.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "gdof/psf_field.h"

using namespace gdof;

namespace {

PsfField parse_ok(const std::string& text) {
    auto f = PsfField::parse(text);
    EXPECT_TRUE(f) << f.message();
    return f ? f.value() : PsfField{};
}

std::string parse_error(const std::string& text) {
    auto f = PsfField::parse(text);
    EXPECT_FALSE(f) << text;
    return f ? std::string() : f.message();
}

const Roi kFrame{0, 0, 200, 100};  // centre (100, 50), half diagonal sqrt(100^2 + 50^2) / ... = 111.8

}  // namespace

TEST(psf_field, DefaultIsDefocusBTimesTheSample) {
    const PsfField f;
    const PsfPoint p{30.5, 20.5, 4.0, 8.0, nullptr};
    const PsfDisplacement d = f.displace(p, 0.5, 0.25, kFrame);
    EXPECT_DOUBLE_EQ(d.dx, 4.0);
    EXPECT_DOUBLE_EQ(d.dy, -2.0);  // v up, image y down
    EXPECT_DOUBLE_EQ(d.dz, 0.0);
    EXPECT_EQ(f.describe(), "defocus");
    EXPECT_FALSE(f.moves_depth());
}

TEST(psf_field, SwirlMovesAlongTheCircleAboutTheFrameCentre) {
    const PsfField f = parse_ok(R"({"psf_field": {"kind": "swirl", "strength": 2, "power": 1}})");
    const double hd = 0.5 * std::hypot(200.0, 100.0);
    const PsfPoint p{140.0, 50.0, 4.0, 10.0, nullptr};  // 40 px right of the centre: tangent is (0, -1)
    const PsfDisplacement d = f.displace(p, 0.0, 1.0, kFrame);  // v = 1: the image-space sample (0, -1), all tangent
    const double arc = 2.0 * 10.0 * (40.0 / hd);
    const double angle = arc / 40.0;
    EXPECT_NEAR(d.dx, 40.0 * std::cos(angle) - 40.0, 1e-9);
    EXPECT_NEAR(d.dy, -40.0 * std::sin(angle), 1e-9);
    // Still on the circle of radius 40.
    EXPECT_NEAR(std::hypot(40.0 + d.dx, d.dy), 40.0, 1e-9);
    // A radial sample does not move it.
    const PsfDisplacement r = f.displace(p, 1.0, 0.0, kFrame);
    EXPECT_NEAR(std::hypot(r.dx, r.dy), 0.0, 1e-12);
}

TEST(psf_field, DepthSumAndBlend) {
    const PsfField f = parse_ok(R"({"samples": 32, "psf_field": {"kind": "sum", "children": [
        {"kind": "defocus", "scale": 2},
        {"kind": "blend", "weight": {"kind": "region", "shape": "sphere", "center": [0, 0, 5], "radius": 1,
                                      "mode": "blur", "blur": 1},
         "children": [{"kind": "depth", "offset": 0}, {"kind": "depth", "offset": -3, "distance": 1}]}]}})");
    EXPECT_EQ(f.samples(), 32);
    EXPECT_TRUE(f.moves_depth());
    ASSERT_EQ(f.weight_count(), 1);
    EXPECT_EQ(f.describe(), "sum(defocus(x2.000000), blend(depth, depth))");
    float w = 0.5f;
    const PsfPoint p{10.5, 10.5, 5.0, 3.0, &w};
    const PsfDisplacement d = f.displace(p, 1.0, 0.0, kFrame);
    EXPECT_DOUBLE_EQ(d.dx, 6.0);
    EXPECT_DOUBLE_EQ(d.dz, 0.5 * (-3.0 + 1.0));
}

TEST(psf_field, BlendWeightIsTheBlurFieldClamped) {
    const PsfField f = parse_ok(R"({"psf_field": {"kind": "blend",
        "weight": {"kind": "region", "shape": "box", "min": [-100, -100, 9], "max": [100, 100, 11], "mode": "blur", "blur": 3},
        "children": [{"kind": "defocus"}, {"kind": "swirl"}]}})");
    CameraDesc cd;
    cd.display_window = Roi{0, 0, 64, 64};
    cd.focal_length_mm = 35.0;
    cd.sensor_width_mm = 36.0;
    auto cam = Camera::create(cd);
    ASSERT_TRUE(cam) << cam.message();
    float w = -1.0f;
    f.evaluate_weights(*cam, 32.0, 32.0, 10.0, &w);
    EXPECT_EQ(w, 1.0f);  // 3 inside, clamped
    f.evaluate_weights(*cam, 32.0, 32.0, 5.0, &w);
    EXPECT_EQ(w, 0.0f);
}

TEST(psf_field, ErrorsNameTheKey) {
    EXPECT_NE(parse_error(R"({"psf_field": {"kind": "defocus", "scal": 2}})").find("psf_field.scal"), std::string::npos);
    EXPECT_NE(parse_error(R"({"psf_field": {"kind": "spiral"}})").find("psf_field.kind"), std::string::npos);
    EXPECT_NE(parse_error(R"({"psf_field": {"kind": "swirl", "strength": "a lot"}})").find("psf_field.strength"),
              std::string::npos);
    EXPECT_NE(parse_error(R"({"psf_field": {"kind": "swirl", "power": -1}})").find("psf_field.power"), std::string::npos);
    EXPECT_NE(parse_error(R"({"psf_field": {"kind": "sum", "children": []}})").find("psf_field.children"),
              std::string::npos);
    EXPECT_NE(parse_error(R"({"psf_field": {"kind": "blend", "weight": {"kind": "region"},
                              "children": [{"kind": "defocus"}, {"kind": "defocus"}]}})")
                  .find("psf_field.weight"),
              std::string::npos);
    EXPECT_NE(parse_error(R"({"psf_field": {"kind": "blend", "weight": {"kind": "thin_lens_typo"},
                              "children": [{"kind": "defocus"}]}})")
                  .find("psf_field.weight"),
              std::string::npos);
    EXPECT_NE(parse_error(R"({"psf_field": {"kind": "defocus"}, "sample": 3})").find("sample"), std::string::npos);
    EXPECT_NE(parse_error(R"({"psf_field": {"kind": "defocus"}, "samples": -3})").find("samples"), std::string::npos);
    EXPECT_NE(parse_error(R"({"kind": "defocus"})").find("psf_field"), std::string::npos);
    EXPECT_NE(parse_error(R"({"psf_field": {"kind": "defocus"})").find("line"), std::string::npos);
}

TEST(psf_field, ApertureSamplesAreAnEvenLatticeAndDeterministic) {
    double spacing = 0;
    auto a = aperture_samples(Aperture{}, 64, 7, &spacing);
    ASSERT_TRUE(a) << a.message();
    ASSERT_NEAR(double(a->size()), 64.0, 2.0);
    EXPECT_NEAR(spacing, std::sqrt(M_PI / 64.0), 0.05 * std::sqrt(M_PI / 64.0));
    // Even: every sample's nearest neighbour is one lattice spacing away.
    for (const auto& s : *a) {
        double nearest = 1e9;
        for (const auto& t : *a)
            if (&s != &t) nearest = std::min(nearest, std::hypot(s.u - t.u, s.v - t.v));
        EXPECT_NEAR(nearest, spacing, 1e-9);
    }
    double mu = 0, mv = 0;
    for (const auto& s : *a) {
        EXPECT_LE(std::hypot(s.u, s.v), 1.0 + 1e-12);
        mu += s.u;
        mv += s.v;
    }
    EXPECT_NEAR(mu / double(a->size()), 0.0, 0.05);  // even: the mean is near the centre
    EXPECT_NEAR(mv / double(a->size()), 0.0, 0.05);
    auto b = aperture_samples(Aperture{}, 64, 7);
    ASSERT_EQ(a->size(), b->size());
    for (std::size_t i = 0; i < a->size(); ++i) EXPECT_EQ((*a)[i].u, (*b)[i].u);
    Aperture hex;
    hex.kind = Aperture::Kind::Polygon;
    hex.blades = 6;
    auto h = aperture_samples(hex, 100, 1);
    ASSERT_TRUE(h) << h.message();
    EXPECT_NEAR(double(h->size()), 100.0, 20.0);
    for (const auto& s : *h) EXPECT_TRUE(aperture_contains(hex, s.u, s.v));
    Aperture cat;
    cat.cats_eye = 0.5;
    auto c = aperture_samples(cat, 16, 1);
    ASSERT_FALSE(c);
    EXPECT_NE(c.message().find("cats_eye"), std::string::npos);
}

TEST(psf_field, ExampleFilesParse) {
    const std::filesystem::path dir = std::filesystem::path(GDOF_SOURCE_DIR) / "examples" / "psf_fields";
    int n = 0;
    for (const auto& e : std::filesystem::directory_iterator(dir)) {
        if (e.path().extension() != ".json") continue;
        std::ifstream f(e.path());
        const std::string text((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
        auto p = PsfField::parse(text);
        EXPECT_TRUE(p) << e.path() << ": " << p.message();
        ++n;
    }
    EXPECT_GE(n, 3);
}

namespace {

// A constant map with the given channel values over a 20x10 display window
// (half the size of kFrame in each axis: it is stretched over the frame).
std::shared_ptr<const Image> constant_map(const std::vector<std::string>& names, const std::vector<float>& values) {
    std::vector<ChannelSpec> specs;
    for (const auto& n : names) specs.push_back({n});
    const Roi w{0, 0, 20, 10};
    auto img = std::make_shared<Image>(specs, w, w);
    for (int c = 0; c < img->nchannels(); ++c)
        for (std::size_t i = 0; i < img->npixels(); ++i) img->plane(c)[i] = values[std::size_t(c)];
    return img;
}

PsfField parse_with(const std::string& text, const std::string& name, std::shared_ptr<const Image> img) {
    BlurField::Context ctx;
    ctx.images[name] = std::move(img);
    auto f = PsfField::parse(text, ctx);
    EXPECT_TRUE(f) << f.message();
    return f ? f.value() : PsfField{};
}

}  // namespace

// image_map: the map's channels are a linear map of the image-space sample
// (u, -v) in pixels per unit aperture, times scale.
TEST(psf_field, ImageMapIsALinearMapOfTheSample) {
    const PsfPoint p{30.5, 20.5, 4.0, 8.0, nullptr};
    const PsfField iso = parse_with(R"({"psf_field": {"kind": "image_map", "image": "m", "scale": 2}})", "m",
                                    constant_map({"Y"}, {3.0f}));
    PsfDisplacement d = iso.displace(p, 0.5, 0.25, kFrame);
    EXPECT_DOUBLE_EQ(d.dx, 3.0);   // 2 * 3 * 0.5
    EXPECT_DOUBLE_EQ(d.dy, -1.5);  // 2 * 3 * -0.25: v up, image y down
    EXPECT_EQ(iso.describe(), "image_map(m)");
    const PsfField axes = parse_with(R"({"psf_field": {"kind": "image_map", "image": "m"}})", "m",
                                     constant_map({"R", "G"}, {12.0f, 6.0f}));
    d = axes.displace(p, 1.0, -1.0, kFrame);
    EXPECT_DOUBLE_EQ(d.dx, 12.0);
    EXPECT_DOUBLE_EQ(d.dy, 6.0);
    // A full matrix [[2, 1], [0, 3]] on (0.5, -0.25), channels picked by name in matrix order.
    const PsfField matrix = parse_with(
        R"({"psf_field": {"kind": "image_map", "image": "m", "channels": ["A", "B", "G", "R"]}})", "m",
        constant_map({"R", "G", "B", "A"}, {3.0f, 0.0f, 1.0f, 2.0f}));
    d = matrix.displace(p, 0.5, 0.25, kFrame);
    EXPECT_DOUBLE_EQ(d.dx, 2.0 * 0.5 + 1.0 * -0.25);
    EXPECT_DOUBLE_EQ(d.dy, 3.0 * -0.25);
    EXPECT_DOUBLE_EQ(d.dz, 0.0);
}

// Sampled as the blur field's image_map: the map's display window stretched
// over the frame, bilinear between pixel centres.
TEST(psf_field, ImageMapIsStretchedOverTheFrameAndInterpolated) {
    auto ramp = std::make_shared<Image>(std::vector<ChannelSpec>{{"Y"}}, Roi{0, 0, 20, 10}, Roi{0, 0, 20, 10});
    for (int y = 0; y < 10; ++y)
        for (int x = 0; x < 20; ++x) ramp->at(0, x, y) = float(x);  // value = map column
    const PsfField f = parse_with(R"({"psf_field": {"kind": "image_map", "image": "m"}})", "m", ramp);
    // kFrame is 200 wide: frame x = 10 * (map x + 0.5); frame x 105 is map x 10 (a pixel centre),
    // frame x 110 half way between map columns 10 and 11.
    EXPECT_DOUBLE_EQ(f.displace({105.0, 50.0, 1.0, 0.0, nullptr}, 1.0, 0.0, kFrame).dx, 10.0);
    EXPECT_DOUBLE_EQ(f.displace({110.0, 50.0, 1.0, 0.0, nullptr}, 1.0, 0.0, kFrame).dx, 10.5);
    EXPECT_DOUBLE_EQ(f.displace({1.0, 50.0, 1.0, 0.0, nullptr}, 1.0, 0.0, kFrame).dx, 0.0);  // clamped at the edge
}

TEST(psf_field, ImageMapErrorsNameTheKeyAndTheImage) {
    BlurField::Context ctx;
    ctx.images["rgb"] = constant_map({"R", "G", "B"}, {1, 1, 1});
    auto three = PsfField::parse(R"({"psf_field": {"kind": "image_map", "image": "rgb"}})", ctx);
    ASSERT_FALSE(three);
    EXPECT_NE(three.message().find("psf_field.image"), std::string::npos) << three.message();
    EXPECT_NE(three.message().find("3 channels"), std::string::npos) << three.message();
    auto missing = PsfField::parse(R"({"psf_field": {"kind": "image_map", "image": "rgb", "channels": ["R", "Q"]}})", ctx);
    ASSERT_FALSE(missing);
    EXPECT_NE(missing.message().find("psf_field.channels[1]"), std::string::npos) << missing.message();
    EXPECT_NE(missing.message().find("\"Q\""), std::string::npos) << missing.message();
    auto nofile = PsfField::parse(R"({"psf_field": {"kind": "image_map", "image": "paint.exr"}})");
    ASSERT_FALSE(nofile);
    EXPECT_NE(nofile.message().find("psf_field.image"), std::string::npos) << nofile.message();
    EXPECT_NE(nofile.message().find("paint.exr"), std::string::npos) << nofile.message();
    EXPECT_NE(parse_error(R"({"psf_field": {"kind": "image_map", "image": "rgb", "scal": 1}})").find("psf_field.scal"),
              std::string::npos);
}
