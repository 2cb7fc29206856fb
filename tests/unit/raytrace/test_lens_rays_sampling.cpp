// Aperture samples: stratification, determinism, shapes (disc, polygon, mask).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <set>
#include <vector>

#include "gdof/lens_rays.h"
#include "test_support.h"

using namespace gdof;

namespace {

// Every elementary interval of area 1/n (n = 2^k) holds exactly one sample.
void expect_net(const std::vector<Vec2>& s, int k) {
    const int n = 1 << k;
    ASSERT_EQ(int(s.size()), n);
    for (int a = 0; a <= k; ++a) {
        const int nx = 1 << a, ny = 1 << (k - a);
        std::vector<int> count(std::size_t(n), 0);
        for (const Vec2& p : s) {
            ASSERT_GE(p.x, 0.0);
            ASSERT_LT(p.x, 1.0);
            ASSERT_GE(p.y, 0.0);
            ASSERT_LT(p.y, 1.0);
            const int cx = int(p.x * nx), cy = int(p.y * ny);
            ++count[std::size_t(cy * nx + cx)];
        }
        for (int c : count) ASSERT_EQ(c, 1) << "cells " << nx << " x " << ny;
    }
}

std::vector<Vec2> samples(std::uint64_t seed, std::uint32_t first, int n) {
    std::vector<Vec2> s(std::size_t(n), Vec2{});
    unit_square_samples(seed, first, s);
    return s;
}

}  // namespace

TEST(lens_rays_sampling, every_power_of_two_prefix_is_a_net) {
    for (int px = 0; px < 6; ++px) {
        const std::uint64_t seed = pixel_seed(px, 3 * px + 1, 42);
        for (int k = 0; k <= 10; ++k) expect_net(samples(seed, 0, 1 << k), k);
    }
}

TEST(lens_rays_sampling, square_grid_cells_hit_once) {
    const std::uint64_t seed = pixel_seed(17, 5, 7);
    for (int m : {2, 4, 8, 16}) {
        const auto s = samples(seed, 0, m * m);
        std::vector<int> count(std::size_t(m * m), 0);
        for (const Vec2& p : s) ++count[std::size_t(int(p.y * m) * m + int(p.x * m))];
        for (int c : count) EXPECT_EQ(c, 1) << m << " x " << m;
    }
}

TEST(lens_rays_sampling, aligned_blocks_after_a_prefix_are_nets_too) {
    const std::uint64_t seed = pixel_seed(2, 9, 1);
    expect_net(samples(seed, 16, 16), 4);
    expect_net(samples(seed, 64, 64), 6);
}

TEST(lens_rays_sampling, deterministic_and_seeded_per_pixel) {
    const std::uint64_t a = pixel_seed(10, 20, 5);
    EXPECT_EQ(a, pixel_seed(10, 20, 5));
    std::set<std::uint64_t> seeds;
    for (int y = -2; y < 30; ++y)
        for (int x = -2; x < 30; ++x) seeds.insert(pixel_seed(x, y, 5));
    EXPECT_EQ(seeds.size(), std::size_t(32 * 32));
    EXPECT_NE(pixel_seed(10, 20, 5), pixel_seed(10, 20, 6));
    EXPECT_NE(pixel_seed(10, 20, 5), pixel_seed(20, 10, 5));

    // The same sample whatever the order or batch it is asked in.
    const auto batch = samples(a, 0, 64);
    for (int i = 63; i >= 0; --i) EXPECT_EQ(unit_square_sample(a, std::uint32_t(i)), batch[std::size_t(i)]);
    // Different pixels differ.
    const auto other = samples(pixel_seed(11, 20, 5), 0, 64);
    int same = 0;
    for (int i = 0; i < 64; ++i) same += other[std::size_t(i)] == batch[std::size_t(i)];
    EXPECT_EQ(same, 0);
}

TEST(lens_rays_sampling, mean_is_unbiased_over_pixels) {
    double sx = 0, sy = 0, sxy = 0;
    int n = 0;
    for (int px = 0; px < 64; ++px)
        for (const Vec2& p : samples(pixel_seed(px, 0, 3), 0, 8)) {
            sx += p.x;
            sy += p.y;
            sxy += p.x * p.y;
            ++n;
        }
    EXPECT_NEAR(sx / n, 0.5, 0.01);
    EXPECT_NEAR(sy / n, 0.5, 0.01);
    EXPECT_NEAR(sxy / n, 0.25, 0.01);
}

TEST(lens_rays_sampling, concentric_disc_map) {
    EXPECT_EQ(concentric_disc({0.5, 0.5}), (Vec2{0.0, 0.0}));
    for (Vec2 c : {Vec2{0, 0}, Vec2{1, 0}, Vec2{0, 1}, Vec2{1, 1}, Vec2{1, 0.5}, Vec2{0.3, 1}}) {
        const Vec2 p = concentric_disc(c);
        EXPECT_NEAR(std::hypot(p.x, p.y), 1.0, 1e-15);
    }
    // Uniform: the fraction inside radius r is r^2; quadrants equal.
    const std::uint64_t seed = pixel_seed(1, 1, 1);
    const int n = 4096;
    int inner = 0, q[4] = {0, 0, 0, 0};
    for (int i = 0; i < n; ++i) {
        const Vec2 p = concentric_disc(unit_square_sample(seed, std::uint32_t(i)));
        const double r = std::hypot(p.x, p.y);
        ASSERT_LE(r, 1.0 + 1e-15);
        inner += r < 0.5;
        ++q[(p.x >= 0 ? 1 : 0) + (p.y >= 0 ? 2 : 0)];
    }
    EXPECT_NEAR(double(inner) / n, 0.25, 0.01);
    for (int c : q) EXPECT_NEAR(double(c) / n, 0.25, 0.005);
    EXPECT_NEAR(ApertureShape::disc().area(), std::numbers::pi, 1e-15);
}

TEST(lens_rays_sampling, polygon_inside_uniform_and_rotated) {
    for (int blades : {3, 5, 6, 9}) {
        const double rot = 17.0;
        auto shape = ApertureShape::polygon(blades, rot);
        ASSERT_TRUE(shape) << shape.message();
        EXPECT_EQ(shape->kind(), ApertureShape::Kind::Polygon);
        const double step = 2 * std::numbers::pi / blades, r0 = rot * std::numbers::pi / 180;
        // Vertex k at angle r0 + k step: the corner sample of the fan hits it.
        const Vec2 v0 = shape->map({1.0 / blades - 1e-13, 1.0 - 1e-13});
        EXPECT_NEAR(v0.x, std::cos(r0 + step), 1e-9);
        EXPECT_NEAR(v0.y, std::sin(r0 + step), 1e-9);
        const std::uint64_t seed = pixel_seed(blades, 0, 9);
        const int n = 4096;
        std::vector<int> per_sector(std::size_t(blades), 0);
        int inner = 0;
        double mx = 0, my = 0;
        for (int i = 0; i < n; ++i) {
            const Vec2 p = shape->map(unit_square_sample(seed, std::uint32_t(i)));
            // Inside every edge's half plane: apothem cos(step/2).
            for (int k = 0; k < blades; ++k) {
                const double mid = r0 + (k + 0.5) * step;
                ASSERT_LE(p.x * std::cos(mid) + p.y * std::sin(mid), std::cos(step / 2) + 1e-12);
            }
            double ang = std::atan2(p.y, p.x) - r0;
            ang -= 2 * std::numbers::pi * std::floor(ang / (2 * std::numbers::pi));
            ++per_sector[std::size_t(std::min(int(ang / step), blades - 1))];
            // Points of the polygon scaled by 1/2 (a quarter of the area).
            double maxproj = 0;
            for (int k = 0; k < blades; ++k) {
                const double mid = r0 + (k + 0.5) * step;
                maxproj = std::max(maxproj, p.x * std::cos(mid) + p.y * std::sin(mid));
            }
            inner += maxproj < 0.5 * std::cos(step / 2);
            mx += p.x;
            my += p.y;
        }
        for (int c : per_sector) EXPECT_NEAR(double(c) / n, 1.0 / blades, 0.003) << blades;
        EXPECT_NEAR(double(inner) / n, 0.25, 0.01) << blades;
        EXPECT_NEAR(mx / n, 0.0, 0.01);
        EXPECT_NEAR(my / n, 0.0, 0.01);
        EXPECT_NEAR(shape->area(), 0.5 * blades * std::sin(step), 1e-12);
    }
    EXPECT_FALSE(ApertureShape::polygon(2));
    EXPECT_FALSE(ApertureShape::polygon(6, std::nan("")));
}

TEST(lens_rays_sampling, mask_cut_out) {
    // 16 x 8 mask: left half weight 3, right half 1, one zero column.
    Image img = Image::with_channels({"R", "A"}, Roi{0, 0, 16, 8});
    const int a = img.channel_index("A");
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 16; ++x) img.at(a, x, y) = x == 12 ? 0.0f : (x < 8 ? 3.0f : 1.0f);
    auto shape = ApertureShape::mask(img);  // channel "A" picked
    ASSERT_TRUE(shape) << shape.message();
    const std::uint64_t seed = pixel_seed(0, 0, 0);
    const int n = 4096;
    int left = 0;
    for (int i = 0; i < n; ++i) {
        const Vec2 p = shape->map(unit_square_sample(seed, std::uint32_t(i)));
        // The 16 x 8 window fits [-1, 1] x [-0.5, 0.5].
        ASSERT_GE(p.x, -1.0);
        ASSERT_LT(p.x, 1.0);
        ASSERT_GE(p.y, -0.5);
        ASSERT_LE(p.y, 0.5);
        // Nothing in the zero column x in [12, 13) -> u in [0.5, 0.625).
        ASSERT_FALSE(p.x > 0.5 + 1e-12 && p.x < 0.625 - 1e-12) << p.x;
        left += p.x < 0;
    }
    // Weights: left 8 columns x 3, right 7 columns x 1 -> 24 / 31.
    EXPECT_NEAR(double(left) / n, 24.0 / 31.0, 0.01);

    // Image y down -> v up: a mask lit only in its top rows gives v > 0.
    Image top = Image::with_channels({"Y"}, Roi{0, 0, 4, 4});
    for (int x = 0; x < 4; ++x) top.at(0, x, 0) = 1.0f;
    auto ts = ApertureShape::mask(top, 0);
    ASSERT_TRUE(ts);
    for (int i = 0; i < 64; ++i) EXPECT_GE(ts->map(unit_square_sample(seed, std::uint32_t(i))).y, 0.5);

    // Errors.
    Image zero = Image::with_channels({"A"}, Roi{0, 0, 4, 4});
    auto e1 = ApertureShape::mask(zero);
    ASSERT_FALSE(e1);
    EXPECT_NE(e1.message().find("no positive"), std::string::npos) << e1.message();
    auto e2 = ApertureShape::mask(img, 5);
    ASSERT_FALSE(e2);
    EXPECT_NE(e2.message().find("channel 5"), std::string::npos) << e2.message();
    img.at(a, 3, 3) = std::nanf("");
    auto e3 = ApertureShape::mask(img);
    ASSERT_FALSE(e3);
    EXPECT_NE(e3.message().find("(3, 3)"), std::string::npos) << e3.message();
    EXPECT_FALSE(ApertureShape::mask(Image{}));
}
