// Rendering: exact Z and P in a pinhole render, thread-count determinism (of
// the image and of the error), pinhole == zero blur field, straight thin lens
// ~ polyline thin lens, adaptive sampling, cancellation.
#include <atomic>
#include <cmath>
#include <cstring>

#include "gdof/raytrace.h"
#include "scene_test_helpers.h"

using namespace gdof;
using gdof::test::ScratchDir;

namespace {

Scene load(const ScratchDir& dir, const std::string& extra_camera = "", int w = 32, int h = 24) {
    gdof::test::write_quad_obj(dir);
    auto r = parse_scene(gdof::test::plane_scene_json(extra_camera, w, h), dir.path().string());
    EXPECT_TRUE(r) << r.message();
    return r ? std::move(r).value() : Scene{};
}

#define RENDER_OR_SKIP(var, scene, settings, stats, exec)                                   \
    auto var##_r = render(scene, settings, stats, exec);                                    \
    if (!var##_r && var##_r.message().find("without Embree") != std::string::npos)          \
        GDOF_SKIP_OR_FAIL(var##_r.message());                                                   \
    ASSERT_TRUE(var##_r) << var##_r.message();                                               \
    const Image& var = var##_r.value()

bool planes_identical(const Image& a, const Image& b) {
    if (a.nchannels() != b.nchannels() || a.data_window() != b.data_window()) return false;
    for (int c = 0; c < a.nchannels(); ++c) {
        const std::size_t bytes = a.npixels() * 4;
        const void* pa = a.plane(c) ? static_cast<const void*>(a.plane(c)) : a.uplane(c);
        const void* pb = b.plane(c) ? static_cast<const void*>(b.plane(c)) : b.uplane(c);
        if (std::memcmp(pa, pb, bytes) != 0) return false;
    }
    return true;
}

double mean_channel(const Image& img, const char* name) {
    const int c = img.channel_index(name);
    double s = 0;
    for (std::size_t i = 0; i < img.npixels(); ++i) s += img.plane(c)[i];
    return s / double(img.npixels());
}

}  // namespace

TEST(raytrace_render, pinhole_z_and_p_are_exact) {
    ScratchDir dir;
    const Scene scene = load(dir);
    RenderOptions rs;
    rs.pinhole = true;
    rs.spp = 1;
    rs.min_spp = 1;
    RenderStats stats;
    RENDER_OR_SKIP(img, scene, rs, &stats, Exec{});
    ASSERT_EQ(img.width(), 32);
    ASSERT_EQ(img.height(), 24);
    const int cz = img.channel_index("Z"), cpx = img.channel_index("P.x"), cpy = img.channel_index("P.y"),
              cpz = img.channel_index("P.z"), ca = img.channel_index("A"), cid = img.channel_index("id");
    ASSERT_GE(cid, 0);
    EXPECT_EQ(img.channel(cid).type, PixelType::UInt);
    for (const char* n : {"R", "G", "B", "albedo.R", "albedo.G", "albedo.B", "N.x", "N.y", "N.z"})
        EXPECT_GE(img.channel_index(n), 0) << n;
    int checked = 0;
    for (int y = 0; y < 24; ++y)
        for (int x = 0; x < 32; ++x) {
            ASSERT_EQ(img.at(ca, x, y), 1.0f);
            const Vec3 p{img.at(cpx, x, y), img.at(cpy, x, y), img.at(cpz, x, y)};
            const PixelDepth pd = scene.camera.project(p);
            EXPECT_NEAR(pd.x, x + 0.5, 2e-3) << x << "," << y;
            EXPECT_NEAR(pd.y, y + 0.5, 2e-3) << x << "," << y;
            EXPECT_NEAR(img.at(cz, x, y), pd.depth, 1e-5 * pd.depth);
            // The plane fills the view (object 1); the small lamp (object 2) is at z = 2.
            const std::uint32_t id = img.uplane(cid)[img.offset(x, y)];
            EXPECT_NEAR(p.z, id == 2 ? 2.0 : -1.0, 1e-5);
            EXPECT_TRUE(id == 1 || id == 2) << id;
            ++checked;
        }
    EXPECT_EQ(checked, 32 * 24);
    EXPECT_EQ(stats.primary_rays, 32u * 24u);
    EXPECT_EQ(stats.segments, 32u * 24u);
    EXPECT_TRUE(img.metadata.has("worldToCamera"));
    EXPECT_TRUE(img.metadata.has("worldToNDC"));
    // Lit by the point light (and the environment): not black.
    EXPECT_GT(mean_channel(img, "R"), 0.01);
}

TEST(raytrace_render, same_image_for_any_thread_count_and_tiling) {
    ScratchDir dir;
    const Scene scene = load(dir, R"(, "f_number": 1.4, "focus_distance": 3)", 48, 32);
    RenderOptions rs;
    rs.spp = 8;
    rs.min_spp = 2;
    Exec one;
    one.nthreads = 1;
    RENDER_OR_SKIP(a, scene, rs, nullptr, one);
    Exec many;
    many.nthreads = 4;
    rs.tile_size = 5;
    RENDER_OR_SKIP(b, scene, rs, nullptr, many);
    EXPECT_TRUE(planes_identical(a, b));
}

TEST(raytrace_render, zero_blur_field_equals_pinhole_bit_for_bit) {
    ScratchDir dir;
    const Scene scene = load(dir);
    RenderOptions rs;
    rs.spp = 4;
    rs.pinhole = true;
    RENDER_OR_SKIP(pin, scene, rs, nullptr, Exec{});
    const BlurField zero;
    rs.pinhole = false;
    rs.blur_field = &zero;
    RENDER_OR_SKIP(field, scene, rs, nullptr, Exec{});
    EXPECT_TRUE(planes_identical(pin, field));
}

TEST(raytrace_render, straight_thin_lens_matches_polyline_thin_lens) {
    ScratchDir dir;
    const Scene scene = load(dir, R"(, "f_number": 1.0, "focus_distance": 3)", 48, 32);
    RenderOptions rs;
    rs.spp = 64;
    rs.adaptive_threshold = 0;
    RenderStats s1, s2;
    RENDER_OR_SKIP(poly, scene, rs, &s1, Exec{});
    rs.straight_thin_lens = true;
    RENDER_OR_SKIP(straight, scene, rs, &s2, Exec{});
    EXPECT_NE(s1.camera, s2.camera);
    // Same aperture samples: depth (a smooth plane) agrees closely pixel by pixel.
    const int cz = poly.channel_index("Z");
    double max_rel = 0;
    for (std::size_t i = 0; i < poly.npixels(); ++i)
        max_rel = std::max(max_rel, std::abs(double(poly.plane(cz)[i]) - straight.plane(cz)[i]) / straight.plane(cz)[i]);
    EXPECT_LT(max_rel, 1e-3);
    EXPECT_NEAR(mean_channel(poly, "R"), mean_channel(straight, "R"), 0.02 * mean_channel(straight, "R"));
}

TEST(raytrace_render, adaptive_sampling_saves_rays) {
    ScratchDir dir;
    const Scene scene = load(dir, "", 48, 32);
    RenderOptions rs;
    rs.pinhole = true;
    rs.spp = 64;
    rs.min_spp = 4;
    rs.adaptive_threshold = 0.02;
    RenderStats adaptive, fixed;
    RENDER_OR_SKIP(a, scene, rs, &adaptive, Exec{});
    rs.adaptive_threshold = 0;
    RENDER_OR_SKIP(f, scene, rs, &fixed, Exec{});
    EXPECT_EQ(fixed.primary_rays, fixed.sample_cap);
    EXPECT_LT(adaptive.primary_rays, fixed.primary_rays);
    EXPECT_GT(adaptive.adaptive_savings(), 0.0);
    EXPECT_NEAR(mean_channel(a, "R"), mean_channel(f, "R"), 0.05 * mean_channel(f, "R"));
    RecordProperty("adaptive_savings", std::to_string(adaptive.adaptive_savings()));
}

TEST(raytrace_render, bad_settings) {
    ScratchDir dir;
    const Scene scene = load(dir);
    RenderOptions rs;
    rs.spp = 0;
    auto r = render(scene, rs);
    ASSERT_FALSE(r);
    EXPECT_TRUE(r.message().find("spp") != std::string::npos || r.message().find("without Embree") != std::string::npos)
        << r.message();
}

TEST(raytrace_render, failing_pixels_give_the_same_error_for_any_thread_count) {
    ScratchDir dir;
    const Scene scene = load(dir, "", 48, 32);
    // Rays crossing the box get a cone over 1e20 scene units: an error on
    // several tiles of the upper right.
    auto field = BlurField::parse(R"({"blurfield": {"kind": "region", "shape": "box", "min": [0.5, 0.5, 0],
        "max": [3, 3, 1], "mode": "blur", "blur": 1e30}})");
    ASSERT_TRUE(field) << field.message();
    RenderOptions rs;
    rs.spp = 2;
    rs.tile_size = 4;
    rs.blur_field = &field.value();
    Exec one;
    one.nthreads = 1;
    auto first = render(scene, rs, nullptr, one);
    if (!first && first.message().find("without Embree") != std::string::npos) GDOF_SKIP_OR_FAIL(first.message());
    ASSERT_FALSE(first);
    EXPECT_NE(first.message().find("blur field at pixel ("), std::string::npos) << first.message();
    Exec many;
    many.nthreads = 4;
    for (int run = 0; run < 3; ++run) {
        auto r = render(scene, rs, nullptr, many);
        ASSERT_FALSE(r);
        EXPECT_EQ(r.message(), first.message());
    }
}

TEST(raytrace_render, cancelling_stops_the_render) {
    ScratchDir dir;
    const Scene scene = load(dir, "", 48, 32);
    RenderOptions rs;
    rs.spp = 2;
    rs.tile_size = 4;
    std::atomic<int> polls{0};
    std::atomic<double> progress{0};
    Exec exec;
    exec.nthreads = 2;
    exec.cancelled = [&] { return ++polls > 10; };  // after a few tiles
    exec.progress = [&](double f) { progress = f; };
    auto r = render(scene, rs, nullptr, exec);
    if (!r && r.message().find("without Embree") != std::string::npos) GDOF_SKIP_OR_FAIL(r.message());
    ASSERT_FALSE(r);
    EXPECT_EQ(r.status().code(), StatusCode::Cancelled);
    EXPECT_EQ(r.message(), "render cancelled");
    EXPECT_LT(progress.load(), 1.0);  // 96 tiles, stopped after about 10
}
