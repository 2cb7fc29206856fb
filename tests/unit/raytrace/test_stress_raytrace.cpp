// Numerical stress: method 1's camera side (lens rays, aperture sampling)
// and the renderer (issue 7, item 4). Random blur fields with radii up to
// 1000 px, thin lenses f/0.5 .. f/1024 focused at the near clip, depth
// ranges 1e-4 .. 1e7, pixels at the frame corners of 1x1, 1x10000 and
// 10000x1 frames, aperture masks with HDR / denormal / NaN values; renders
// of 1x1, 1x10000-style frames (the 10000 px long side) with HDR lights.
// Properties: cones and rays are finite with sorted vertices, the cone
// radius is B * footprint at every vertex, aperture offsets stay in their
// shape, invalid options are errors naming the option, rendered images have
// no NaN/Inf in the beauty and consistent AOVs. Renders skip without Embree.
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "gdof/lens_rays.h"
#include "gdof/raytrace.h"
#include "scene_test_helpers.h"
#include "stress_test_helpers.h"

using namespace gdof;
using namespace gdof::test;

namespace {

Camera make_camera(const Roi& display, double focal_mm) {
    CameraDesc d;
    d.position = {0.1, -0.2, 0.3};
    d.look_at = {0.1, -0.2, 1.3};
    d.focal_length_mm = focal_mm;
    d.display_window = display;
    auto c = Camera::create(d);
    EXPECT_TRUE(c) << c.message();
    return c ? c.value() : Camera();
}

const std::vector<Roi> kFrames = {{0, 0, 1, 1}, {0, 0, 10000, 1}, {0, 0, 1, 10000}, {0, 0, 640, 360}};

// A random field: thin lens (focus at the near clip sometimes), focal planes
// over 1e-4 .. 1e7 with ramps to 1000 px, a region, or min / max of two.
std::string random_field_json(StressRng& rng, int depth = 0) {
    switch (rng.integer(0, depth ? 2 : 3)) {
        case 0: {
            const double f = rng.log_uniform(5.0, 500.0);
            const double s = rng.chance(0.3) ? f / 1000.0 * (1.0 + rng.log_uniform(1e-6, 1e-2)) : rng.log_uniform(f / 900.0, 1e6);
            return R"({"kind": "thin_lens", "focal_length_mm": )" + num(f) + R"(, "f_number": )" + num(rng.log_uniform(0.5, 1024.0)) +
                   R"(, "focus_distance": )" + num(s) + "}";
        }
        case 1: {
            const double a = rng.log_uniform(1e-4, 1e7);
            return R"({"kind": "focal_planes", "depths": [)" + num(a) + ", " + num(a * rng.log_uniform(1.001, 1e4)) +
                   R"(], "max_blur": )" + num(rng.uniform(0.0, 1000.0)) + R"(, "interpolation": ")" +
                   (rng.chance(0.5) ? "smooth" : "linear") + "\"}";
        }
        case 2: {
            const double z = rng.log_uniform(1e-3, 1e6);
            return R"({"kind": "region", "shape": "sphere", "center": [0.1, -0.2, )" + num(z) + R"(], "radius": )" +
                   num(z * rng.uniform(0.0, 0.9)) + R"(, "blur": )" + num(rng.uniform(0.0, 1000.0)) + R"(, "falloff": )" +
                   num(z * rng.uniform(0.0, 1.0)) + R"(, "mode": ")" + (rng.chance(0.5) ? "focus" : "blur") + "\"}";
        }
        default:
            return std::string(R"({"kind": ")") + (rng.chance(0.5) ? "min" : "max") + R"(", "children": [)" +
                   random_field_json(rng, 1) + ", " + random_field_json(rng, 1) + "]}";
    }
}

BlurField parse_field(const std::string& node) {
    auto f = BlurField::parse(R"({"blurfield": )" + node + "}");
    EXPECT_TRUE(f) << f.message() << "\n" << node;
    return f ? f.value() : BlurField();
}

bool finite(const Vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

}  // namespace

// Cones over huge depth ranges for random fields and pixels (corners of
// 1x1, 1x10000, 10000x1 frames): vertex depths strictly increasing from the
// lens plane, radii finite and equal to B * footprint at every vertex but the
// lens plane, in-focus depths where rho is 0; every aperture sample's
// polyline is finite, stays at its depths, and its far direction is a unit
// vector.
TEST(stress_raytrace, cones_and_polyline_rays_are_finite_and_follow_the_field) {
    GDOF_STRESS_RNG(rng, 5001);
    for (int iter = 0; iter < 120; ++iter) {
        const Roi frame = rng.pick(kFrames);
        const Camera cam = make_camera(frame, rng.log_uniform(5.0, 500.0));
        const std::string json = random_field_json(rng);
        const BlurField field = parse_field(json);
        NonlinearCameraOptions o;
        o.depth_min = rng.log_uniform(1e-4, 1.0);
        o.depth_max = rng.chance(0.5) ? 1e7 : o.depth_min * rng.log_uniform(2.0, 1e11);
        o.ray_tolerance_px = rng.log_uniform(1e-3, 1.0);
        o.max_profile_vertices = rng.pick(std::vector<int>{2, 50, 20000});
        SCOPED_TRACE("field " + json + ", depths [" + num(o.depth_min) + ", " + num(o.depth_max) + "], frame " + to_string(frame));
        auto nl = NonlinearCamera::create(cam, field, o,
                                          rng.chance(0.5) ? ApertureShape::disc() : ApertureShape::polygon(rng.integer(3, 12)).value());
        ASSERT_TRUE(nl) << nl.message();
        for (int k = 0; k < 4; ++k) {
            const double px = rng.chance(0.5) ? rng.pick(std::vector<double>{0.0, double(frame.x1), 0.5}) : rng.uniform(0.0, frame.x1);
            const double py = rng.chance(0.5) ? rng.pick(std::vector<double>{0.0, double(frame.y1), 0.5}) : rng.uniform(0.0, frame.y1);
            SCOPED_TRACE("pixel (" + num(px) + ", " + num(py) + ")");
            PixelCone cone;
            const Status st = nl->prepare(px, py, cone);
            ASSERT_TRUE(st) << st.message();
            ASSERT_EQ(cone.depth.size(), cone.rho.size());
            ASSERT_GE(cone.depth.size(), 1u);
            EXPECT_EQ(cone.depth[0], 0.0);
            EXPECT_TRUE(std::isfinite(cone.far_slope)) << cone.far_slope;
            EXPECT_TRUE(cone.max_blur_px >= 0 && std::isfinite(cone.max_blur_px)) << cone.max_blur_px;
            for (std::size_t i = 0; i < cone.depth.size(); ++i) {
                ASSERT_TRUE(std::isfinite(cone.rho[i])) << "vertex " << i << " rho " << cone.rho[i];
                if (i > 0) {
                    ASSERT_LT(cone.depth[i - 1], cone.depth[i]) << "vertex " << i;
                    // Every kept vertex is exact: |rho| = B * footprint (up to the ray tolerance).
                    const double b = field.evaluate_on_ray(cam, px, py, cone.depth[i]);
                    const double fp = nl->footprint(cone.depth[i]);
                    EXPECT_NEAR(std::fabs(cone.rho[i]) / fp, b, o.ray_tolerance_px + 1e-9 * b)
                        << "vertex " << i << " depth " << num(cone.depth[i]);
                }
            }
            for (double z : cone.in_focus) {
                EXPECT_TRUE(std::isfinite(z) && z >= o.depth_min && z <= o.depth_max) << z;
                EXPECT_EQ(NonlinearCamera::rho_at(cone, z), 0.0) << "in-focus depth " << num(z);
            }
            PolylineRay ray;
            for (int s = 0; s < 8; ++s) {
                const Vec2 u = unit_square_sample(pixel_seed(int(px), int(py), 7), std::uint32_t(rng.integer(0, 1 << 30)));
                nl->ray_from_unit(cone, u, ray);
                ASSERT_FALSE(ray.points.empty());
                for (std::size_t i = 0; i < ray.points.size(); ++i) {
                    ASSERT_TRUE(finite(ray.points[i])) << "vertex " << i;
                    // p(z) = c(z) + rho(z) * offset stays at depth z.
                    const double z = dot(ray.points[i] - cam.position(), cam.forward());
                    const double rho = std::fabs(cone.rho[std::min(i, cone.rho.size() - 1)]);
                    EXPECT_NEAR(z, ray.depth[i], 1e-9 * (ray.depth[i] + rho + 1.0))
                        << "vertex " << i;
                }
                ASSERT_TRUE(finite(ray.far_direction));
                EXPECT_NEAR(length(ray.far_direction), 1.0, 1e-12);
                const double z = rng.log_uniform(o.depth_min, o.depth_max);
                EXPECT_TRUE(finite(nl->point_at(cone, nl->shape().map(u), z))) << "depth " << num(z);
            }
        }
    }
}

// The thin_lens field over f/0.5 .. f/1024 with focus from the near clip
// (s = f (1 + 1e-6)) to 1e6 units is the straight thin lens of radius
// thin_lens_equivalent_radius: the rays agree at random depths.
TEST(stress_raytrace, thin_lens_field_is_the_straight_thin_lens_at_the_extremes) {
    GDOF_STRESS_RNG(rng, 5002);
    for (int iter = 0; iter < 200; ++iter) {
        const Roi frame = rng.pick(kFrames);
        ThinLens l;
        l.focal_length_mm = rng.log_uniform(5.0, 500.0);
        l.f_number = rng.log_uniform(0.5, 1024.0);
        l.focus_distance = rng.chance(0.3) ? l.focal_length_mm / 1000.0 * (1.0 + rng.log_uniform(1e-6, 1e-1))
                                           : rng.log_uniform(l.focal_length_mm / 900.0, 1e6);
        l.image_width_px = frame.width();
        const Camera cam = make_camera(frame, l.focal_length_mm);
        auto field = BlurField::from_thin_lens(l);
        ASSERT_TRUE(field) << field.message();
        NonlinearCameraOptions o;
        o.depth_min = std::min(1e-4, l.focus_distance * 0.5);
        o.depth_max = 1e7;
        auto nl = NonlinearCamera::create(cam, *field, o);
        ASSERT_TRUE(nl) << nl.message();
        const double px = rng.uniform(0.0, frame.x1), py = rng.uniform(0.0, frame.y1);
        SCOPED_TRACE("f " + num(l.focal_length_mm) + " N " + num(l.f_number) + " s " + num(l.focus_distance) + " pixel (" +
                     num(px) + ", " + num(py) + ")");
        auto cone = nl->prepare(px, py);
        ASSERT_TRUE(cone) << cone.message();
        const double R = thin_lens_equivalent_radius(l);
        ASSERT_TRUE(std::isfinite(R) && R > 0) << R;
        for (int k = 0; k < 8; ++k) {
            const Vec2 a = concentric_disc({rng.uniform(0.0, 1.0), rng.uniform(0.0, 1.0)});
            const CameraRay straight = thin_lens_ray(cam, px, py, R, l.focus_distance, a);
            ASSERT_TRUE(finite(straight.origin) && finite(straight.direction));
            const double z = rng.log_uniform(o.depth_min, o.depth_max);
            const Vec3 p_poly = nl->point_at(*cone, a, z);
            const Vec3 p_straight = straight.at(z / straight.depth_per_t);
            const double scale = length(p_straight - cam.position()) + R;
            EXPECT_LT(length(p_poly - p_straight), 1e-6 * scale) << "depth " << num(z);
        }
    }
}

// Aperture sampling: unit-square samples lie in [0, 1)^2 for any seed and
// index; disc, polygon and mask offsets stay inside their shape; masks with
// HDR, denormal, 1x1 and 1x10000 images work, and NaN / Inf / empty / no
// positive value are errors naming the problem.
TEST(stress_raytrace, aperture_samples_stay_in_their_shape) {
    GDOF_STRESS_RNG(rng, 5003);
    for (int iter = 0; iter < 40; ++iter) {
        const std::uint64_t seed = pixel_seed(rng.integer(-100000, 100000), rng.integer(-100000, 100000),
                                              std::uint64_t(rng.gen()()) << 32 | rng.gen()());
        const int w = rng.pick(std::vector<int>{1, 10000, 1, 7}), h = w == 10000 ? 1 : rng.pick(std::vector<int>{1, 10000, 5});
        Image mask = Image::with_channels({"A"}, {0, 0, w, h});
        for (std::size_t i = 0; i < mask.npixels(); ++i) mask.plane(0)[i] = rng.chance(0.3) ? -1.0f : rng.pixel();
        mask.plane(0)[std::size_t(rng.integer(0, int(mask.npixels()) - 1))] = float(rng.log_uniform(1e-30, 1e6));  // one positive
        auto m = ApertureShape::mask(mask);
        ASSERT_TRUE(m) << m.message();
        auto poly = ApertureShape::polygon(rng.integer(3, 64), rng.uniform(-1e6, 1e6));
        ASSERT_TRUE(poly) << poly.message();
        const double half_w = double(w) / std::max(w, h), half_h = double(h) / std::max(w, h);
        for (int k = 0; k < 500; ++k) {
            const std::uint32_t index = rng.chance(0.1) ? 0xffffffffu - std::uint32_t(rng.integer(0, 3)) : std::uint32_t(rng.gen()());
            const Vec2 u = unit_square_sample(seed, index);
            ASSERT_TRUE(u.x >= 0 && u.x < 1 && u.y >= 0 && u.y < 1) << "sample " << index << ": " << u.x << ", " << u.y;
            const Vec2 d = ApertureShape::disc().map(u);
            EXPECT_LE(d.x * d.x + d.y * d.y, 1.0 + 1e-12);
            const Vec2 p = poly->map(u);
            EXPECT_LE(p.x * p.x + p.y * p.y, 1.0 + 1e-12);
            const Vec2 q = m->map(u);
            EXPECT_TRUE(std::isfinite(q.x) && std::isfinite(q.y) && std::fabs(q.x) <= half_w + 1e-12 &&
                        std::fabs(q.y) <= half_h + 1e-12)
                << q.x << ", " << q.y << " outside the " << w << "x" << h << " mask";
        }
    }
    Image bad = Image::with_channels({"A"}, {0, 0, 4, 3});
    bad.plane(0)[5] = 1.0f;
    bad.at(0, 2, 1) = float(kStressNaN);
    auto m = ApertureShape::mask(bad);
    ASSERT_FALSE(m);
    EXPECT_TRUE(contains(m.message(), "(2, 1)")) << m.message();
    bad.at(0, 2, 1) = float(kStressInf);
    EXPECT_FALSE(ApertureShape::mask(bad));
    Image zero = Image::with_channels({"A"}, {0, 0, 4, 3});
    m = ApertureShape::mask(zero);
    ASSERT_FALSE(m);
    EXPECT_TRUE(contains(m.message(), "no positive value")) << m.message();
    EXPECT_FALSE(ApertureShape::mask(Image::with_channels({"A"}, {})));
    EXPECT_FALSE(ApertureShape::polygon(2));
    EXPECT_FALSE(ApertureShape::polygon(6, kStressNaN));
}

// Invalid nonlinear-camera options and pixel positions are errors naming them.
TEST(stress_raytrace, invalid_options_are_errors_naming_the_option) {
    GDOF_STRESS_RNG(rng, 5004);
    const Camera cam = make_camera({0, 0, 64, 48}, 35.0);
    const BlurField field = parse_field(random_field_json(rng));
    const std::vector<double> bad = {kStressNaN, kStressInf, -kStressInf, 0.0, -1.0};
    for (int iter = 0; iter < 40; ++iter) {
        NonlinearCameraOptions o;
        std::string name;
        switch (rng.integer(0, 3)) {
            case 0: o.depth_min = rng.pick(bad), name = "depth_min"; break;
            case 1: o.depth_max = rng.chance(0.5) ? rng.pick(bad) : o.depth_min * 0.5, name = "depth_max"; break;
            case 2: o.profile_tolerance_px = rng.pick(bad), name = "profile_tolerance_px"; break;
            default: o.ray_tolerance_px = rng.pick(bad), name = "ray_tolerance_px"; break;
        }
        auto nl = NonlinearCamera::create(cam, field, o);
        ASSERT_FALSE(nl) << name;
        EXPECT_TRUE(contains(nl.message(), name)) << nl.message();
    }
    auto nl = NonlinearCamera::create(cam, field);
    ASSERT_TRUE(nl) << nl.message();
    for (double v : {kStressNaN, kStressInf}) {
        auto c = nl->prepare(v, 3.5);
        ASSERT_FALSE(c) << "pixel " << v;
        EXPECT_TRUE(contains(c.message(), "pixel")) << c.message();
    }
}

namespace {

#define RENDER_OR_SKIP(var, scene, settings)                                                   \
    auto var##_r = render(scene, settings);                                                    \
    if (!var##_r && var##_r.message().find("without Embree") != std::string::npos)           \
        GDOF_SKIP_OR_FAIL(var##_r.message());                                                     \
    ASSERT_TRUE(var##_r) << var##_r.message();                                                 \
    const Image& var = var##_r.value()

// Beauty finite, 0 <= A <= 1; where Z is +inf nothing was hit and P is NaN,
// elsewhere Z >= 0 and P, N finite. "" if so, else the first problem.
std::string check_render(const Image& img) {
    const int ca = img.channel_index("A"), cz = img.channel_index("Z"), cpx = img.channel_index("P.x"),
              cnx = img.channel_index("N.x");
    for (const char* n : {"R", "G", "B", "A", "albedo.R", "albedo.G", "albedo.B"}) {
        const int c = img.channel_index(n);
        if (c < 0) return std::string("no channel ") + n;
        for (std::size_t i = 0; i < img.npixels(); ++i)
            if (!std::isfinite(img.plane(c)[i])) return std::string(n) + " is " + num(img.plane(c)[i]) + " at index " + std::to_string(i);
    }
    for (std::size_t i = 0; i < img.npixels(); ++i) {
        const float a = img.plane(ca)[i];
        if (!(a >= 0 && a <= 1)) return "A is " + num(a) + " at index " + std::to_string(i);
        if (cz < 0 || cpx < 0 || cnx < 0) continue;
        const float z = img.plane(cz)[i], p = img.plane(cpx)[i], nx = img.plane(cnx)[i];
        if (std::isnan(z)) return "Z is NaN at index " + std::to_string(i);
        if (std::isinf(z) != std::isnan(p)) return "Z " + num(z) + " with P.x " + num(p) + " at index " + std::to_string(i);
        if (std::isfinite(z) && (z < 0 || !std::isfinite(nx))) return "Z " + num(z) + ", N.x " + num(nx) + " at index " + std::to_string(i);
    }
    return {};
}

}  // namespace

// Renders of a lit plane on 1x1, 1 x N and N x 1 frames (N up to 10000
// pixels on the long side, few samples), HDR lights (1e6), random blur
// fields up to 1000 px and thin lenses f/0.5 .. f/1024 focused at the near
// clip: no NaN/Inf in the beauty, 0 <= A <= 1, consistent Z / P / N.
TEST(stress_raytrace, renders_at_extreme_sizes_and_blurs_are_finite) {
    GDOF_STRESS_RNG(rng, 5005);
    ScratchDir dir;
    write_quad_obj(dir);
    for (int iter = 0; iter < 16; ++iter) {
        const int kind = rng.integer(0, 3);
        const int w = kind == 0 ? 1 : kind == 1 ? 10000 : kind == 2 ? 1 : rng.integer(2, 40);
        const int h = kind == 0 ? 1 : kind == 1 ? 1 : kind == 2 ? 10000 : rng.integer(2, 30);
        const bool lens = rng.chance(0.5);
        std::string extra;
        if (lens) {
            // The camera is 35 mm: focus at the near clip is just beyond 0.035 units.
            const double s = rng.chance(0.5) ? 0.035 * (1.0 + rng.log_uniform(1e-6, 1e-2)) : rng.log_uniform(0.04, 1e6);
            extra = R"(, "f_number": )" + num(rng.log_uniform(0.5, 1024.0)) + R"(, "focus_distance": )" + num(s);
        }
        std::string json = plane_scene_json(extra, w, h);
        const double light = rng.chance(0.5) ? 1e6 : 20.0;
        const std::string from = R"("intensity": 20)";
        json.replace(json.find(from), from.size(), R"("intensity": )" + num(light));
        if (rng.chance(0.3)) {
            const std::string env = R"("environment": [0.1, 0.1, 0.1])";
            json.replace(json.find(env), env.size(), R"("environment": [0, 0, 0])");
        }
        auto scene = parse_scene(json, dir.path().string());
        ASSERT_TRUE(scene) << scene.message();
        RenderOptions rs;
        rs.spp = w * h <= 4 ? rng.integer(1, 1024) : rng.integer(1, 4);
        rs.min_spp = rng.integer(1, 8);  // may exceed spp
        rs.light_samples = rng.integer(1, 2);
        rs.adaptive_threshold = rng.chance(0.5) ? 0.0 : rng.log_uniform(1e-6, 1e3);
        rs.tile_size = rng.integer(1, 100);
        rs.seed = std::uint64_t(rng.gen()()) << 32 | rng.gen()();
        rs.pixel_jitter = rng.chance(0.5);
        rs.polyline_tolerance_px = rng.log_uniform(1e-4, 10.0);
        rs.straight_thin_lens = lens && rng.chance(0.5);
        const std::string field_json = lens ? "" : random_field_json(rng);
        BlurField field;
        if (!lens) {
            field = parse_field(field_json);
            rs.blur_field = &field;
        }
        SCOPED_TRACE(::testing::Message() << w << "x" << h << ", spp " << rs.spp << ", min_spp " << rs.min_spp << ", light "
                                          << light << (lens ? ", camera lens" + extra : ", field " + field_json));
        RENDER_OR_SKIP(img, scene.value(), rs);
        ASSERT_EQ(img.width(), w);
        ASSERT_EQ(img.height(), h);
        EXPECT_EQ(check_render(img), "");
    }
}

// Non-finite or overflowing mesh vertices (nan, inf, 1e400) are errors
// naming the OBJ file; a huge but finite scene (1e7 units away, lights of
// 1e6) renders finite.
TEST(stress_raytrace, non_finite_meshes_are_errors_and_huge_scenes_render) {
    GDOF_STRESS_RNG(rng, 5006);
    ScratchDir dir;
    const std::vector<std::string> bad = {"nan", "inf", "-inf", "1e400"};
    for (int iter = 0; iter < 8; ++iter) {
        const std::string v = rng.pick(bad);
        const int at = rng.integer(0, 2);
        std::string obj = "o tri\n";
        for (int i = 0; i < 3; ++i) obj += "v " + (i == at ? v : std::to_string(i)) + " " + std::to_string(i % 2) + " 1\n";
        obj += "f 1 2 3\n";
        write_file(dir.file("bad.obj"), obj);
        SCOPED_TRACE("vertex " + std::to_string(at) + " = " + v);
        auto m = load_obj(dir.file("bad.obj"));
        ASSERT_FALSE(m) << "accepted a non-finite vertex";
        EXPECT_TRUE(contains(m.message(), "bad.obj")) << m.message();
        auto s = parse_scene(R"({"camera": {"position": [0, 0, -5], "look_at": [0, 0, 0]}, "meshes": [{"file": "bad.obj"}]})",
                             dir.path().string());
        ASSERT_FALSE(s);
        EXPECT_TRUE(contains(s.message(), "bad.obj")) << s.message();
    }
    write_quad_obj(dir);
    const double far = 1e7;
    const std::string json = R"({"camera": {"position": [0, 0, )" + num(far + 5) + R"(], "look_at": [0, 0, 0], "resolution": [16, 12],
        "f_number": 0.5, "focus_distance": )" + num(far) + R"(},
      "meshes": [{"file": "quad.obj", "scale": [1e6, 1e6, 1]}],
      "lights": [{"type": "point", "position": [0, 0, 1e5], "intensity": 1e6}]})";
    auto scene = parse_scene(json, dir.path().string());
    ASSERT_TRUE(scene) << scene.message();
    RenderOptions rs;
    rs.spp = 4;
    RENDER_OR_SKIP(img, scene.value(), rs);
    EXPECT_EQ(check_render(img), "");
    EXPECT_GT(img.at(img.channel_index("A"), 8, 6), 0.0f);  // the plane is in view
}

// Material colours in the MTL file that are not finite numbers (nan, inf,
// 1e400): the scene is refused with an error naming the file, or the render
// stays finite.
TEST(stress_raytrace, non_finite_material_colours_are_refused_or_harmless) {
    // MTL colours are checked like vertices: "Kd 1e400" is an error naming
    // the file, never an inf beauty.
    ScratchDir dir;
    const std::vector<std::string> values = {"nan", "inf", "-inf", "1e400", "-1e400", "1e30"};
    for (const std::string& key : {std::string("Kd"), std::string("Ke")})
        for (const std::string& v : values) {
            write_file(dir.file("m.mtl"), "newmtl grey\n" + key + " " + v + " 0.5 0.5\n" + (key == "Ke" ? "Kd 0.5 0.5 0.5\n" : ""));
            write_file(dir.file("m.obj"), "mtllib m.mtl\nv -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nusemtl grey\nf 1 2 3 4\n");
            SCOPED_TRACE(key + " " + v);
            auto scene = parse_scene(R"({"camera": {"position": [0, 0, 3], "look_at": [0, 0, 0], "resolution": [8, 6]},
                "meshes": [{"file": "m.obj", "scale": [10, 10, 1]}],
                "lights": [{"type": "point", "position": [0, 0, 2], "intensity": 5}], "environment": [0.2, 0.2, 0.2]})",
                                     dir.path().string());
            if (!scene) {
                EXPECT_TRUE(contains(scene.message(), "m.mtl") || contains(scene.message(), "m.obj")) << scene.message();
                continue;
            }
            RenderOptions rs;
            rs.spp = 2;
            RENDER_OR_SKIP(img, scene.value(), rs);
            EXPECT_EQ(check_render(img), "") << "material " << key << " " << v << " accepted and rendered";
        }
}

// Light intensities and colours: beyond 1e20 the scene is refused naming the
// key; within it, a product that leaves the float range (a 1e20 albedo lit by
// a 1e20 light 1e-3 away: ~1e46) is a render error naming the pixel, never an
// inf beauty; a 1e20 light at a normal distance renders finite.
TEST(stress_raytrace, huge_lights_are_refused_or_errors_naming_the_pixel) {
    ScratchDir dir;
    write_file(dir.file("m.obj"), "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nf 1 2 3 4\n");
    auto scene_with = [&](const std::string& kd, const std::string& light_z, const std::string& intensity,
                          const std::string& env) {
        return parse_scene(R"({"camera": {"position": [0, 0, 3], "look_at": [0, 0, 0], "resolution": [8, 6]},
            "meshes": [{"file": "m.obj", "scale": [10, 10, 1], "material": {"kd": )" + kd + R"(}}],
            "lights": [{"type": "point", "position": [0, 0, )" + light_z + R"(], "intensity": )" + intensity + R"(}],
            "environment": )" + env + "}",
                           dir.path().string());
    };
    for (const auto& [intensity, env, key] :
         {std::tuple{"1e300", "0.1", "lights[0].intensity"}, std::tuple{"[1, 1e21, 1]", "0.1", "lights[0].intensity"},
          std::tuple{"5", "1e300", "environment"}}) {
        auto s = scene_with("0.5", "2", intensity, env);
        ASSERT_FALSE(s) << intensity << " / " << env;
        EXPECT_TRUE(contains(s.message(), key) && contains(s.message(), "1e20")) << s.message();
    }
    RenderOptions rs;
    rs.spp = 2;
    {
        auto s = scene_with("1e20", "1e-3", "1e20", "0");
        ASSERT_TRUE(s) << s.message();
        auto img = render(s.value(), rs);
        if (!img && contains(img.message(), "without Embree")) GDOF_SKIP_OR_FAIL(img.message());
        ASSERT_FALSE(img) << "rendered a beauty beyond float range";
        EXPECT_TRUE(contains(img.message(), "pixel (") && contains(img.message(), "float range")) << img.message();
    }
    auto s = scene_with("0.5", "2", "1e20", "1e20");
    ASSERT_TRUE(s) << s.message();
    RENDER_OR_SKIP(img, s.value(), rs);
    EXPECT_EQ(check_render(img), "");
}
