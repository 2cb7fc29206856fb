// What the ray tracer hands the other methods, and what the blur field does
// to its images:
//  - two focal planes render each plane as sharp as a thin lens focused on
//    it (region by region) and blur what lies between;
//  - a small emissive square off the focal plane images as a disc of the
//    thin-lens CoC radius;
//  - the deep output flattens to exactly the flat render;
//  - AOV selection, a lens override, and a blur field that cannot be
//    sampled (an error, not a silent pinhole).
#include <cmath>
#include <sstream>

#include "gdof/layers.h"
#include "gdof/raytrace.h"
#include "scene_test_helpers.h"

using namespace gdof;
using gdof::test::ScratchDir;
using gdof::test::write_file;

namespace {

constexpr int kW = 192, kH = 64;
constexpr double kTan = 18.0 / 50.0;  // half-width / depth: 50 mm lens, 36 mm sensor

// Quads of an emissive checkerboard (cells of `cell` scene units) covering
// x in [x0, x1], y in [-h, h] at depth d (the camera looks down -z).
std::string checker_obj(double x0, double x1, double h, double d, double cell, int& vbase) {
    std::ostringstream o;
    const int nx = int(std::ceil((x1 - x0) / cell)), ny = int(std::ceil(2 * h / cell));
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
            const double a = x0 + i * cell, b = std::min(x1, a + cell);
            const double c = -h + j * cell, e = std::min(h, c + cell);
            o << "usemtl " << (((i + j) & 1) ? "white" : "dark") << "\n";
            o << "v " << a << " " << c << " " << -d << "\nv " << b << " " << c << " " << -d << "\n";
            o << "v " << b << " " << e << " " << -d << "\nv " << a << " " << e << " " << -d << "\n";
            o << "f " << vbase << " " << vbase + 1 << " " << vbase + 2 << " " << vbase + 3 << "\n";
            vbase += 4;
        }
    return o.str();
}

// Three checkerboards side by side: depth 3 on the left third, 5 in the
// middle, 9 on the right (each exactly filling its third of a 192 x 64 view).
Scene three_planes(const ScratchDir& dir, const std::string& camera_extra = "", double camera_x = 0) {
    write_file(dir.file("planes.mtl"), "newmtl white\nKd 0 0 0\nKe 1 1 1\nnewmtl dark\nKd 0 0 0\nKe 0.1 0.1 0.1\n");
    std::string obj = "mtllib planes.mtl\n";
    int vb = 1;
    const double cell = 4 * 2 * kTan / kW;  // 4 px at depth 1
    obj += "o near\n" + checker_obj(-2 * kTan * 3, -kTan / 3 * 3, 0.2 * 3, 3, cell * 3, vb);
    obj += "o mid\n" + checker_obj(-kTan / 3 * 5, kTan / 3 * 5, 0.2 * 5, 5, cell * 5, vb);
    obj += "o far\n" + checker_obj(kTan / 3 * 9, 2 * kTan * 9, 0.2 * 9, 9, cell * 9, vb);
    write_file(dir.file("planes.obj"), obj);
    const std::string cx = std::to_string(camera_x);
    const std::string json = R"({"camera": {"position": [)" + cx + R"(, 0, 0], "look_at": [)" + cx + R"(, 0, -1], "focal_length_mm": 50,
        "sensor_width_mm": 36, "resolution": [)" + std::to_string(kW) + ", " + std::to_string(kH) + "]" +
                             camera_extra + R"(}, "meshes": [{"file": "planes.obj"}]})";
    auto r = parse_scene(json, dir.path().string());
    EXPECT_TRUE(r) << r.message();
    return r ? std::move(r).value() : Scene{};
}

#define RENDER_OR_SKIP(var, ...)                                                                 \
    auto var##_r = render(__VA_ARGS__);                                                          \
    if (!var##_r && var##_r.message().find("without Embree") != std::string::npos)               \
        GDOF_SKIP_OR_FAIL(var##_r.message());                                                       \
    ASSERT_TRUE(var##_r) << var##_r.message();                                                   \
    const Image& var = var##_r.value()

// Columns [x0, x1) x all rows: max |a - b| over R, G, B.
double max_diff(const Image& a, const Image& b, int x0, int x1) {
    double m = 0;
    for (int c = 0; c < 3; ++c)
        for (int y = 0; y < kH; ++y)
            for (int x = x0; x < x1; ++x) m = std::max(m, std::abs(double(a.at(c, x, y)) - b.at(c, x, y)));
    return m;
}

// Mean squared horizontal + vertical difference of G (sharpness).
double gradient_energy(const Image& img, int x0, int x1) {
    double e = 0;
    int n = 0;
    for (int y = 2; y + 3 < kH; ++y)
        for (int x = x0; x + 1 < x1; ++x) {
            const double dx = img.at(1, x + 1, y) - img.at(1, x, y), dy = img.at(1, x, y + 1) - img.at(1, x, y);
            e += dx * dx + dy * dy, ++n;
        }
    return e / n;
}

LensInfo lens_at(const Scene& s, double focus, double f_number) {
    LensInfo l = s.camera.lens();
    l.focus_distance = focus;
    l.f_number = f_number;
    return l;
}

}  // namespace

TEST(raytrace_outputs, two_focal_planes_are_as_sharp_as_thin_lenses_focused_on_each) {
    ScratchDir dir;
    const Scene scene = three_planes(dir);
    auto field = BlurField::parse(R"({"blurfield": {"kind": "focal_planes", "depths": [3, 9], "max_blur": 8}})");
    ASSERT_TRUE(field) << field.message();
    RenderOptions rs;
    rs.spp = 32;
    rs.adaptive_threshold = 0;
    rs.aovs = RenderAov::None;
    rs.blur_field = &field.value();
    RENDER_OR_SKIP(planes, scene, rs);

    RenderOptions tl = rs;
    tl.blur_field = nullptr;
    tl.lens = lens_at(scene, 3.0, 2.0);
    RENDER_OR_SKIP(at3, scene, tl);
    tl.lens = lens_at(scene, 9.0, 2.0);
    RENDER_OR_SKIP(at9, scene, tl);
    RenderOptions ph = rs;
    ph.pinhole = true;
    RENDER_OR_SKIP(pin, scene, ph);

    // Regions well inside each third (12 px from the borders, where the
    // blurred middle plane spreads over the sharp ones).
    const int l0 = 0, l1 = kW / 3 - 12, m0 = kW / 3 + 12, m1 = 2 * kW / 3 - 12, r0 = 2 * kW / 3 + 12, r1 = kW;
    // Each plane equals the thin lens focused on it (same samples: the rays
    // of both cameras cross at the same point of the plane).
    EXPECT_LT(max_diff(planes, at3, l0, l1), 1e-4);
    EXPECT_LT(max_diff(planes, at9, r0, r1), 1e-4);
    // ... and those thin lenses blur the other plane (the comparison can fail).
    EXPECT_GT(max_diff(planes, at9, l0, l1), 0.1);
    EXPECT_GT(max_diff(planes, at3, r0, r1), 0.1);
    // Sharp planes keep the pinhole's gradient energy; the middle plane
    // (B = 8 * 2/3 = 5.3 px, checker cells of 4 px) is blurred.
    EXPECT_GT(gradient_energy(planes, l0, l1), 0.9 * gradient_energy(pin, l0, l1));
    EXPECT_GT(gradient_energy(planes, r0, r1), 0.9 * gradient_energy(pin, r0, r1));
    EXPECT_LT(gradient_energy(planes, m0, m1), 0.2 * gradient_energy(pin, m0, m1));
}

TEST(raytrace_outputs, emissive_square_off_focus_images_as_a_coc_disc) {
    ScratchDir dir;
    // A 1.5 px emissive square at depth 2 (85 mm f/2, focused at 4: CoC radius ~9.4 px).
    const int W = 64;
    const double depth = 2.0, half = 0.75 * (2 * 18.0 / 85.0 * depth / W);
    write_file(dir.file("sq.mtl"), "newmtl lamp\nKd 0 0 0\nKe 1 1 1\n");
    std::ostringstream obj;
    obj << "mtllib sq.mtl\nusemtl lamp\n"
        << "v " << -half << " " << -half << " " << -depth << "\nv " << half << " " << -half << " " << -depth << "\n"
        << "v " << half << " " << half << " " << -depth << "\nv " << -half << " " << half << " " << -depth << "\n"
        << "f 1 2 3 4\n";
    write_file(dir.file("sq.obj"), obj.str());
    auto scene = parse_scene(R"({"camera": {"position": [0, 0, 0], "look_at": [0, 0, -1], "focal_length_mm": 85,
        "sensor_width_mm": 36, "resolution": [64, 64], "f_number": 2, "focus_distance": 4},
        "meshes": [{"file": "sq.obj"}]})", dir.path().string());
    ASSERT_TRUE(scene) << scene.message();
    RenderOptions rs;
    rs.spp = 1024;
    rs.adaptive_threshold = 0;
    rs.pixel_jitter = false;
    rs.aovs = RenderAov::None;
    RENDER_OR_SKIP(img, scene.value(), rs);
    // The image is the disc convolved with the square (side s = 1.5 px):
    // E[r^2] = R^2 / 2 + s^2 / 6.
    double m0 = 0, mx = 0, my = 0;
    for (int y = 0; y < W; ++y)
        for (int x = 0; x < W; ++x) m0 += img.at(1, x, y), mx += img.at(1, x, y) * (x + 0.5), my += img.at(1, x, y) * (y + 0.5);
    mx /= m0, my /= m0;
    double m2 = 0;
    for (int y = 0; y < W; ++y)
        for (int x = 0; x < W; ++x) m2 += img.at(1, x, y) * ((x + 0.5 - mx) * (x + 0.5 - mx) + (y + 0.5 - my) * (y + 0.5 - my));
    m2 /= m0;
    const double radius = std::sqrt(2 * (m2 - 1.5 * 1.5 / 6));
    const ThinLens lens{85, 2, 4, 36, double(W), 1000};
    EXPECT_NEAR(radius, lens.coc_radius_px(depth), 0.5) << "CoC formula " << lens.coc_radius_px(depth);
    EXPECT_NEAR(mx, W / 2.0, 0.2);
    EXPECT_NEAR(my, W / 2.0, 0.2);
}

TEST(raytrace_outputs, deep_render_flattens_to_the_flat_render) {
    ScratchDir dir;
    for (const char* env : {"", R"(, "environment": [0.2, 0.3, 0.4])"}) {
        // Shifted a fraction of a pixel, so the planes' edges cut pixels.
        Scene scene = three_planes(dir, "", 0.005);
        if (*env) scene.environment = Vec3{0.2, 0.3, 0.4};
        auto tracer = RayTracer::build(scene);
        if (!tracer && tracer.message().find("without Embree") != std::string::npos) GDOF_SKIP_OR_FAIL(tracer.message());
        ASSERT_TRUE(tracer) << tracer.message();
        for (bool pinhole : {true, false}) {
            RenderOptions rs;
            rs.spp = 16;
            rs.pinhole = pinhole;
            rs.lens = lens_at(scene, 5.0, 2.8);
            rs.adaptive_threshold = 0.05;  // adaptive: pixels keep different sample counts
            auto flat = render(*tracer.value(), rs);
            auto deep = render_deep(*tracer.value(), rs);
            ASSERT_TRUE(flat) << flat.message();
            ASSERT_TRUE(deep) << deep.message();
            auto flattened = flatten_deep(deep.value());
            ASSERT_TRUE(flattened) << flattened.message();
            double m = 0;
            for (const char* ch : {"R", "G", "B", "A"}) {
                const int a = flat->channel_index(ch), b = flattened->channel_index(ch);
                ASSERT_GE(a, 0);
                ASSERT_GE(b, 0);
                for (int y = 0; y < kH; ++y)
                    for (int x = 0; x < kW; ++x) m = std::max(m, std::abs(double(flat->at(a, x, y)) - flattened->at(b, x, y)));
            }
            EXPECT_LT(m, 1e-5) << "pinhole " << pinhole << " environment '" << env << "'";
            // Edges give several surfaces per pixel, sorted by depth.
            const DeepImage& d = deep.value();
            const int z = d.z_channel();
            std::size_t multi = 0;
            for (std::size_t p = 0; p < d.npixels(); ++p) {
                multi += d.sample_count(p) > 1;
                for (std::size_t k = d.first_sample(p) + 1; k < d.first_sample(p) + d.sample_count(p); ++k)
                    ASSERT_LE(d.samples(z)[k - 1], d.samples(z)[k]);
            }
            EXPECT_GT(multi, std::size_t(kH)) << "the planes' edges should give pixels with two surfaces";
            EXPECT_GE(d.channel_index("ZBack"), 0);
            EXPECT_GE(d.channel_index("id"), 0);
        }
    }
}

TEST(raytrace_outputs, aovs_select_channels) {
    ScratchDir dir;
    const Scene scene = three_planes(dir);
    RenderOptions rs;
    rs.spp = 2;
    rs.aovs = parse_render_aovs("Z,id").value();
    RENDER_OR_SKIP(img, scene, rs);
    std::vector<std::string> names;
    for (const ChannelSpec& c : img.channels()) names.push_back(c.name);
    EXPECT_EQ(names, (std::vector<std::string>{"R", "G", "B", "A", "Z", "id"}));
    rs.aovs = RenderAov::None;
    RENDER_OR_SKIP(bare, scene, rs);
    EXPECT_EQ(bare.nchannels(), 4);
    // The beauty does not depend on which AOVs are written.
    EXPECT_EQ(max_diff(img, bare, 0, kW), 0.0);
    EXPECT_FALSE(parse_render_aovs("Z,depth"));
    EXPECT_NE(parse_render_aovs("Z,depth").message().find("'depth'"), std::string::npos);
    EXPECT_EQ(format_render_aovs(parse_render_aovs("all").value()), "albedo,Z,P,N,id");
}

TEST(raytrace_outputs, lens_override_is_the_scene_camera_with_that_lens) {
    ScratchDir dir;
    const Scene with_lens = three_planes(dir, R"(, "f_number": 2.8, "focus_distance": 5)");
    const Scene without = three_planes(dir);
    RenderOptions rs;
    rs.spp = 8;
    RENDER_OR_SKIP(a, with_lens, rs);
    rs.lens = lens_at(without, 5.0, 2.8);
    RENDER_OR_SKIP(b, without, rs);
    EXPECT_EQ(max_diff(a, b, 0, kW), 0.0);
    EXPECT_NEAR(b.metadata.get_float("fNumber").value_or(0), 2.8, 1e-6);
}

TEST(raytrace_outputs, unsampleable_blur_field_is_an_error_not_a_pinhole) {
    ScratchDir dir;
    const Scene scene = three_planes(dir, R"(, "f_number": 2.8, "focus_distance": 5)");
    // 1e308 x a thin lens overflows to +inf blur away from the focus.
    auto field = BlurField::parse(R"({"blurfield": {"kind": "scale", "factor": 1e308, "child":
        {"kind": "thin_lens", "focal_length_mm": 50, "f_number": 2.8, "focus_distance": 5, "sensor_width_mm": 36}}})");
    ASSERT_TRUE(field) << field.message();
    RenderOptions rs;
    rs.spp = 2;
    rs.blur_field = &field.value();
    auto img = render(scene, rs);
    if (!img && img.message().find("without Embree") != std::string::npos) GDOF_SKIP_OR_FAIL(img.message());
    ASSERT_FALSE(img);
    EXPECT_NE(img.message().find("blur field"), std::string::npos) << img.message();
    EXPECT_NE(img.message().find(" px"), std::string::npos) << img.message();
}
