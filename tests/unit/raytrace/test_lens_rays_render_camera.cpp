// Ray generation in the camera: a pixel's camera samples (PixelSampler), the
// jittered polyline ray (NonlinearCamera::generate_ray) and the three render
// cameras behind RenderCamera (pinhole, straight thin lens, polyline).
#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <tuple>
#include <utility>
#include <vector>

#include "gdof/lens_rays.h"
#include "lens_rays_test_helpers.h"

using namespace gdof;
using namespace gdof::test;

namespace {

// A sphere that is sharp (B = 0) around (0, 0, 4), blurred elsewhere: B
// changes across the image, so the field is not depth-only.
const char* kSphereField = R"({"blurfield": {"kind": "region", "shape": "sphere", "center": [0, 0, 4],
    "radius": 0.5, "mode": "focus", "blur": 6, "falloff": 1}})";

void expect_same_cone(const PixelCone& a, const PixelCone& b) {
    EXPECT_EQ(a.px, b.px);
    EXPECT_EQ(a.py, b.py);
    EXPECT_EQ(a.central.origin, b.central.origin);
    EXPECT_EQ(a.central.direction, b.central.direction);
    EXPECT_EQ(a.depth, b.depth);
    EXPECT_EQ(a.rho, b.rho);
    EXPECT_EQ(a.far_slope, b.far_slope);
    EXPECT_EQ(a.pinhole, b.pinhole);
}

void expect_straight(const PolylineRay& r, const CameraRay& ref) {
    ASSERT_EQ(r.points.size(), 1u);
    ASSERT_EQ(r.depth.size(), 1u);
    EXPECT_EQ(r.points[0], ref.origin);
    EXPECT_EQ(r.depth[0], 0.0);
    EXPECT_EQ(r.far_direction, ref.direction);
}

}  // namespace

TEST(lens_rays_render_camera, pixel_sampler_is_the_pixel_seeded_sequence) {
    for (auto [x, y, seed] : {std::tuple{0, 0, 0ull}, std::tuple{17, -3, 5ull}, std::tuple{639, 359, 42ull}}) {
        const PixelSampler plain(x, y, seed, false), jittered(x, y, seed, true), again(x, y, seed, true);
        std::set<std::pair<int, int>> cells;
        for (std::uint32_t i = 0; i < 16; ++i) {
            const Vec2 a = unit_square_sample(pixel_seed(x, y, seed), i);
            EXPECT_EQ(plain.sample(i).aperture, a);
            EXPECT_EQ(plain.sample(i).pixel_offset, (Vec2{0, 0}));
            // Jitter does not move the aperture sample; it is its own sequence.
            const CameraSample s = jittered.sample(i);
            EXPECT_EQ(s.aperture, a);
            EXPECT_EQ(s.pixel_offset, again.sample(i).pixel_offset);
            EXPECT_NE(s.pixel_offset, (Vec2{a.x - 0.5, a.y - 0.5}));
            ASSERT_GE(s.pixel_offset.x, -0.5);
            ASSERT_LT(s.pixel_offset.x, 0.5);
            ASSERT_GE(s.pixel_offset.y, -0.5);
            ASSERT_LT(s.pixel_offset.y, 0.5);
            cells.insert({int((s.pixel_offset.x + 0.5) * 4), int((s.pixel_offset.y + 0.5) * 4)});
        }
        // 16 jitter offsets stratify the pixel: one in each cell of a 4 x 4 grid.
        EXPECT_EQ(cells.size(), 16u);
    }
    EXPECT_NE(PixelSampler(1, 0, 0, true).sample(0).pixel_offset, PixelSampler(0, 1, 0, true).sample(0).pixel_offset);
}

TEST(lens_rays_render_camera, pinhole_and_straight_thin_lens_are_their_rays_bit_for_bit) {
    const Camera cam = make_camera(35.0, 320, 240, {1, 2, -3}, {0.3, 1.7, 4});
    const RenderCamera pin = RenderCamera::pinhole(cam);
    const RenderCamera thin = RenderCamera::straight_thin_lens(cam, 0.02, 3.0);
    EXPECT_EQ(pin.kind(), RenderCamera::Kind::Pinhole);
    EXPECT_EQ(thin.kind(), RenderCamera::Kind::StraightThinLens);
    PixelCone cone;
    PolylineRay ray;
    const PixelSampler sampler(40, 7, 9, true);
    for (std::uint32_t i = 0; i < 8; ++i) {
        const CameraSample s = sampler.sample(i);
        const double x = 40.5 + s.pixel_offset.x, y = 7.5 + s.pixel_offset.y;
        ASSERT_TRUE(pin.prepare_pixel(40.5, 7.5, cone));
        pin.generate_ray(cone, s, ray);
        expect_straight(ray, cam.central_ray(x, y));
        ASSERT_TRUE(thin.prepare_pixel(40.5, 7.5, cone));
        thin.generate_ray(cone, s, ray);
        expect_straight(ray, thin_lens_ray(cam, x, y, 0.02, 3.0, concentric_disc(s.aperture)));
    }
}

TEST(lens_rays_render_camera, polyline_camera_prepares_the_pixel_cone) {
    const Camera cam = make_camera();
    const NonlinearCamera nl = make_nl(cam, parse_ok(kSphereField));
    ASSERT_FALSE(nl.depth_only());
    auto rc = RenderCamera::polyline(nl);
    ASSERT_TRUE(rc) << rc.message();
    EXPECT_EQ(rc->kind(), RenderCamera::Kind::Polyline);
    PixelCone cone, ref;
    PolylineRay ray, ref_ray;
    for (auto [px, py] : {std::pair{160.5, 120.5}, std::pair{3.5, 230.5}, std::pair{160.5, 121.5}}) {
        ASSERT_TRUE(rc->prepare_pixel(px, py, cone));  // the same buffer, pixel after pixel
        ASSERT_TRUE(nl.prepare(px, py, ref));
        expect_same_cone(cone, ref);
        // Unjittered: exactly the cone's ray of the aperture sample.
        const CameraSample s{{0, 0}, {0.3, 0.8}};
        rc->generate_ray(cone, s, ray);
        nl.ray_from_unit(ref, s.aperture, ref_ray);
        EXPECT_EQ(ray.points, ref_ray.points);
        EXPECT_EQ(ray.depth, ref_ray.depth);
        EXPECT_EQ(ray.far_direction, ref_ray.far_direction);
    }
}

TEST(lens_rays_render_camera, depth_only_field_moves_one_shared_cone) {
    const Camera cam = make_camera();
    auto field = BlurField::from_thin_lens(make_lens(cam));
    ASSERT_TRUE(field) << field.message();
    const NonlinearCamera nl = make_nl(cam, *field);
    ASSERT_TRUE(nl.depth_only());
    auto rc = RenderCamera::polyline(nl);
    ASSERT_TRUE(rc) << rc.message();
    PixelCone shared, cone;
    ASSERT_TRUE(nl.prepare(0.5, 0.5, shared));  // the display window's first pixel
    for (auto [px, py] : {std::pair{7.5, 230.5}, std::pair{319.5, 0.5}}) {
        ASSERT_TRUE(rc->prepare_pixel(px, py, cone));
        PixelCone expected = shared;
        nl.retarget(expected, px, py);
        expect_same_cone(cone, expected);
        EXPECT_EQ(cone.in_focus, shared.in_focus);
    }
    // A cone buffer last used by another camera is overwritten, not trusted.
    ASSERT_TRUE(make_nl(cam, parse_ok(kSphereField)).prepare(5.5, 5.5, cone));
    ASSERT_TRUE(rc->prepare_pixel(7.5, 230.5, cone));
    EXPECT_EQ(cone.depth, shared.depth);
    EXPECT_EQ(cone.rho, shared.rho);
}

TEST(lens_rays_render_camera, jittered_ray_is_the_ray_of_the_offset_position) {
    const Camera cam = make_camera(35.0, 320, 240, {0.5, -1, 2}, {1, 0, 9});
    auto field = BlurField::from_thin_lens(make_lens(cam, 35.0, 2.0, 3.0));
    ASSERT_TRUE(field) << field.message();
    const NonlinearCamera nl = make_nl(cam, *field);
    PixelCone cone, moved;
    PolylineRay ray, ref;
    ASSERT_TRUE(nl.prepare(100.5, 60.5, cone));
    ASSERT_FALSE(cone.pinhole);
    const PixelSampler sampler(100, 60, 3, true);
    for (std::uint32_t i = 0; i < 16; ++i) {
        const CameraSample s = sampler.sample(i);
        nl.generate_ray(cone, s, ray);
        // A thin-lens cone is the same at every pixel: the jittered ray is the
        // offset position's ray of the same aperture sample, at every depth.
        moved = cone;
        nl.retarget(moved, 100.5 + s.pixel_offset.x, 60.5 + s.pixel_offset.y);
        nl.ray_from_unit(moved, s.aperture, ref);
        ASSERT_EQ(ray.points.size(), ref.points.size());
        for (double z : {0.0, 0.5, 3.0, 7.0, 100.0, 1e4}) {
            const Vec3 p = polyline_at(cam, ray, z), q = polyline_at(cam, ref, z);
            EXPECT_LE(dist(p, q), 1e-9 * (1 + z)) << "sample " << i << " z " << z;
        }
        EXPECT_LE(length(ray.far_direction - ref.far_direction), 1e-9);
    }
    // A pinhole cone: the central ray of the offset position, bit for bit.
    const NonlinearCamera zero = make_nl(cam, BlurField());
    ASSERT_TRUE(zero.prepare(100.5, 60.5, cone));
    ASSERT_TRUE(cone.pinhole);
    const CameraSample s = sampler.sample(5);
    zero.generate_ray(cone, s, ray);
    expect_straight(ray, cam.central_ray(100.5 + s.pixel_offset.x, 60.5 + s.pixel_offset.y));
}

TEST(lens_rays_render_camera, unsampleable_fields_are_errors) {
    const Camera cam = make_camera();
    // Depth-only: the shared cone cannot be made, so neither can the camera.
    auto huge = RenderCamera::polyline(make_nl(cam, parse_ok(R"({"blurfield": {"kind": "scale", "factor": 1e308,
        "child": {"kind": "thin_lens", "focal_length_mm": 50, "f_number": 2.8, "focus_distance": 2}}})")));
    ASSERT_FALSE(huge);
    EXPECT_NE(huge.message().find(" px"), std::string::npos) << huge.message();
    // Per pixel: only the pixels whose rays cross the box fail.
    auto box = RenderCamera::polyline(make_nl(cam, parse_ok(R"({"blurfield": {"kind": "region", "shape": "box",
        "min": [-0.2, -0.2, 3], "max": [0.2, 0.2, 4], "mode": "blur", "blur": 1e30}})")));
    ASSERT_TRUE(box) << box.message();
    PixelCone cone;
    EXPECT_TRUE(box->prepare_pixel(0.5, 0.5, cone));
    const Status st = box->prepare_pixel(160.5, 120.5, cone);
    ASSERT_FALSE(st);
    EXPECT_NE(st.message().find("pixel (160.5, 120.5)"), std::string::npos) << st.message();
}
