// The bundled example scene: its passes are exact ground truth, so P must
// project back through the camera written in its own metadata to the pixel
// centre with depth Z; the deep file's samples must be sorted and flatten to
// full coverage; the quickstart's blur field is sharp at its focal depths.
#include <cmath>

#include "gdof/blur_field.h"
#include "gdof/camera.h"
#include "gdof/io/image_io.h"
#include "test_support.h"

using namespace gdof;
using namespace gdof::test;

namespace {
CommandResult make_scene(const ScratchDir& dir) {
    return run_command(std::string("'") + GDOF_EXAMPLE_SCENE_PATH + "' --size 160x90 --subsamples 2 -o " +
                       quote(dir.file("scene.exr")) + " --deep " + quote(dir.file("deep.exr")));
}
}  // namespace

TEST(example_scene, PositionsProjectToTheirPixelsThroughTheFileCamera) {
    ScratchDir dir;
    auto r = make_scene(dir);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    auto img = io::read_flat(dir.file("scene.exr"));
    ASSERT_TRUE(img) << img.message();
    auto cam = Camera::from_image(*img);
    ASSERT_TRUE(cam) << cam.message();
    const int z = img->channel_index("Z"), px = img->channel_index("P.x");
    ASSERT_GE(z, 0);
    ASSERT_GE(px, 0);
    EXPECT_EQ(img->channel(img->channel_index("id")).type, PixelType::UInt);
    double worst = 0;
    for (int y = 0; y < 90; y += 3)
        for (int x = 0; x < 160; x += 3) {
            Vec3 p{img->at(px, x, y), img->at(px + 1, x, y), img->at(px + 2, x, y)};
            PixelDepth pd = cam->project(p);
            worst = std::max(worst, std::abs(pd.x - (x + 0.5)) + std::abs(pd.y - (y + 0.5)));
            EXPECT_NEAR(pd.depth, img->at(z, x, y), 1e-4 * img->at(z, x, y)) << x << "," << y;
        }
    EXPECT_LT(worst, 2e-3) << "P and the camera metadata disagree by " << worst << " px";
}

TEST(example_scene, DeepSamplesAreSortedAndCoverEveryPixel) {
    ScratchDir dir;
    auto r = make_scene(dir);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    auto set = io::read_image(dir.file("deep.exr"));
    ASSERT_TRUE(set) << set.message();
    ASSERT_TRUE(set->is_deep(0));
    const DeepImage& d = set->deep(0);
    const int a = d.channel_index("A"), zc = d.z_channel();
    ASSERT_GE(a, 0);
    ASSERT_GE(zc, 0);
    std::size_t multi = 0;
    for (std::size_t p = 0; p < d.npixels(); ++p) {
        ASSERT_GE(d.sample_count(p), 1u);
        double coverage = 0;
        for (std::size_t k = d.first_sample(p); k < d.first_sample(p) + d.sample_count(p); ++k) {
            coverage += d.samples(a)[k];
            if (k > d.first_sample(p)) {
                ASSERT_LE(d.samples(zc)[k - 1], d.samples(zc)[k]);
            }
        }
        EXPECT_NEAR(coverage, 1.0, 2e-3);  // half alpha, coverage fractions add to 1
        multi += d.sample_count(p) > 1;
    }
    EXPECT_GT(multi, 100u) << "edges should produce pixels with several samples";
}

TEST(example_scene, QuickstartBlurFieldIsSharpAtItsFocalDepths) {
    ScratchDir dir;
    auto r = make_scene(dir);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const std::string field = std::string(GDOF_SOURCE_DIR) + "/examples/scene/two_planes.json";
    r = run_gdof(quote(dir.file("scene.exr")) + " --blurfield " + quote(field) + " --eval-blur -o " +
                 quote(dir.file("blur.exr")));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    auto img = io::read_flat(dir.file("blur.exr"));
    ASSERT_TRUE(img) << img.message();
    const int b = img->channel_index("blur"), z = img->channel_index("Z");
    ASSERT_GE(b, 0);
    int near_focus = 0, far_from_focus = 0;
    for (int y = 0; y < 90; ++y)
        for (int x = 0; x < 160; ++x) {
            float depth = img->at(z, x, y), blur = img->at(b, x, y);
            ASSERT_TRUE(std::isfinite(blur));
            if (std::abs(depth - 2.9f) < 0.01f || std::abs(depth - 12.6f) < 0.01f) {
                EXPECT_LT(blur, 0.01f) << x << "," << y;
                ++near_focus;
            }
            if (depth > 6.0f && depth < 10.0f) {
                EXPECT_NEAR(blur, 10.0f, 0.5f) << "depth " << depth;
                ++far_from_focus;
            }
        }
    EXPECT_GT(near_focus, 0);
    EXPECT_GT(far_from_focus, 0);
}
