// The image_map displacement through the defocus pipeline (method 4): a
// constant 1-channel map is the `defocus` field with the equivalent blur,
// and a 2-channel map spreads a point into the predicted ellipse.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>

#include "defocus_test_helpers.h"
#include "gdof/defocus.h"
#include "gdof/psf_field.h"

using namespace gdof;
using namespace gdof::test;

namespace {

// A constant map (one value per channel) over `display`.
std::shared_ptr<const Image> constant_map(const Roi& display, const std::vector<float>& values) {
    std::vector<ChannelSpec> specs;
    for (std::size_t c = 0; c < values.size(); ++c) specs.push_back({std::string(1, "RGBA"[c])});
    auto img = std::make_shared<Image>(specs, display, display);
    for (int c = 0; c < img->nchannels(); ++c)
        for (std::size_t i = 0; i < img->npixels(); ++i) img->plane(c)[i] = values[std::size_t(c)];
    return img;
}

Image vibrated(const Layer& l, const Roi& display, double blur, const std::string& psf_json,
               std::shared_ptr<const Image> map, int samples) {
    DefocusOptions o;
    o.filter = DefocusFilter::Vibrate;
    o.vibrate.samples = samples;
    BlurField::Context ctx;
    ctx.images["map"] = std::move(map);
    auto f = PsfField::parse(psf_json, ctx);
    EXPECT_TRUE(f) << f.message();
    if (f) o.psf_field = f.value();
    auto out = defocus_layers({l}, constant_field(display, blur), test_camera(display), o);
    EXPECT_TRUE(out) << out.message();
    return out ? std::move(out).value() : Image{};
}

}  // namespace

// 3 px per unit aperture times scale 2 is B = 6: the same splats as
// `defocus` on B = 6 (the map's displacement does not use B).
TEST(vibrate_image_map, ConstantMapEqualsTheEquivalentDefocus) {
    const Roi display{0, 0, 80, 60};
    Layer l = make_layer(display, display, [](int x, int y) {
        const bool disc = std::hypot(x + 0.5 - 40.0, y + 0.5 - 30.0) < 14.0;
        const float a = disc ? 1.0f : 0.0f;
        return Rgba{a * texture(x, y, 0), a * texture(x, y, 1), a * 0.5f, a};
    });
    const Image ref = vibrated(l, display, 6.0, R"({"psf_field": {"kind": "defocus"}})", nullptr, 64);
    const Image map = vibrated(l, display, 6.0, R"({"psf_field": {"kind": "image_map", "image": "map", "scale": 2}})",
                               constant_map(display, {3.0f}), 64);
    const Image still = vibrated(l, display, 0.0, R"({"psf_field": {"kind": "defocus"}})", nullptr, 64);
    const double d = max_abs_diff(ref, map, display), moved = max_abs_diff(ref, still, display);
    std::printf("constant image_map (3 x 2) vs defocus B = 6: max |diff| %.3g (defocus vs sharp %.3g)\n", d, moved);
    EXPECT_LE(d, 1e-4);
    EXPECT_GT(moved, 0.1);
}

// Per-axis scales (12, 6): an HDR point spreads into the ellipse of semi-axes
// 12 px across and 6 px down, uniformly: second moments a^2 / 4 and b^2 / 4
// (plus the prefilter's sigma^2 and a pixel's 1/12), its light inside the
// ellipse, the energy kept.
TEST(vibrate_image_map, TwoChannelMapGivesThePredictedEllipse) {
    const Roi display{0, 0, 80, 60};
    Layer l = make_layer(display, display, [](int x, int y) {
        return x == 40 && y == 30 ? Rgba{1000.0f, 1000.0f, 1000.0f, 1.0f} : Rgba{0, 0, 0, 0};
    });
    const int samples = 256;
    const Image out = vibrated(l, display, 0.0, R"({"psf_field": {"kind": "image_map", "image": "map"}})",
                               constant_map(display, {12.0f, 6.0f}), samples);
    double total = 0, mx = 0, my = 0;
    for (int y = 0; y < 60; ++y)
        for (int x = 0; x < 80; ++x) {
            const double v = value_at(out, 0, x, y);
            total += v;
            mx += v * (x + 0.5);
            my += v * (y + 0.5);
        }
    mx /= total;
    my /= total;
    double vx = 0, vy = 0, cxy = 0, inside = 0;
    for (int y = 0; y < 60; ++y)
        for (int x = 0; x < 80; ++x) {
            const double v = value_at(out, 0, x, y), dx = x + 0.5 - mx, dy = y + 0.5 - my;
            vx += v * dx * dx;
            vy += v * dy * dy;
            cxy += v * dx * dy;
            // The ellipse grown by the prefilter's reach (3 sigma) and a pixel.
            if (std::hypot(dx / (12.0 + 3.5), dy / (6.0 + 3.5)) <= 1.0) inside += v;
        }
    vx /= total;
    vy /= total;
    cxy /= total;
    // The prefilter: sigma = 0.7 x the sample spacing x |dd/du| (the larger axis, 12).
    const double spacing = std::sqrt(M_PI / samples), sigma = 0.7 * spacing * 12.0;
    const double px = sigma * sigma + 1.0 / 12.0;
    std::printf("2-channel map (12, 6): centre (%.3f, %.3f), var x %.2f (predicted %.2f), var y %.2f (%.2f), "
                "cov %.3f, inside %.4f\n", mx, my, vx, 36.0 + px, vy, 9.0 + px, cxy, inside / total);
    EXPECT_NEAR(total, 1000.0, 1.0);
    EXPECT_NEAR(mx, 40.5, 0.25);  // the lattice's mean is near, not at, the centre
    EXPECT_NEAR(my, 30.5, 0.25);
    EXPECT_NEAR(vx, 36.0 + px, 0.05 * 36.0);
    EXPECT_NEAR(vy, 9.0 + px, 0.05 * 9.0 + 0.2);
    EXPECT_NEAR(cxy, 0.0, 0.2) << "the axes are the image's";
    EXPECT_GT(inside / total, 0.99);
}
