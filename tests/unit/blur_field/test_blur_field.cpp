// Blur field evaluation: every kind against hand values, combinators, batch ==
// single, (pixel, depth) == world-point evaluation, concurrent evaluation.
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "gdof/blur_field.h"
#include "test_support.h"

using namespace gdof;

namespace {


// At the origin looking down world -z: the point (0, 0, -d) has depth d.
Camera test_camera(Roi dw = {0, 0, 1920, 1080}) {
    CameraDesc d;
    d.position = {0, 0, 0};
    d.look_at = {0, 0, -1};
    d.up = {0, 1, 0};
    d.focal_length_mm = 50;
    d.sensor_width_mm = 36;
    d.display_window = dw;
    auto c = Camera::create(d);
    EXPECT_TRUE(c) << c.message();
    return c.value();
}

BlurField parse_ok(const std::string& text, const BlurField::Context& ctx = {}) {
    auto r = BlurField::parse(text, ctx);
    EXPECT_TRUE(r) << r.message() << "\n" << text;
    return r ? r.value() : BlurField();
}

// B at the point on the optical axis at depth d.
double on_axis(const BlurField& f, const Camera& cam, double d) { return f.evaluate(cam, Vec3{0, 0, -d}); }

const char* kThinLens = R"({"blurfield": {"kind": "thin_lens", "focal_length_mm": 50, "f_number": 2,
                            "focus_distance": 2, "sensor_width_mm": 36}})";

}  // namespace

TEST(blur_field, ThinLensEqualsThinLensCoc) {
    const Camera cam = test_camera();
    const BlurField f = parse_ok(kThinLens);
    ThinLens l;
    l.focal_length_mm = 50, l.f_number = 2, l.focus_distance = 2, l.sensor_width_mm = 36, l.image_width_px = 1920;
    // Hand value at 4 m: 4000/468 px (see test_thin_lens.cpp).
    EXPECT_NEAR(on_axis(f, cam, 4.0), 4000.0 / 468.0, 1e-5);
    EXPECT_EQ(on_axis(f, cam, 2.0), 0.0f);
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-1, 1), logd(std::log(0.05), std::log(1e4));
    for (int i = 0; i < 500; ++i) {
        const double d = std::exp(logd(rng));
        const Vec3 p = cam.unproject(960 + 900 * u(rng), 540 + 500 * u(rng), d);
        const double want = l.coc_radius_px(d);
        EXPECT_NEAR(f.evaluate(cam, p), want, 1e-6 * want + 1e-6) << d;
        EXPECT_NEAR(f.evaluate_on_ray(cam, 100.5, 200.5, d), want, 1e-12 * want);
    }
    // The camera's width is used: half the width, half the radius.
    const Camera half = test_camera({0, 0, 960, 540});
    EXPECT_NEAR(on_axis(f, half, 4.0), 0.5 * 4000.0 / 468.0, 1e-5);
    // Programmatic construction gives the same field.
    auto g = BlurField::from_thin_lens(l);
    ASSERT_TRUE(g);
    EXPECT_EQ(g->evaluate(cam, Vec3{0.3, -0.2, -7.0}), f.evaluate(cam, Vec3{0.3, -0.2, -7.0}));
    EXPECT_TRUE(f.depth_only());
    // Behind the camera / NaN.
    EXPECT_TRUE(std::isinf(on_axis(f, cam, -1.0)));
    EXPECT_TRUE(std::isnan(f.evaluate(cam, Vec3{0, 0, std::nan("")})));
}

TEST(blur_field, FocalPlanesLinear) {
    const Camera cam = test_camera();
    // Planes at 2 and 6, max 10 px, no slope: ramps reach 10 px half way between
    // the planes (2 scene units), and the outer ramps use the same length.
    const BlurField f = parse_ok(R"({"blurfield": {"kind": "focal_planes", "depths": [6, 2], "max_blur": 10}})");
    const std::vector<std::pair<double, double>> hand = {{2, 0},   {3, 5},  {4, 10}, {5, 5},   {6, 0},
                                                         {7, 5},   {8, 10}, {20, 10}, {1, 5}, {0.5, 7.5}};
    for (auto [d, b] : hand) EXPECT_NEAR(on_axis(f, cam, d), b, 1e-5) << d;
    // With a slope of 2 px per scene unit: ramp length 10/2 = 5.
    const BlurField s =
        parse_ok(R"({"blurfield": {"kind": "focal_planes", "depths": [2, 6], "max_blur": 10, "slope": 2}})");
    EXPECT_NEAR(on_axis(s, cam, 4.0), 4.0, 1e-5);   // 2 from both planes
    EXPECT_NEAR(on_axis(s, cam, 1.0), 2.0, 1e-5);
    EXPECT_NEAR(on_axis(s, cam, 12.0), 10.0, 1e-5);  // clamped at max_blur
    // Slope only, single plane: unbounded linear.
    const BlurField o = parse_ok(R"({"blurfield": {"kind": "focal_planes", "depths": [3], "slope": 1.5}})");
    EXPECT_NEAR(on_axis(o, cam, 103.0), 150.0, 1e-4);
    EXPECT_NEAR(on_axis(o, cam, 1.0), 3.0, 1e-5);
}

TEST(blur_field, FocalPlanesSmooth) {
    const Camera cam = test_camera();
    const BlurField f = parse_ok(
        R"({"blurfield": {"kind": "focal_planes", "depths": [2, 6], "max_blur": 10, "interpolation": "smooth"}})");
    // smoothstep S(t) = t^2 (3 - 2 t) over the ramp length 2.
    EXPECT_NEAR(on_axis(f, cam, 2.0), 0.0, 1e-6);
    EXPECT_NEAR(on_axis(f, cam, 3.0), 5.0, 1e-5);                          // S(0.5) = 0.5
    EXPECT_NEAR(on_axis(f, cam, 2.5), 10 * 0.0625 * 2.5, 1e-5);            // S(0.25) = 0.15625
    EXPECT_NEAR(on_axis(f, cam, 4.0), 10.0, 1e-5);
    EXPECT_NEAR(on_axis(f, cam, 7.5), 10 * 0.5625 * 1.5, 1e-5);            // S(0.75) = 0.84375
    // C1: symmetric difference quotient continuous across the plane (slope 0).
    const double h = 1e-4;
    EXPECT_NEAR(f.evaluate_on_ray(cam, 960, 540, 2 + h) / h, 0.0, 1e-2);
}

TEST(blur_field, RegionSphere) {
    const Camera cam = test_camera();
    const std::string sphere = R"("shape": "sphere", "center": [0, 0, -5], "radius": 1, "blur": 8, "falloff": 2)";
    const BlurField lin = parse_ok(R"({"blurfield": {"kind": "region", )" + sphere + R"(, "interpolation": "linear"}})");
    EXPECT_NEAR(on_axis(lin, cam, 5.0), 0.0, 1e-6);   // centre
    EXPECT_NEAR(on_axis(lin, cam, 4.2), 0.0, 1e-6);   // inside
    EXPECT_NEAR(on_axis(lin, cam, 3.0), 4.0, 1e-5);   // 1 outside of 2: half
    EXPECT_NEAR(on_axis(lin, cam, 2.0), 8.0, 1e-5);
    EXPECT_NEAR(on_axis(lin, cam, 1.0), 8.0, 1e-5);
    EXPECT_NEAR(lin.evaluate(cam, Vec3{1.5, 0, -5}), 2.0, 1e-5);  // 0.5 outside sideways
    const BlurField smooth = parse_ok(R"({"blurfield": {"kind": "region", )" + sphere + "}}");  // smooth default
    EXPECT_NEAR(on_axis(smooth, cam, 3.5), 8 * 0.15625, 1e-5);  // S(0.25)
    EXPECT_NEAR(on_axis(smooth, cam, 3.0), 4.0, 1e-5);
    const BlurField blur =
        parse_ok(R"({"blurfield": {"kind": "region", "mode": "blur", )" + sphere + R"(, "interpolation": "linear"}})");
    EXPECT_NEAR(on_axis(blur, cam, 5.0), 8.0, 1e-5);
    EXPECT_NEAR(on_axis(blur, cam, 3.0), 4.0, 1e-5);
    EXPECT_NEAR(on_axis(blur, cam, 1.0), 0.0, 1e-6);
    // Hard edge.
    const BlurField hard = parse_ok(
        R"({"blurfield": {"kind": "region", "shape": "sphere", "center": [0, 0, -5], "radius": 1, "blur": 3}})");
    EXPECT_EQ(on_axis(hard, cam, 4.01), 0.0f);
    EXPECT_EQ(on_axis(hard, cam, 3.99), 3.0f);
    EXPECT_FALSE(hard.depth_only());
}

TEST(blur_field, RegionBoxAndPlane) {
    const Camera cam = test_camera();
    const BlurField box = parse_ok(
        R"({"blurfield": {"kind": "region", "shape": "box", "min": [-1, -1, -6], "max": [1, 1, -4], "blur": 3}})");
    EXPECT_EQ(on_axis(box, cam, 5.0), 0.0f);
    EXPECT_EQ(on_axis(box, cam, 3.0), 3.0f);
    EXPECT_EQ(box.evaluate(cam, Vec3{0.9, -0.9, -4.1}), 0.0f);
    // Rotated 90 degrees about z: the long side (x size 4) now lies along y.
    const BlurField rot = parse_ok(R"({"blurfield": {"kind": "region", "shape": "box", "center": [0, 0, -5],
        "size": [4, 0.2, 0.2], "rotation_deg": [0, 0, 90], "blur": 10, "falloff": 2.8, "interpolation": "linear"}})");
    EXPECT_EQ(rot.evaluate(cam, Vec3{0, 1.5, -5}), 0.0f);
    // (1.5, 0, -5): 1.5 - 0.1 = 1.4 outside along the short side -> 10 * 1.4 / 2.8
    EXPECT_NEAR(rot.evaluate(cam, Vec3{1.5, 0, -5}), 5.0, 1e-5);
    // Outside a corner: Euclidean distance to the box.
    const BlurField corner = parse_ok(R"({"blurfield": {"kind": "region", "shape": "box", "center": [0, 0, -5],
        "size": [2, 2, 2], "blur": 10, "falloff": 10, "interpolation": "linear"}})");
    EXPECT_NEAR(corner.evaluate(cam, Vec3{4, 5, -5}), 10 * 5.0 / 10.0, 1e-5);  // (3, 4, 0) from the corner
    const BlurField plane = parse_ok(R"({"blurfield": {"kind": "region", "shape": "plane", "point": [0, 0, -5],
        "normal": [0, 0, 2], "thickness": 1, "blur": 6, "falloff": 1, "interpolation": "linear"}})");
    EXPECT_EQ(on_axis(plane, cam, 5.0), 0.0f);
    EXPECT_EQ(on_axis(plane, cam, 5.4), 0.0f);
    EXPECT_NEAR(on_axis(plane, cam, 6.0), 3.0, 1e-5);
    EXPECT_NEAR(on_axis(plane, cam, 4.0), 3.0, 1e-5);
    EXPECT_NEAR(on_axis(plane, cam, 7.0), 6.0, 1e-5);
    EXPECT_NEAR(plane.evaluate(cam, Vec3{100, -50, -6}), 3.0, 1e-5);  // only the normal distance counts
}

TEST(blur_field, ImageMap) {
    const Camera cam = test_camera({0, 0, 8, 4});
    // A 4 x 2 map over the 8 x 4 display: value(x, y) = x + 10 y.
    auto map = std::make_shared<Image>(Image::with_channels({"R", "mask"}, {0, 0, 4, 2}));
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 4; ++x) map->at(1, x, y) = float(x + 10 * y);
    BlurField::Context ctx;
    ctx.images["paint"] = map;
    const BlurField f =
        parse_ok(R"({"blurfield": {"kind": "image_map", "image": "paint", "channel": "mask", "scale": 2}})", ctx);
    // Camera pixel position (4, 2) -> map (2, 1) -> sample space (1.5, 0.5):
    // bilinear of 1, 2, 11, 12 = 6.5, times 2.
    EXPECT_NEAR(f.evaluate_pixel(cam, 4.0, 2.0, 3.0), 13.0, 1e-5);
    EXPECT_NEAR(f.evaluate(cam, cam.unproject(4.0, 2.0, 3.0)), 13.0, 1e-4);
    // Map pixel centre (0.5, 0.5) of the map = camera (1, 1): exactly 0; edges clamp.
    EXPECT_NEAR(f.evaluate_pixel(cam, 1.0, 1.0, 1.0), 0.0, 1e-6);
    EXPECT_NEAR(f.evaluate_pixel(cam, 0.0, 0.0, 1.0), 0.0, 1e-6);
    EXPECT_NEAR(f.evaluate_pixel(cam, 8.0, 4.0, 1.0), 2 * 13.0, 1e-5);
    // Constant along a central ray.
    EXPECT_EQ(f.evaluate_pixel(cam, 4.0, 2.0, 0.5), f.evaluate_pixel(cam, 4.0, 2.0, 500.0));
    // Default channel = first channel (all zeros here).
    const BlurField r = parse_ok(R"({"blurfield": {"kind": "image_map", "image": "paint"}})", ctx);
    EXPECT_EQ(r.evaluate_pixel(cam, 4.0, 2.0, 3.0), 0.0f);
}

TEST(blur_field, Combinators) {
    const Camera cam = test_camera();
    const std::string a = R"({"kind": "focal_planes", "depths": [2, 6], "max_blur": 10})";  // 5 at depth 3
    const std::string b = R"({"kind": "focal_planes", "depths": [3], "slope": 1})";          // 0 at 3, 1 at 2
    auto field = [&](const std::string& kind) {
        return parse_ok(R"({"blurfield": {"kind": ")" + kind + R"(", "children": [)" + a + ", " + b + "]}}");
    };
    // Depth 2.5: a = 2.5, b = 0.5.   Depth 5: a = 5, b = 2.
    EXPECT_NEAR(on_axis(field("min"), cam, 2.5), 0.5, 1e-5);
    EXPECT_NEAR(on_axis(field("max"), cam, 2.5), 2.5, 1e-5);
    EXPECT_NEAR(on_axis(field("add"), cam, 5.0), 7.0, 1e-5);
    EXPECT_NEAR(on_axis(field("mul"), cam, 5.0), 10.0, 1e-5);
    EXPECT_NEAR(on_axis(field("mul"), cam, 3.0), 0.0, 1e-6);
    const BlurField sc = parse_ok(R"({"blurfield": {"kind": "scale", "factor": 0.5, "child": )" + a + "}}");
    EXPECT_NEAR(on_axis(sc, cam, 3.0), 2.5, 1e-5);
    const BlurField cl = parse_ok(R"({"blurfield": {"kind": "clamp", "min": 1, "max": 3, "child": )" + a + "}}");
    EXPECT_NEAR(on_axis(cl, cam, 2.0), 1.0, 1e-5);
    EXPECT_NEAR(on_axis(cl, cam, 2.5), 2.5, 1e-5);
    EXPECT_NEAR(on_axis(cl, cam, 4.0), 3.0, 1e-5);
    const BlurField mr = parse_ok(R"({"blurfield": )" + a + R"(, "max_radius": 4})");
    EXPECT_NEAR(on_axis(mr, cam, 4.0), 4.0, 1e-5);
    EXPECT_NEAR(on_axis(mr, cam, 2.5), 2.5, 1e-5);
    EXPECT_EQ(mr.max_radius(), 4.0);
    EXPECT_EQ(field("min").describe(), "min(focal_planes, focal_planes)");
    // Nested: a sharp subject (sphere) inside a thin-lens crowd.
    const BlurField nested = parse_ok(R"({"blurfield": {"kind": "min", "children": [
        {"kind": "thin_lens", "focal_length_mm": 50, "f_number": 2, "focus_distance": 10},
        {"kind": "region", "shape": "sphere", "center": [0, 0, -4], "radius": 0.5, "blur": 100}]}})");
    EXPECT_EQ(on_axis(nested, cam, 4.0), 0.0f);
    EXPECT_GT(on_axis(nested, cam, 3.0), 5.0f);
}

TEST(blur_field, BatchEqualsSingleAndPixelDepthEqualsPoints) {
    const Camera cam = test_camera();
    auto map = std::make_shared<Image>(Image::with_channels({"Y"}, {0, 0, 16, 9}));
    for (int y = 0; y < 9; ++y)
        for (int x = 0; x < 16; ++x) map->at(0, x, y) = float((x * 7 + y * 3) % 5);
    BlurField::Context ctx;
    ctx.images["m"] = map;
    const BlurField f = parse_ok(R"({"blurfield": {"kind": "max", "children": [
        {"kind": "min", "children": [
            {"kind": "thin_lens", "focal_length_mm": 35, "f_number": 1.4, "focus_distance": 3},
            {"kind": "region", "shape": "sphere", "center": [0.5, 0, -4], "radius": 1, "blur": 20, "falloff": 0.5}]},
        {"kind": "mul", "children": [{"kind": "image_map", "image": "m"},
                                      {"kind": "focal_planes", "depths": [1, 8], "max_blur": 3, "interpolation": "smooth"}]}]},
        "max_radius": 30})", ctx);
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> ux(0, 1920), uy(0, 1080), ud(0.2, 50);
    const std::size_t n = 1000;  // several chunks, last one partial
    std::vector<Vec3> pts(n);
    std::vector<PixelDepth> pds(n);
    for (std::size_t i = 0; i < n; ++i) {
        pds[i] = {ux(rng), uy(rng), ud(rng)};
        pts[i] = cam.unproject(pds[i].x, pds[i].y, pds[i].depth);
    }
    std::vector<float> batch(n), batch_pd(n);
    ASSERT_TRUE(f.evaluate(cam, pts, batch));
    ASSERT_TRUE(f.evaluate(cam, pds, batch_pd));
    for (std::size_t i = 0; i < n; ++i) {
        EXPECT_EQ(batch[i], f.evaluate(cam, pts[i])) << i;
        EXPECT_EQ(batch_pd[i], f.evaluate_pixel(cam, pds[i].x, pds[i].y, pds[i].depth)) << i;
        EXPECT_NEAR(batch[i], batch_pd[i], 1e-4 * (1 + batch[i])) << i;
        EXPECT_LE(batch[i], 30.0f);
    }
    std::vector<float> wrong(n - 1);
    EXPECT_FALSE(f.evaluate(cam, pts, wrong));
}

TEST(blur_field, ConcurrentEvaluationIsIdentical) {
    const Camera cam = test_camera();
    const BlurField f = parse_ok(R"({"blurfield": {"kind": "add", "children": [
        {"kind": "thin_lens", "focal_length_mm": 50, "f_number": 2, "focus_distance": 2},
        {"kind": "region", "shape": "box", "center": [0, 0, -6], "size": [2, 2, 2], "rotation_deg": [10, 20, 30],
         "blur": 5, "falloff": 1, "mode": "blur"}]}})");
    const std::size_t n = 20000;
    std::vector<Vec3> pts(n);
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(-3, 3), d(0.5, 20);
    for (auto& p : pts) p = {u(rng), u(rng), -d(rng)};
    std::vector<float> ref(n);
    ASSERT_TRUE(f.evaluate(cam, pts, ref));
    const int nthreads = 4;
    std::vector<std::vector<float>> out(nthreads, std::vector<float>(n));
    std::vector<std::thread> threads;
    BlurField copy = f;  // copies share the tree
    for (int t = 0; t < nthreads; ++t)
        threads.emplace_back([&, t] {
            const BlurField& g = (t % 2) ? copy : f;
            for (int rep = 0; rep < 3; ++rep) (void)g.evaluate(cam, pts, out[t]);
        });
    for (auto& th : threads) th.join();
    for (int t = 0; t < nthreads; ++t) EXPECT_EQ(out[t], ref) << "thread " << t;
}

TEST(blur_field, DefaultIsZero) {
    const BlurField f;
    const Camera cam = test_camera();
    EXPECT_EQ(f.evaluate(cam, Vec3{1, 2, -3}), 0.0f);
    EXPECT_EQ(f.describe(), "zero");
}
