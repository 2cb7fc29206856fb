// The thin-lens camera images an edge off the focal plane with the blur of
// the thin-lens CoC formula; an edge on the focal plane stays as sharp as
// with a pinhole.
#include <cmath>

#include "gdof/raytrace.h"
#include "scene_test_helpers.h"

using namespace gdof;
using gdof::test::ScratchDir;

namespace {

// Camera at the origin looking down -z (85 mm, f/1.4, focused at 4);
// an emissive half-plane x >= 0 at depth `depth`.
Scene edge_scene(const ScratchDir& dir, double depth) {
    gdof::test::write_quad_obj(dir);
    const std::string json = R"({
      "camera": {"position": [0, 0, 0], "look_at": [0, 0, -1], "focal_length_mm": 85, "sensor_width_mm": 36,
                 "resolution": [640, 6], "f_number": 1.4, "focus_distance": 4},
      "meshes": [{"file": "quad.obj", "scale": [5, 5, 1], "translate": [5, 0, )" +
                             std::to_string(-depth) + R"(], "material": {"kd": 0, "ke": 1}}]})";
    auto r = parse_scene(json, dir.path().string());
    EXPECT_TRUE(r) << r.message();
    return r ? std::move(r).value() : Scene{};
}

// Blur radius from the edge's alpha profile: the derivative of the profile is
// the disc's line spread function, whose variance is R^2 / 4.
double edge_radius(const Image& img) {
    const int ca = img.channel_index("A");
    double radius_sum = 0;
    for (int y = 0; y < img.height(); ++y) {
        double m0 = 0, m1 = 0, m2 = 0;
        for (int x = 0; x + 1 < img.width(); ++x) {
            const double d = double(img.at(ca, x + 1, y)) - img.at(ca, x, y);
            const double c = x + 1.0;
            m0 += d, m1 += d * c, m2 += d * c * c;
        }
        const double mean = m1 / m0, var = m2 / m0 - mean * mean;
        radius_sum += 2.0 * std::sqrt(std::max(0.0, var));
    }
    return radius_sum / img.height();
}

}  // namespace

TEST(raytrace_coc, edge_blur_matches_thin_lens_coc) {
    ScratchDir dir;
    for (double depth : {2.0, 8.0}) {
        const Scene scene = edge_scene(dir, depth);
        RenderOptions rs;
        rs.spp = 256;
        rs.adaptive_threshold = 0;
        rs.pixel_jitter = false;
        auto img = render(scene, rs);
        if (!img && img.message().find("without Embree") != std::string::npos) GDOF_SKIP_OR_FAIL(img.message());
        ASSERT_TRUE(img) << img.message();
        ThinLens lens{85, 1.4, 4.0, 36, 640, 1000};
        const double want = lens.coc_radius_px(depth);
        const double got = edge_radius(img.value());
        EXPECT_NEAR(got, want, 1.0) << "depth " << depth;
        RecordProperty("coc_depth_" + std::to_string(int(depth)), std::to_string(got) + " vs " + std::to_string(want));
        // The straight-ray thin lens gives the same blur.
        rs.straight_thin_lens = true;
        auto img2 = render(scene, rs);
        ASSERT_TRUE(img2) << img2.message();
        EXPECT_NEAR(edge_radius(img2.value()), want, 1.0) << "straight, depth " << depth;
    }
}

TEST(raytrace_coc, focal_plane_is_as_sharp_as_pinhole) {
    ScratchDir dir;
    const Scene scene = edge_scene(dir, 4.0);
    RenderOptions rs;
    rs.spp = 64;
    rs.adaptive_threshold = 0;
    rs.pixel_jitter = false;
    auto lens = render(scene, rs);
    if (!lens && lens.message().find("without Embree") != std::string::npos) GDOF_SKIP_OR_FAIL(lens.message());
    ASSERT_TRUE(lens) << lens.message();
    rs.pinhole = true;
    auto pin = render(scene, rs);
    ASSERT_TRUE(pin) << pin.message();
    const int ca = lens->channel_index("A");
    int differing = 0;
    for (std::size_t i = 0; i < lens->npixels(); ++i)
        differing += std::abs(lens->plane(ca)[i] - pin->plane(ca)[i]) > 0.02f ? 1 : 0;
    EXPECT_LE(differing, lens->height());  // at most the edge pixel of each row
}
