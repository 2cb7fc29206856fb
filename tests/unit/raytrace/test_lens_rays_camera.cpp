// Nonlinear (polyline) camera of method 1: pinhole equality, thin-lens
// equality, CoC discs, focal planes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "gdof/lens_rays.h"
#include "lens_rays_test_helpers.h"
#include "test_support.h"

using namespace gdof;
using namespace gdof::test;

namespace {

const std::vector<std::pair<double, double>> kPixels = {
    {160.5, 120.5}, {0.5, 0.5}, {319.5, 239.5}, {17.25, 201.75}, {300.5, 3.5}};

}  // namespace

TEST(lens_rays_camera, zero_field_is_the_pinhole_ray_bit_for_bit) {
    const Camera cam = make_camera(35.0, 320, 240, {1, 2, -3}, {0.3, 1.7, 4});
    const NonlinearCamera nl = make_nl(cam, BlurField());
    PixelCone cone;
    PolylineRay ray;
    for (auto [px, py] : kPixels) {
        ASSERT_TRUE(nl.prepare(px, py, cone));
        EXPECT_TRUE(cone.pinhole);
        EXPECT_EQ(cone.max_blur_px, 0.0);
        const CameraRay pin = cam.central_ray(px, py);
        for (std::uint32_t i = 0; i < 32; ++i) {
            nl.ray_from_unit(cone, unit_square_sample(pixel_seed(int(px), int(py), 1), i), ray);
            ASSERT_EQ(ray.points.size(), 1u);
            EXPECT_EQ(ray.points[0], pin.origin);
            EXPECT_EQ(ray.far_direction, pin.direction);
        }
    }
}

TEST(lens_rays_camera, thin_lens_field_equals_straight_thin_lens) {
    for (double f : {24.0, 50.0, 135.0}) {
        for (double s : {0.5, 2.0, 7.0}) {
            const Camera cam = make_camera(f, 320, 240, {0.5, -1, 2}, {1, 0, 9});
            const ThinLens lens = make_lens(cam, f, 2.0, s);
            auto field = BlurField::from_thin_lens(lens);
            ASSERT_TRUE(field) << field.message();
            const NonlinearCamera nl = make_nl(cam, *field);
            const double R = thin_lens_equivalent_radius(lens);
            EXPECT_NEAR(R, f / 4.0 / 1000.0 * (s * 1000) / (s * 1000 - f), 1e-15);
            PixelCone cone;
            PolylineRay ray;
            for (auto [px, py] : kPixels) {
                ASSERT_TRUE(nl.prepare(px, py, cone));
                ASSERT_FALSE(cone.pinhole);
                // rho is linear on each side of s: lens point, focus point, then straight.
                ASSERT_EQ(cone.depth.size(), 2u) << "f " << f << " s " << s;
                EXPECT_EQ(cone.depth[0], 0.0);
                EXPECT_EQ(cone.rho[1], 0.0);
                ASSERT_EQ(cone.in_focus.size(), 1u);
                EXPECT_NEAR(cone.in_focus[0], s, 1e-12 * s);
                EXPECT_NEAR(cone.rho[0], R, 1e-12 * R);
                for (std::uint32_t i = 0; i < 16; ++i) {
                    const Vec2 a = nl.shape().map(unit_square_sample(pixel_seed(int(px), int(py), 3), i));
                    nl.ray(cone, a, ray);
                    const CameraRay ref = thin_lens_ray(cam, px, py, R, s, a);
                    EXPECT_LE(dist(ray.points[0], ref.origin), 1e-12);
                    for (double z : {0.0, 0.003, 0.3, 0.9 * s, s, 1.7 * s, 25.0, 999.0, 1e4, 1e7}) {
                        const Vec3 p = polyline_at(cam, ray, z);
                        const Vec3 q = ref.at(z / ref.depth_per_t);
                        const double scale = R * std::fabs(z - s) / s + 1e-300;
                        EXPECT_LE(dist(p, q), 1e-9 * (scale + z * 1e-3))
                            << "f " << f << " s " << s << " z " << z << " px " << px;
                        EXPECT_NEAR(depth_of(cam, p), z, 1e-9 * (1 + z));
                    }
                    const Vec3 far_dir = ray.far_direction;
                    EXPECT_LE(length(far_dir - ref.direction), 1e-12);
                }
            }
        }
    }
}

TEST(lens_rays_camera, thin_lens_radius_factor_is_v_over_f) {
    const Camera cam = make_camera();
    const ThinLens lens = make_lens(cam, 50.0, 2.8, 2.0);
    EXPECT_NEAR(thin_lens_aperture_radius(lens), 0.050 / 5.6, 1e-15);
    EXPECT_NEAR(thin_lens_equivalent_radius(lens) / thin_lens_aperture_radius(lens), 2000.0 / 1950.0, 1e-14);
    // The textbook radius f / (2N) gives a CoC smaller than ThinLens by (s - f) / s.
    const double z = 5.0, s = 2.0;
    const double pbrt_px = thin_lens_aperture_radius(lens) * std::fabs(z - s) / s * cam.focal_length_px() / z;
    EXPECT_NEAR(pbrt_px / lens.coc_radius_px(z), 1950.0 / 2000.0, 1e-12);
}

TEST(lens_rays_camera, point_off_focus_images_as_coc_disc) {
    const Camera cam = make_camera(50.0, 640, 480);
    const ThinLens lens = make_lens(cam, 50.0, 1.8, 2.0);
    auto field = BlurField::from_thin_lens(lens);
    ASSERT_TRUE(field);
    const NonlinearCamera nl = make_nl(cam, *field);
    PixelCone cone;
    for (auto [px, py] : std::vector<std::pair<double, double>>{{320.5, 240.5}, {10.5, 470.5}, {600.25, 33.5}}) {
        ASSERT_TRUE(nl.prepare(px, py, cone));
        for (double z : {0.6, 1.2, 1.9, 2.3, 5.0, 40.0}) {
            const double coc = lens.coc_radius_px(z);
            // Crossings of the pixel's rays with the plane at depth z, projected:
            // the rim of the aperture lands exactly on the CoC circle ...
            for (int k = 0; k < 32; ++k) {
                const double ang = 2 * std::numbers::pi * k / 32;
                const PixelDepth q = cam.project(nl.point_at(cone, {std::cos(ang), std::sin(ang)}, z));
                EXPECT_NEAR(q.depth, z, 1e-12 * z);
                EXPECT_NEAR(std::hypot(q.x - px, q.y - py), coc, 1e-6 * coc + 1e-9) << "z " << z;
            }
            // ... and stratified samples fill the disc up to it.
            double rmax = 0, rsum = 0;
            const int n = 256;
            for (int i = 0; i < n; ++i) {
                const Vec2 a = nl.shape().map(unit_square_sample(pixel_seed(int(px), int(py), 0), std::uint32_t(i)));
                const PixelDepth q = cam.project(nl.point_at(cone, a, z));
                const double r = std::hypot(q.x - px, q.y - py);
                rmax = std::max(rmax, r);
                rsum += r;
            }
            EXPECT_LE(rmax, coc * (1 + 1e-9));
            EXPECT_GE(rmax, 0.95 * coc);
            EXPECT_NEAR(rsum / n, 2.0 / 3.0 * coc, 0.02 * coc);  // uniform disc: mean radius 2R/3
        }
    }
}

TEST(lens_rays_camera, focal_planes_cross_at_each_in_focus_depth) {
    const Camera cam = make_camera(50.0, 320, 240, {0, 1, 0}, {0.2, 1, 5});
    const BlurField field =
        parse_ok(R"({"blurfield": {"kind": "focal_planes", "depths": [2, 5], "max_blur": 6}})");
    const NonlinearCamera nl = make_nl(cam, field);
    PixelCone cone;
    PolylineRay ray;
    for (auto [px, py] : kPixels) {
        ASSERT_TRUE(nl.prepare(px, py, cone));
        ASSERT_EQ(cone.in_focus.size(), 2u);
        EXPECT_DOUBLE_EQ(cone.in_focus[0], 2.0);
        EXPECT_DOUBLE_EQ(cone.in_focus[1], 5.0);
        // Signs: + before 2, - between, + after 5.
        EXPECT_GT(NonlinearCamera::rho_at(cone, 1.0), 0);
        EXPECT_LT(NonlinearCamera::rho_at(cone, 3.5), 0);
        EXPECT_GT(NonlinearCamera::rho_at(cone, 8.0), 0);
        // |rho| reproduces B in pixels.
        for (double z : {0.5, 1.0, 1.99, 2.5, 3.5, 4.9, 6.0, 50.0})
            EXPECT_NEAR(std::fabs(NonlinearCamera::rho_at(cone, z)) / nl.footprint(z),
                        field.evaluate_on_ray(cam, px, py, z), 0.02)
                << z;
        for (std::uint32_t i = 0; i < 16; ++i) {
            nl.ray_from_unit(cone, unit_square_sample(pixel_seed(3, 4, 5), i), ray);
            int hits = 0;
            for (std::size_t k = 0; k < ray.points.size(); ++k)
                if (ray.depth[k] == 2.0 || ray.depth[k] == 5.0) {
                    // Exactly the central ray's point at that depth.
                    EXPECT_EQ(ray.points[k], cone.line.at(ray.depth[k]));
                    ++hits;
                }
            EXPECT_EQ(hits, 2);
            // Depth increases along the polyline and each vertex sits at its depth.
            for (std::size_t k = 0; k < ray.points.size(); ++k) {
                EXPECT_NEAR(depth_of(cam, ray.points[k]), ray.depth[k], 1e-12 * (1 + ray.depth[k]));
                if (k) {
                    EXPECT_GT(ray.depth[k], ray.depth[k - 1]);
                }
            }
        }
    }
}

TEST(lens_rays_camera, retarget_matches_prepare_for_depth_only_fields) {
    const Camera cam = make_camera();
    auto field = BlurField::from_thin_lens(make_lens(cam));
    ASSERT_TRUE(field);
    const NonlinearCamera nl = make_nl(cam, *field);
    ASSERT_TRUE(nl.depth_only());
    PixelCone a, b;
    ASSERT_TRUE(nl.prepare(160.5, 120.5, a));
    nl.retarget(a, 7.5, 230.5);
    ASSERT_TRUE(nl.prepare(7.5, 230.5, b));
    ASSERT_EQ(a.depth.size(), b.depth.size());
    for (std::size_t i = 0; i < a.depth.size(); ++i) {
        EXPECT_NEAR(a.depth[i], b.depth[i], 1e-12 * (1 + b.depth[i]));
        EXPECT_NEAR(a.rho[i], b.rho[i], 1e-12);
    }
    EXPECT_EQ(a.central.origin, b.central.origin);
    EXPECT_EQ(a.central.direction, b.central.direction);
}

TEST(lens_rays_camera, polygon_aperture_rim_scales_with_blur) {
    const Camera cam = make_camera();
    const ThinLens lens = make_lens(cam);
    auto field = BlurField::from_thin_lens(lens);
    auto hex = ApertureShape::polygon(6, 0.0);
    ASSERT_TRUE(field && hex);
    NonlinearCameraOptions o;
    o.depth_min = 0.01;
    auto nl = NonlinearCamera::create(cam, *field, o, *hex);
    ASSERT_TRUE(nl) << nl.message();
    PixelCone cone;
    ASSERT_TRUE(nl->prepare(100.5, 80.5, cone));
    // The corner (1, 0) of the hexagon: its ray lies CoC px to the right in
    // front of the focus distance, to the left beyond it (the rays crossed).
    const PixelDepth q = cam.project(nl->point_at(cone, {1.0, 0.0}, 6.0));
    EXPECT_NEAR(q.x - 100.5, -lens.coc_radius_px(6.0), 1e-6);
    EXPECT_NEAR(q.y - 80.5, 0.0, 1e-9);
    const PixelDepth n = cam.project(nl->point_at(cone, {1.0, 0.0}, 0.8));
    EXPECT_NEAR(n.x - 100.5, lens.coc_radius_px(0.8), 1e-6);
}

TEST(lens_rays_camera, option_errors) {
    const Camera cam = make_camera();
    NonlinearCameraOptions o;
    o.depth_min = 0;
    auto r = NonlinearCamera::create(cam, BlurField(), o);
    ASSERT_FALSE(r);
    EXPECT_NE(r.message().find("depth_min"), std::string::npos);
    o = {};
    o.depth_max = std::numeric_limits<double>::infinity();
    r = NonlinearCamera::create(cam, BlurField(), o);
    ASSERT_FALSE(r);
    EXPECT_NE(r.message().find("depth_max"), std::string::npos);
    o = {};
    o.profile_tolerance_px = -1;
    EXPECT_FALSE(NonlinearCamera::create(cam, BlurField(), o));
    o = {};
    o.ray_tolerance_px = std::nan("");
    EXPECT_FALSE(NonlinearCamera::create(cam, BlurField(), o));
}

TEST(lens_rays_camera, cone_radius_follows_any_field_densely) {
    const Camera cam = make_camera(50.0, 320, 240);
    const char* fields[] = {
        R"({"blurfield": {"kind": "focal_planes", "depths": [2, 5], "max_blur": 6}})",
        R"({"blurfield": {"kind": "focal_planes", "depths": [1.5, 4], "max_blur": 9, "interpolation": "smooth"}})",
        R"({"blurfield": {"kind": "region", "shape": "sphere", "center": [0, 0, 3], "radius": 0.5, "blur": 8,
            "falloff": 1.0}})",
        R"({"blurfield": {"kind": "region", "shape": "box", "center": [0, 0, 4], "size": [1, 1, 1], "blur": 5,
            "mode": "blur"}})",
    };
    for (const char* text : fields) {
        const BlurField field = parse_ok(text);
        NonlinearCameraOptions o;
        const NonlinearCamera nl = make_nl(cam, field, o);
        PixelCone cone;
        for (auto [px, py] : kPixels) {
            ASSERT_TRUE(nl.prepare(px, py, cone)) << text;
            double worst = 0;
            for (int i = 1; i < 4000; ++i) {
                const double z = 0.02 * std::pow(1000.0 / 0.02, i / 4000.0);  // log-spaced
                const double got = std::fabs(NonlinearCamera::rho_at(cone, z)) / nl.footprint(z);
                const double want = field.evaluate_on_ray(cam, px, py, z);
                // Away from hard steps (two vertices 1e-9 apart).
                if (std::fabs(got - want) > 1.0) continue;
                worst = std::max(worst, std::fabs(got - want));
            }
            EXPECT_LE(worst, 2.5 * o.ray_tolerance_px) << text << " px " << px << " vertices " << cone.depth.size();
            EXPECT_LE(cone.depth.size(), 200u) << text;
        }
    }
}
