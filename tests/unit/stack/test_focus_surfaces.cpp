// Focus surfaces: the B-spline against hand-computed values (approximating
// by default, interpolating on request), the JSON, maps, and near/far from a
// blur field along pixel rays.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "gdof/blur_field.h"
#include "gdof/camera.h"
#include "gdof/focus_surfaces.h"
#include "test_support.h"

namespace gdof {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

BSplineSurface make(int nx, int ny, std::vector<double> v, bool interpolate = false) {
    auto r = BSplineSurface::create(nx, ny, std::move(v), interpolate);
    EXPECT_TRUE(r) << r.message();
    return r ? r.value() : BSplineSurface{};
}

// Control points P = [0, 6, 0, 0] along u (knots at u = 0, 1/3, 2/3, 1).
// By hand, with the uniform cubic basis (1/6)[(1-t)^3, 3t^3-6t^2+4, -3t^3+3t^2+3t+1, t^3]
// and the phantom P[-1] = 2 P[0] - P[1] = -6, P[4] = 2 P[3] - P[2] = 0:
//   u = 0   : (P[-1] + 4 P[0] + P[1]) / 6 = (-6 + 0 + 6) / 6 = 0
//   u = 1/3 : (P[0] + 4 P[1] + P[2]) / 6 = 24 / 6 = 4
//   u = 2/3 : (P[1] + 4 P[2] + P[3]) / 6 = 6 / 6 = 1
//   u = 1/2 : segment 1, t = 1/2, weights (1/48, 23/48, 23/48, 1/48): 6 * 23/48 = 2.875
//   u = 1   : P[3] = 0
TEST(focus_surfaces, bspline_approximates_hand_computed_1d) {
    const BSplineSurface s = make(4, 1, {0, 6, 0, 0});
    EXPECT_NEAR(s.evaluate(0.0, 0.5), 0.0, 1e-12);
    EXPECT_NEAR(s.evaluate(1.0 / 3.0, 0.5), 4.0, 1e-12);
    EXPECT_NEAR(s.evaluate(2.0 / 3.0, 0.5), 1.0, 1e-12);
    EXPECT_NEAR(s.evaluate(0.5, 0.5), 2.875, 1e-12);
    EXPECT_NEAR(s.evaluate(1.0, 0.5), 0.0, 1e-12);
    // u = 1/6: segment 0, t = 1/2: P[-1..2] = (-6, 0, 6, 0): (-6 + 6 * 23) / 48 = 2.75
    EXPECT_NEAR(s.evaluate(1.0 / 6.0, 0.5), 2.75, 1e-12);
    // Same along v (a 1-wide column).
    const BSplineSurface c = make(1, 4, {0, 6, 0, 0});
    EXPECT_NEAR(c.evaluate(0.3, 1.0 / 3.0), 4.0, 1e-12);
    EXPECT_NEAR(c.evaluate(0.9, 0.5), 2.875, 1e-12);
}

// Tensor product: a single 6 at control point (1, 1) of a 4 x 4 grid of zeros.
//   at (1/3, 1/3): (4/6) * (4/6) * 6 = 8/3
//   at (1/3, 2/3): (4/6) * (1/6) * 6 = 2/3
//   at (1/2, 1/2): (23/48)^2 * 6
TEST(focus_surfaces, bspline_tensor_product_hand_computed) {
    std::vector<double> g(16, 0.0);
    g[1 * 4 + 1] = 6.0;
    const BSplineSurface s = make(4, 4, g);
    EXPECT_NEAR(s.evaluate(1.0 / 3.0, 1.0 / 3.0), 8.0 / 3.0, 1e-12);
    EXPECT_NEAR(s.evaluate(1.0 / 3.0, 2.0 / 3.0), 2.0 / 3.0, 1e-12);
    EXPECT_NEAR(s.evaluate(0.5, 0.5), 6.0 * (23.0 / 48.0) * (23.0 / 48.0), 1e-12);
    EXPECT_NEAR(s.evaluate(0.0, 0.0), 0.0, 1e-12);
}

TEST(focus_surfaces, corners_and_bilinear_grids_are_exact) {
    // z = 2 + 0.5 i + 0.25 j at control (i, j): the surface is that plane.
    const int nx = 5, ny = 3;
    std::vector<double> g;
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) g.push_back(2.0 + 0.5 * i + 0.25 * j);
    const BSplineSurface s = make(nx, ny, g);
    for (double u : {0.0, 0.1, 0.37, 0.5, 0.99, 1.0})
        for (double v : {0.0, 0.2, 0.5, 0.77, 1.0})
            EXPECT_NEAR(s.evaluate(u, v), 2.0 + 0.5 * u * (nx - 1) + 0.25 * v * (ny - 1), 1e-12) << u << "," << v;
    // Corners of an arbitrary grid are hit.
    const BSplineSurface t = make(3, 3, {1, 7, 2, 9, 3, 8, 4, 6, 5});
    EXPECT_NEAR(t.evaluate(0, 0), 1, 1e-12);
    EXPECT_NEAR(t.evaluate(1, 0), 2, 1e-12);
    EXPECT_NEAR(t.evaluate(0, 1), 4, 1e-12);
    EXPECT_NEAR(t.evaluate(1, 1), 5, 1e-12);
    // ... but not the interior control point (approximation): (4/6)^2 * 3 + ... != 3.
    EXPECT_GT(std::abs(t.evaluate(0.5, 0.5) - 3.0), 0.5);
}

// Interpolating mode on [0, 6, 0, 0]: by hand, P[0] = 0, P[3] = 0 and
//   4 P[1] + P[2] = 36, P[1] + 4 P[2] = 0  ->  P[1] = 9.6, P[2] = -2.4
TEST(focus_surfaces, bspline_interpolates_when_asked) {
    const BSplineSurface s = make(4, 1, {0, 6, 0, 0}, true);
    ASSERT_EQ(s.control_points().size(), 4u);
    EXPECT_NEAR(s.control_points()[1], 9.6, 1e-12);
    EXPECT_NEAR(s.control_points()[2], -2.4, 1e-12);
    EXPECT_NEAR(s.evaluate(1.0 / 3.0, 0), 6.0, 1e-12);
    EXPECT_NEAR(s.evaluate(2.0 / 3.0, 0), 0.0, 1e-12);
    // 2D: passes through every control value at its grid position.
    const std::vector<double> g = {1, 7, 2, 5, 9, 3, 8, 1, 4, 6, 5, 2};
    const BSplineSurface t = make(4, 3, g, true);
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 4; ++i) EXPECT_NEAR(t.evaluate(i / 3.0, j / 2.0), g[std::size_t(j * 4 + i)], 1e-12);
    EXPECT_FALSE(BSplineSurface::create(2, 1, {1, kInf}, true));
}

TEST(focus_surfaces, infinity_propagates_only_where_it_has_weight) {
    // Far grid: right column infinite.
    const BSplineSurface s = make(4, 1, {2, 2, 2, kInf});
    EXPECT_TRUE(std::isinf(s.evaluate(1.0, 0)));
    EXPECT_TRUE(std::isinf(s.evaluate(0.5, 0)));             // P[3] has weight in segment 1
    EXPECT_NEAR(s.evaluate(1.0 / 3.0, 0), 2.0, 1e-12);         // knot 1: weights on P[0..2] only
    EXPECT_NEAR(s.evaluate(0.1, 0), 2.0, 1e-12);
}

// The separable whole-image evaluation is evaluate() at every pixel centre,
// bit for bit: grids of every shape (1x1, single rows / columns, larger),
// approximating and interpolating, with infinite control points, odd sizes,
// any thread count.
TEST(focus_surfaces, evaluate_pixels_is_evaluate_at_pixel_centres_bit_for_bit) {
    std::vector<BSplineSurface> surfaces = {make(1, 1, {3.5}), make(4, 1, {2, 2, 2, kInf}), make(1, 3, {1, kInf, 4}),
                                            make(3, 2, {1, 2, 3, 4, 5, 6}, true)};
    std::vector<double> big(7 * 5);
    for (std::size_t i = 0; i < big.size(); ++i) big[i] = 1.0 + std::sin(double(i) * 1.7) * 0.9;
    surfaces.push_back(make(7, 5, big));
    big[12] = kInf;
    surfaces.push_back(make(7, 5, big));
    for (const BSplineSurface& s : surfaces)
        for (auto [w, h] : {std::pair{1, 1}, std::pair{97, 31}, std::pair{256, 7}})
            for (int threads : {1, 2, 5}) {
                Exec e;
                e.nthreads = threads;
                std::vector<float> out(std::size_t(w) * std::size_t(h), -1.0f);
                ASSERT_TRUE(s.evaluate_pixels(w, h, out.data(), e));
                for (int y = 0; y < h; ++y)
                    for (int x = 0; x < w; ++x) {
                        const float ref = float(s.evaluate((x + 0.5) / w, (y + 0.5) / h));
                        const float got = out[std::size_t(y) * std::size_t(w) + std::size_t(x)];
                        ASSERT_TRUE(got == ref || (std::isnan(got) && std::isnan(ref)))
                            << s.nx() << "x" << s.ny() << " at " << x << "," << y << ": " << got << " vs " << ref;
                    }
            }
}

TEST(focus_surfaces, json_surfaces_and_errors) {
    auto r = parse_focus_surfaces(R"({"gdof_surfaces": 1,
        "near": {"grid": [[1, 2], [3, 4]]},
        "far": "inf"})");
    ASSERT_TRUE(r) << r.message();
    EXPECT_EQ(r->near.nx(), 2);
    EXPECT_EQ(r->near.ny(), 2);
    EXPECT_NEAR(r->near.evaluate(1, 0), 2.0, 1e-12);  // top row first
    EXPECT_NEAR(r->near.evaluate(0, 1), 3.0, 1e-12);
    EXPECT_TRUE(std::isinf(r->far.evaluate(0.3, 0.3)));

    auto d = desired_from_surfaces(r.value(), 4, 2);
    ASSERT_TRUE(d) << d.message();
    // Pixel (0, 0) centre at u = 1/8, v = 1/4: bilinear 1 + 1/8 + 2/4
    EXPECT_NEAR(d->near[0], 1.0 + 0.125 + 0.5, 1e-6);
    EXPECT_TRUE(std::isinf(d->far[7]));

    auto interp = parse_focus_surfaces(R"({"interpolate": true, "near": {"grid": [[0, 6, 0, 0]]}, "far": 9})");
    ASSERT_TRUE(interp) << interp.message();
    EXPECT_NEAR(interp->near.evaluate(1.0 / 3.0, 0.5), 6.0, 1e-12);

    auto err = [](const std::string& json, const std::string& needle) {
        auto e = parse_focus_surfaces(json);
        ASSERT_FALSE(e) << json;
        EXPECT_NE(e.message().find(needle), std::string::npos) << e.message();
    };
    err(R"({"near": {"grid": [[1, 2], [3]]}, "far": 4})", "near.grid[1]: has 1 values, row 0 has 2");
    err(R"({"near": 1, "far": {"grid": [[1, 2], [3, "x"]]}})", "far.grid[1][1]: must be a number or \"inf\", got string \"x\"");
    err(R"({"near": 1, "far": {"grid": [[1, -2]]}})", "far.grid[0][1]: must be >= 0");
    err(R"({"near": 1})", "far: missing required key");
    err(R"({"near": 1, "far": 2, "farr": 3})", "farr: unknown key");
    err(R"({"near": {"points": [[1]]}, "far": 2})", "near.points: unknown key");
    err(R"({"near": {"grid": [[1, "inf"]], "interpolate": true}, "far": 2})", "near: \"interpolate\": true cannot");
}

TEST(focus_surfaces, maps) {
    Image n = Image::with_channels({"near"}, {0, 0, 3, 2});
    Image f = Image::with_channels({"R", "far"}, {5, 5, 8, 7});
    for (std::size_t i = 0; i < 6; ++i) n.plane(0)[i] = float(i), f.plane(1)[i] = float(10 + i);
    EXPECT_EQ(find_focus_map_channel(n, "near"), 0);
    EXPECT_EQ(find_focus_map_channel(f, "far"), 1);
    auto d = desired_from_maps(n, 0, f, 1);
    ASSERT_TRUE(d) << d.message();
    EXPECT_EQ(d->window, (Roi{0, 0, 3, 2}));
    EXPECT_EQ(d->near[4], 4.0f);
    EXPECT_EQ(d->far[4], 14.0f);
    Image g = Image::with_channels({"far"}, {0, 0, 2, 2});
    auto bad = desired_from_maps(n, 0, g, 0);
    ASSERT_FALSE(bad);
    EXPECT_NE(bad.message().find("3x2"), std::string::npos) << bad.message();
    EXPECT_NE(bad.message().find("2x2"), std::string::npos) << bad.message();
}

Camera test_camera(int w, int h) {
    CameraDesc cd;
    cd.display_window = {0, 0, w, h};
    cd.focal_length_mm = 50;
    cd.sensor_width_mm = 36;
    auto c = Camera::create(cd);
    EXPECT_TRUE(c) << c.message();
    return c.value();
}

TEST(focus_surfaces, from_a_thin_lens_field_equals_its_dof_limits) {
    const int W = 32, H = 16;
    const Camera cam = test_camera(W, H);
    ThinLens lens;
    lens.focal_length_mm = 50;
    lens.f_number = 4;
    lens.focus_distance = 3;
    lens.sensor_width_mm = 36;
    lens.image_width_px = W;
    auto field = BlurField::from_thin_lens(lens);
    ASSERT_TRUE(field) << field.message();
    Image z = Image::with_channels({"Z"}, {0, 0, W, H});
    for (std::size_t i = 0; i < z.npixels(); ++i) z.plane(0)[i] = 1.0f + float(i % 7);
    BlurFocusOptions bs;
    bs.coc_px = 0.05;  // tiny image: a small CoC keeps a finite far
    auto d = desired_from_blur_field(field.value(), cam, z, bs);
    ASSERT_TRUE(d) << d.message();
    const auto lim = lens.dof_limits(0.05);
    for (std::size_t i = 0; i < d->npixels(); i += 37) {
        EXPECT_NEAR(d->near[i], lim.near, 1e-4 * lim.near) << i;
        EXPECT_NEAR(d->far[i], lim.far, 1e-4 * lim.far) << i;
    }
}

TEST(focus_surfaces, two_focal_planes_choose_the_interval_at_the_pixel_depth) {
    const int W = 8, H = 4;
    const Camera cam = test_camera(W, H);
    auto field = BlurField::parse(R"({"blurfield": {"kind": "focal_planes", "depths": [2.0, 10.0],
                                     "max_blur": 10, "slope": 8, "interpolation": "linear"}})");
    ASSERT_TRUE(field) << field.message();
    Image z = Image::with_channels({"Z"}, {0, 0, W, H});
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) z.at(0, x, y) = x < 4 ? 2.0f : 11.0f;
    BlurFocusOptions bs;
    bs.coc_px = 0.5;
    auto d = desired_from_blur_field(field.value(), cam, z, bs);
    ASSERT_TRUE(d) << d.message();
    // Left: the interval around 2; right (at 11, out of focus): the nearest, around 10.
    EXPECT_LT(d->near[0], 2.0f);
    EXPECT_GT(d->far[0], 2.0f);
    EXPECT_LT(d->far[0], 3.0f);
    EXPECT_LT(d->near[7], 10.0f);
    EXPECT_GT(d->near[7], 5.0f);
    EXPECT_GT(d->far[7], 10.0f);

    // choose_interval directly: inside, nearest in inverse depth, sky, unknown.
    InFocusIntervals iv;
    iv.intervals = {{1.8, 2.2}, {9, 11}};
    iv.min_depth = 2.0;
    EXPECT_EQ(choose_interval(iv, 2.1).near, 1.8);
    EXPECT_EQ(choose_interval(iv, 5.0).near, 9.0);   // 1/5 - 1/9 < 1/2.2 - 1/5
    EXPECT_EQ(choose_interval(iv, 3.0).near, 1.8);
    EXPECT_EQ(choose_interval(iv, kInf).near, 9.0);  // sky: the farthest
    EXPECT_EQ(choose_interval(iv, std::nan("")).near, 1.8);  // primary
}

TEST(focus_surfaces, region_field_on_a_grid_matches_per_pixel_search) {
    // A sphere of focus: B varies across the image, so rays are searched on a grid.
    const int W = 24, H = 12;
    const Camera cam = test_camera(W, H);
    auto field = BlurField::parse(R"({"blurfield": {"kind": "region", "shape": "sphere", "center": [0, 0, 4],
        "radius": 1.0, "mode": "focus", "blur": 8, "falloff": 1.0, "interpolation": "linear"}})");
    ASSERT_TRUE(field) << field.message();
    Image z = Image::with_channels({"Z"}, {0, 0, W, H});
    for (std::size_t i = 0; i < z.npixels(); ++i) z.plane(0)[i] = 4.0f;
    BlurFocusOptions exact, coarse;
    exact.coc_px = coarse.coc_px = 1.0;
    exact.grid_step = 1;
    coarse.grid_step = 4;
    auto a = desired_from_blur_field(field.value(), cam, z, exact);
    auto b = desired_from_blur_field(field.value(), cam, z, coarse);
    ASSERT_TRUE(a) << a.message();
    ASSERT_TRUE(b) << b.message();
    // Grid nodes agree exactly; the centre ray passes through the sphere.
    EXPECT_EQ(a->near[0], b->near[0]);
    EXPECT_EQ(a->far[4 * W + 8], b->far[4 * W + 8]);
    const std::size_t c = std::size_t(H / 2) * W + W / 2;
    EXPECT_LT(a->near[c], 4.0f);
    EXPECT_GT(a->far[c], 4.0f);
}

}  // namespace
}  // namespace gdof
