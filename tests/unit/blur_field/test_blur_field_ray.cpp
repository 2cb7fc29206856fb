// Per-ray queries: profile breakpoints (in-focus depths, kinks, region
// boundaries), polyline accuracy, and in-focus intervals against analytic
// answers (thin lens: the ThinLens depth-of-field limits).
#include <cmath>
#include <limits>
#include <random>

#include "gdof/blur_field.h"
#include "test_support.h"

using namespace gdof;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

Camera test_camera() {
    CameraDesc d;
    d.position = {0.5, 1.0, 2.0};
    d.look_at = {0.5, 1.0, -10.0};
    d.up = {0, 1, 0};
    d.focal_length_mm = 50;
    d.sensor_width_mm = 36;
    d.display_window = {0, 0, 1920, 1080};
    auto c = Camera::create(d);
    EXPECT_TRUE(c) << c.message();
    return c.value();
}

BlurField parse_ok(const std::string& text) {
    auto r = BlurField::parse(text);
    EXPECT_TRUE(r) << r.message();
    return r ? r.value() : BlurField();
}

// Is there a vertex within rel of d?
bool has_vertex(const RayProfile& p, double d, double rel = 1e-9) {
    for (double v : p.depth)
        if (std::fabs(v - d) <= rel * d) return true;
    return false;
}

void expect_rel(double got, double want, double rel) {
    if (std::isinf(want)) {
        EXPECT_TRUE(std::isinf(got)) << got;
        return;
    }
    EXPECT_NEAR(got, want, rel * std::fabs(want)) << "got " << got << " want " << want;
}

ThinLens lens(double focus) {
    ThinLens l;
    l.focal_length_mm = 50, l.f_number = 2, l.focus_distance = focus, l.sensor_width_mm = 36, l.image_width_px = 1920;
    return l;
}

}  // namespace

TEST(blur_field_ray, ThinLensIntervalEqualsDofLimits) {
    const Camera cam = test_camera();
    for (double focus : {2.0, 10.0, 40.0}) {  // 40 m is beyond the hyperfocal distance for 1 px
        const ThinLens l = lens(focus);
        auto f = BlurField::from_thin_lens(l);
        ASSERT_TRUE(f);
        for (double coc : {0.5, 1.0, 3.0, 10.0})
            for (auto [px, py] : {std::pair{960.0, 540.0}, std::pair{10.5, 1070.5}, std::pair{1500.25, 99.75}}) {
                SCOPED_TRACE("focus " + std::to_string(focus) + " coc " + std::to_string(coc));
                const auto lim = l.dof_limits(coc);
                auto r = f->in_focus_interval(cam, px, py, coc, 0.01, kInf);
                ASSERT_TRUE(r) << r.message();
                ASSERT_EQ(r->intervals.size(), 1u);
                expect_rel(r->intervals[0].near, lim.near, 1e-6);
                expect_rel(r->intervals[0].far, lim.far, 1e-6);
                expect_rel(r->min_depth, focus, 1e-12);
                EXPECT_EQ(r->min_radius, 0.0);
                expect_rel(r->primary().near, lim.near, 1e-6);
                // A finite range clips the interval.
                auto c = f->in_focus_interval(cam, px, py, coc, 0.01, focus);
                ASSERT_TRUE(c);
                ASSERT_EQ(c->intervals.size(), 1u);
                EXPECT_EQ(c->intervals[0].far, focus);
            }
    }
    // Nothing is sharp enough: empty, primary() collapses to the sharpest depth.
    auto f = BlurField::from_thin_lens(lens(2.0));
    auto r = f->in_focus_interval(cam, 960, 540, 1.0, 5.0, 50.0);
    ASSERT_TRUE(r);
    EXPECT_TRUE(r->empty());
    EXPECT_EQ(r->primary().near, 5.0);
    EXPECT_EQ(r->primary().far, 5.0);
}

TEST(blur_field_ray, ThinLensProfile) {
    const Camera cam = test_camera();
    const ThinLens l = lens(3.0);
    auto f = BlurField::from_thin_lens(l);
    RayProfileOptions o;
    o.tolerance_px = 0.01;
    auto p = f->sample_along_ray(cam, 700.5, 300.5, 0.5, 100.0, o);
    ASSERT_TRUE(p) << p.message();
    ASSERT_GE(p->size(), 3u);
    EXPECT_EQ(p->depth.front(), 0.5);
    EXPECT_EQ(p->depth.back(), 100.0);
    // One in-focus vertex, exactly at the focus distance.
    const auto zeros = p->in_focus_depths();
    ASSERT_EQ(zeros.size(), 1u);
    EXPECT_NEAR(zeros[0], 3.0, 1e-12);
    for (std::size_t i = 1; i < p->size(); ++i) EXPECT_LT(p->depth[i - 1], p->depth[i]);
    // Polyline within ~tolerance of the exact CoC everywhere (dense check).
    double worst = 0;
    for (int i = 0; i <= 20000; ++i) {
        const double d = 0.5 * std::pow(200.0, i / 20000.0);
        worst = std::max(worst, std::fabs(p->radius_at(d) - l.coc_radius_px(d)));
    }
    EXPECT_LE(worst, 2.0 * o.tolerance_px);
    // Vertex values are exact; the line maps depth to the pixel's ray.
    for (std::size_t i = 0; i < p->size(); i += 7) EXPECT_NEAR(p->radius[i], l.coc_radius_px(p->depth[i]), 1e-9);
    const PixelDepth pd = cam.project(p->line.at(7.0));
    EXPECT_NEAR(pd.x, 700.5, 1e-9);
    EXPECT_NEAR(pd.depth, 7.0, 1e-12);
    // A tighter tolerance gives more vertices.
    o.tolerance_px = 0.001;
    auto q = f->sample_along_ray(cam, 700.5, 300.5, 0.5, 100.0, o);
    EXPECT_GT(q->size(), p->size());
}

TEST(blur_field_ray, FocalPlanesBreakpoints) {
    const Camera cam = test_camera();
    const BlurField f = parse_ok(R"({"blurfield": {"kind": "focal_planes", "depths": [2, 5, 9], "max_blur": 6, "slope": 2}})");
    auto p = f.sample_along_ray(cam, 123.5, 456.5, 0.5, 20.0);
    ASSERT_TRUE(p) << p.message();
    // In-focus vertices at each listed depth, flagged InFocus.
    const auto zeros = p->in_focus_depths();
    ASSERT_EQ(zeros.size(), 3u);
    EXPECT_DOUBLE_EQ(zeros[0], 2.0);
    EXPECT_DOUBLE_EQ(zeros[1], 5.0);
    EXPECT_DOUBLE_EQ(zeros[2], 9.0);
    // Kinks: ramp ends (plane +- 6/2 = 3) and the tent top between 2 and 5 (3.5).
    for (double d : {3.5, 8.0, 6.0, 12.0}) EXPECT_TRUE(has_vertex(*p, d)) << d;
    // Piecewise linear: no extra samples, and the polyline is exact.
    EXPECT_LE(p->size(), 12u);
    for (int i = 0; i <= 1000; ++i) {
        const double d = 0.5 + 19.5 * i / 1000.0;
        EXPECT_NEAR(p->radius_at(d), f.evaluate_on_ray(cam, 123.5, 456.5, d), 1e-9) << d;
    }
    // Intervals below 1 px: +-0.5 around each plane.
    auto r = f.in_focus_interval(cam, 123.5, 456.5, 1.0, 0.5, 20.0);
    ASSERT_TRUE(r);
    ASSERT_EQ(r->intervals.size(), 3u);
    const double want[3][2] = {{1.5, 2.5}, {4.5, 5.5}, {8.5, 9.5}};
    for (int i = 0; i < 3; ++i) {
        EXPECT_NEAR(r->intervals[i].near, want[i][0], 1e-9);
        EXPECT_NEAR(r->intervals[i].far, want[i][1], 1e-9);
    }
    // primary(): the interval around the first sharpest depth.
    EXPECT_NEAR(r->primary().near, 1.5, 1e-9);
}

TEST(blur_field_ray, SmoothFocalPlanesWithinTolerance) {
    const Camera cam = test_camera();
    const BlurField f = parse_ok(
        R"({"blurfield": {"kind": "focal_planes", "depths": [2, 5], "max_blur": 6, "interpolation": "smooth"}})");
    RayProfileOptions o;
    o.tolerance_px = 0.005;
    auto p = f.sample_along_ray(cam, 960, 540, 1.0, 8.0, o);
    ASSERT_TRUE(p);
    EXPECT_GT(p->size(), 10u);  // curved parts subdivided
    double worst = 0;
    for (int i = 0; i <= 7000; ++i) {
        const double d = 1.0 + 7.0 * i / 7000.0;
        worst = std::max(worst, std::fabs(p->radius_at(d) - f.evaluate_on_ray(cam, 960, 540, d)));
    }
    EXPECT_LE(worst, 1.5 * o.tolerance_px);
    EXPECT_EQ(p->in_focus_depths(), (std::vector<double>{2.0, 5.0}));
}

TEST(blur_field_ray, RegionBoundaryCrossings) {
    const Camera cam = test_camera();
    // Sphere of focus centred on the optical axis 5 units in front of the camera.
    const Vec3 c{0.5, 1.0, -3.0};
    const BlurField f = parse_ok(R"({"blurfield": {"kind": "region", "shape": "sphere", "center": [0.5, 1.0, -3.0],
        "radius": 1, "blur": 8, "falloff": 2, "interpolation": "linear"}})");
    for (auto [px, py] : {std::pair{960.0, 540.0}, std::pair{1100.5, 600.5}}) {
        auto p = f.sample_along_ray(cam, px, py, 0.5, 20.0);
        ASSERT_TRUE(p) << p.message();
        // Analytic ray-sphere intersections, in depth: |o + v d - c|^2 = R^2.
        const DepthLine line = cam.depth_line(px, py);
        auto hits = [&](double R) {
            const Vec3 oc = line.origin - c;
            const double A = dot(line.per_depth, line.per_depth), B = 2 * dot(oc, line.per_depth),
                         C = dot(oc, oc) - R * R;
            const double disc = std::sqrt(B * B - 4 * A * C);
            return std::pair{(-B - disc) / (2 * A), (-B + disc) / (2 * A)};
        };
        for (double R : {1.0, 3.0}) {
            auto [d0, d1] = hits(R);
            EXPECT_TRUE(has_vertex(*p, d0, 1e-9)) << "R " << R << " near hit " << d0;
            EXPECT_TRUE(has_vertex(*p, d1, 1e-9)) << "R " << R << " far hit " << d1;
        }
        // In-focus interval below any CoC < blur: the sphere itself (falloff starts at its surface).
        auto r = f.in_focus_interval(cam, px, py, 1e-9, 0.5, kInf);
        ASSERT_TRUE(r);
        ASSERT_EQ(r->intervals.size(), 1u);
        const auto [h0, h1] = hits(1.0);
        EXPECT_NEAR(r->intervals[0].near, h0, 1e-8);
        EXPECT_NEAR(r->intervals[0].far, h1, 1e-8);
        // CoC 4 px = half the falloff: the sphere of radius 2.
        auto r4 = f.in_focus_interval(cam, px, py, 4.0, 0.5, 20.0);
        ASSERT_TRUE(r4);
        ASSERT_EQ(r4->intervals.size(), 1u);
        const auto [g0, g1] = hits(2.0);
        EXPECT_NEAR(r4->intervals[0].near, g0, 1e-8);
        EXPECT_NEAR(r4->intervals[0].far, g1, 1e-8);
    }
    // A ray missing the sphere: no interval, min radius = blur.
    auto miss = f.in_focus_interval(cam, 5.5, 5.5, 1.0, 0.5, 20.0);
    ASSERT_TRUE(miss);
    EXPECT_TRUE(miss->empty());
}

TEST(blur_field_ray, HardEdgeIsAStep) {
    const Camera cam = test_camera();
    const BlurField f = parse_ok(R"({"blurfield": {"kind": "region", "shape": "box", "center": [0.5, 1.0, -4.0],
        "size": [1, 1, 2], "mode": "blur", "blur": 5}})");
    auto p = f.sample_along_ray(cam, 960, 540, 1.0, 10.0);
    ASSERT_TRUE(p);
    // Box spans depth 5..7 on the axis: steps there, two vertices each.
    EXPECT_NEAR(p->radius_at(4.9), 0.0, 1e-9);
    EXPECT_NEAR(p->radius_at(6.0), 5.0, 1e-9);
    EXPECT_NEAR(p->radius_at(7.1), 0.0, 1e-9);
    EXPECT_TRUE(has_vertex(*p, 5.0, 1e-8));
    EXPECT_TRUE(has_vertex(*p, 7.0, 1e-8));
    auto r = f.in_focus_interval(cam, 960, 540, 1.0, 1.0, 10.0);
    ASSERT_TRUE(r);
    ASSERT_EQ(r->intervals.size(), 2u);
    EXPECT_NEAR(r->intervals[0].far, 5.0, 1e-9);
    EXPECT_NEAR(r->intervals[1].near, 7.0, 1e-9);
}

TEST(blur_field_ray, CombinatorKinks) {
    const Camera cam = test_camera();
    const ThinLens l = lens(3.0);
    // clamp(max 5) of a thin lens kinks where the CoC is 5 px: the DOF limits for 5 px.
    const BlurField f = parse_ok(R"({"blurfield": {"kind": "thin_lens", "focal_length_mm": 50, "f_number": 2,
        "focus_distance": 3}, "max_radius": 5})");
    auto p = f.sample_along_ray(cam, 960, 540, 0.5, 50.0);
    ASSERT_TRUE(p);
    const auto lim = l.dof_limits(5.0);
    EXPECT_TRUE(has_vertex(*p, lim.near, 1e-9)) << lim.near;
    EXPECT_TRUE(has_vertex(*p, lim.far, 1e-9)) << lim.far;
    // min of two lenses focused at 2 and 6: kink where they cross, zeros at both.
    const BlurField m = parse_ok(R"({"blurfield": {"kind": "min", "children": [
        {"kind": "thin_lens", "focal_length_mm": 50, "f_number": 2, "focus_distance": 2},
        {"kind": "thin_lens", "focal_length_mm": 50, "f_number": 2, "focus_distance": 6}]}})");
    auto q = m.sample_along_ray(cam, 960, 540, 0.5, 50.0);
    ASSERT_TRUE(q);
    EXPECT_EQ(q->in_focus_depths().size(), 2u);
    // Equal CoC between the two focus distances where 1 - 2/z = 6/z - 1 (approx., same lens
    // factor up to (s - f)): solve exactly with ThinLens.
    const ThinLens a = lens(2.0), b = lens(6.0);
    double lo = 2.0, hi = 6.0;
    for (int i = 0; i < 200; ++i) {
        const double mid = 0.5 * (lo + hi);
        (a.coc_radius_px(mid) < b.coc_radius_px(mid) ? lo : hi) = mid;
    }
    EXPECT_TRUE(has_vertex(*q, lo, 1e-9)) << lo;
    auto r = m.in_focus_interval(cam, 960, 540, 1.0, 0.5, kInf);
    ASSERT_TRUE(r);
    EXPECT_EQ(r->intervals.size(), 2u);
    expect_rel(r->intervals[0].near, a.dof_limits(1.0).near, 1e-6);
    expect_rel(r->intervals[1].far, b.dof_limits(1.0).far, 1e-6);
}

TEST(blur_field_ray, ArgumentErrors) {
    const Camera cam = test_camera();
    auto f = BlurField::from_thin_lens(lens(2.0));
    EXPECT_FALSE(f->sample_along_ray(cam, 0, 0, -1, 10));
    EXPECT_FALSE(f->sample_along_ray(cam, 0, 0, 5, 5));
    EXPECT_FALSE(f->sample_along_ray(cam, 0, 0, 1, kInf));
    EXPECT_FALSE(f->sample_along_ray(cam, std::nan(""), 0, 1, 10));
    EXPECT_FALSE(f->in_focus_interval(cam, 0, 0, -1, 1, 10));
    EXPECT_TRUE(f->in_focus_interval(cam, 0, 0, 1, 0, kInf));  // depth_min 0 is fine
    auto iv = f->primary_in_focus_interval(cam, 960, 540, 1.0, 0.1, kInf);
    ASSERT_TRUE(iv);
    expect_rel(iv->near, lens(2.0).dof_limits(1.0).near, 1e-6);
}
