// gdof --lightfield PATTERN --lf lf.json --stack stack.json -o stack/ref.####.exr
#include <OpenImageIO/imageio.h>

#include <cmath>

#include "cli_test_helpers.h"
#include "gdof/focal_stack.h"
#include "gdof/io/image_io.h"
#include "test_support.h"

using namespace gdof::test;

namespace {

// 5 x 5 views (file indices 1..5) of a textured square at disparity 1 over a
// background at disparity 0, 8-bit sRGB PNG, in gdof's convention (a point at
// central x appears at x - d * du).
void write_views(const std::string& dir, int w = 40, int h = 30) {
    for (int r = 1; r <= 5; ++r)
        for (int c = 1; c <= 5; ++c) {
            const int du = c - 3, dv = r - 3;
            std::vector<unsigned char> px(std::size_t(w) * std::size_t(h) * 3);
            for (int y = 0; y < h; ++y)
                for (int x = 0; x < w; ++x) {
                    const int X = x + du, Y = y + dv;  // disparity 1
                    const bool square = X >= 10 && X < 30 && Y >= 8 && Y < 22;
                    for (int ch = 0; ch < 3; ++ch) {
                        const int v = square ? 40 + ((X * 7 + Y * 3 + ch * 11) % 9) * 20 : 30 + ((x + 2 * y + ch) % 5) * 40;
                        px[(std::size_t(y) * std::size_t(w) + std::size_t(x)) * 3 + std::size_t(ch)] = (unsigned char)v;
                    }
                }
            char name[64];
            std::snprintf(name, sizeof name, "/v_%02d_%02d.png", r, c);
            const std::string path = dir + name;
            OIIO::ImageSpec spec(w, h, 3, OIIO::TypeDesc::UINT8);
            auto out = OIIO::ImageOutput::create(path);
            ASSERT_TRUE(out && out->open(path, spec));
            ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, px.data()));
            out->close();
        }
}

const char* kLf = R"({"disparity_at_infinity": -0.5, "focal_baseline": 2})";
const char* kStack = R"({"coc_px": 1, "references": [
    {"disparity": 0, "aperture": 0}, {"disparity": 1, "aperture": 2}, {"depth": 4, "aperture": 1}]})";

std::string lightfield_args(const ScratchDir& d, const std::string& out_pattern) {
    return "--lightfield " + quote(d.file("views/v_%02d_%02d.png")) + " --lf " + quote(d.file("lf.json")) +
           " --stack " + quote(d.file("stack.json")) + " -o " + quote(out_pattern);
}

void setup(const ScratchDir& d) {
    fs::create_directories(d.path() / "views");
    write_views((d.path() / "views").string());
    write_text(d.file("lf.json"), kLf);
    write_text(d.file("stack.json"), kStack);
}

}  // namespace

TEST(cli_lightfield, writes_one_image_per_reference_and_the_manifest) {
    ScratchDir d;
    setup(d);
    auto r = run_gdof(lightfield_args(d, d.file("stack/ref.####.exr")) + " --stats");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_TRUE(contains(r.output, "view x pixels")) << r.output;
    EXPECT_EQ(list_dir(d.file("stack")),
              (std::vector<std::string>{"manifest.json", "ref.0001.exr", "ref.0002.exr", "ref.0003.exr"}));

    auto m = gdof::parse_stack_manifest(read_text(d.file("stack/manifest.json")), d.file("stack"));
    ASSERT_TRUE(m) << m.message();
    ASSERT_EQ(m->references.size(), 3u);
    EXPECT_EQ(m->width, 40);
    EXPECT_EQ(m->height, 30);
    const auto& refs = m->references;
    EXPECT_EQ(refs[0].file, "ref.0001.exr");
    EXPECT_EQ(refs[0].path, d.file("stack/ref.0001.exr"));
    // Radius 0: everything in focus.
    EXPECT_EQ(refs[0].near, 0.0);
    EXPECT_TRUE(std::isinf(refs[0].far));
    // d_f = 1, r = 2, c = 1: d in [0.5, 1.5]: near = 2 / 2, far = 2 / 1.
    EXPECT_DOUBLE_EQ(refs[1].near, 1.0);
    EXPECT_DOUBLE_EQ(refs[1].far, 2.0);
    EXPECT_DOUBLE_EQ(refs[1].focus_disparity, 1.0);
    EXPECT_DOUBLE_EQ(refs[1].aperture_radius_views, 2.0);
    EXPECT_DOUBLE_EQ(refs[1].focus_distance, 2.0 / 1.5);
    // Depth 4 -> d_f = 0, r = 1: d in [-1, 1]: near = 2 / 1.5, far = inf.
    EXPECT_DOUBLE_EQ(refs[2].focus_disparity, 0.0);
    EXPECT_DOUBLE_EQ(refs[2].near, 2.0 / 1.5);
    EXPECT_TRUE(std::isinf(refs[2].far));

    // Reference 1 (radius 0) is the central view, linearised.
    OIIO::ImageSpec spec;
    const std::vector<float> ref = read_pixels(d.file("stack/ref.0001.exr"), &spec);
    EXPECT_EQ(spec.width, 40);
    EXPECT_EQ(spec.nchannels, 3);
    auto central = gdof::io::read_flat(d.file("views/v_03_03.png"));
    ASSERT_TRUE(central) << central.message();
    for (int y = 0; y < 30; ++y)
        for (int x = 0; x < 40; ++x)
            for (int c = 0; c < 3; ++c)
                ASSERT_EQ(ref[(std::size_t(y) * 40 + std::size_t(x)) * 3 + std::size_t(c)], central->at(c, x, y));

    // Reference 2 (focused on the square at disparity 1, integer shifts): the
    // square's interior equals the central view exactly.
    const std::vector<float> sq = read_pixels(d.file("stack/ref.0002.exr"));
    for (int y = 11; y < 19; ++y)
        for (int x = 13; x < 27; ++x)
            for (int c = 0; c < 3; ++c)
                ASSERT_NEAR(sq[(std::size_t(y) * 40 + std::size_t(x)) * 3 + std::size_t(c)], central->at(c, x, y), 1e-6)
                    << x << "," << y;
}

TEST(cli_lightfield, missing_view_fails_naming_the_file_and_writes_nothing) {
    ScratchDir d;
    setup(d);
    fs::remove(d.file("views/v_04_02.png"));
    auto r = run_gdof(lightfield_args(d, d.file("stack/ref.####.exr")));
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_TRUE(contains(r.output, d.file("views/v_04_02.png"))) << r.output;
    EXPECT_FALSE(fs::exists(d.file("stack/manifest.json")));
    EXPECT_FALSE(fs::exists(d.file("stack/ref.0001.exr")));
}

TEST(cli_lightfield, mismatched_sizes_and_bad_stacks_fail_before_writing) {
    ScratchDir d;
    setup(d);
    write_text(d.file("stack.json"), R"({"references": [{"disparity": 0, "aperture": 1}, {"depth": 4, "aperture": 1}]})");
    auto dup = run_gdof(lightfield_args(d, d.file("stack/ref.####.exr")));
    EXPECT_EQ(dup.exit_code, 1) << dup.output;
    EXPECT_TRUE(contains(dup.output, "duplicate")) << dup.output;
    EXPECT_FALSE(fs::exists(d.file("stack")));

    write_text(d.file("stack.json"), R"({"references": [{"disparity": 0, "aperture": 1, "f": 2}]})");
    auto key = run_gdof(lightfield_args(d, d.file("stack/ref.####.exr")));
    EXPECT_EQ(key.exit_code, 1) << key.output;
    EXPECT_TRUE(contains(key.output, "references[0].f")) << key.output;

    write_text(d.file("stack.json"), kStack);
    OIIO::ImageSpec spec(41, 30, 3, OIIO::TypeDesc::UINT8);
    std::vector<unsigned char> px(41 * 30 * 3, 100);
    auto out = OIIO::ImageOutput::create(d.file("views/v_02_05.png"));
    ASSERT_TRUE(out && out->open(d.file("views/v_02_05.png"), spec));
    out->write_image(OIIO::TypeDesc::UINT8, px.data());
    out->close();
    auto size = run_gdof(lightfield_args(d, d.file("stack/ref.####.exr")));
    EXPECT_EQ(size.exit_code, 1) << size.output;
    EXPECT_TRUE(contains(size.output, d.file("views/v_02_05.png"))) << size.output;
    EXPECT_TRUE(contains(size.output, "41x30")) << size.output;
    EXPECT_FALSE(fs::exists(d.file("stack")));
}

TEST(cli_lightfield, usage_errors) {
    ScratchDir d;
    setup(d);
    const std::string views = quote(d.file("views/v_%02d_%02d.png"));
    auto no_stack = run_gdof("--lightfield " + views + " -o " + quote(d.file("s/ref.####.exr")));
    EXPECT_EQ(no_stack.exit_code, 2) << no_stack.output;
    EXPECT_TRUE(contains(no_stack.output, "--stack")) << no_stack.output;
    auto no_out = run_gdof("--lightfield " + views + " --stack " + quote(d.file("stack.json")));
    EXPECT_EQ(no_out.exit_code, 2) << no_out.output;
    EXPECT_TRUE(contains(no_out.output, "no -o")) << no_out.output;
    auto no_pattern = run_gdof(lightfield_args(d, d.file("s/ref.exr")));
    EXPECT_EQ(no_pattern.exit_code, 2) << no_pattern.output;
    EXPECT_TRUE(contains(no_pattern.output, "frame pattern")) << no_pattern.output;
    auto stray = run_gdof("--stack " + quote(d.file("stack.json")) + " " + quote(d.file("views/v_03_03.png")) +
                          " -o " + quote(d.file("x.exr")));
    EXPECT_EQ(stray.exit_code, 2) << stray.output;
    EXPECT_TRUE(contains(stray.output, "only used with --lightfield")) << stray.output;
    EXPECT_TRUE(contains(run_gdof("--help").output, "--lightfield"));
}

TEST(cli_lightfield, real_lytro_views) {
    GDOF_REQUIRE_SHARED(dir, "lightfield/lytro_2067");
    ScratchDir d;
    const std::string ex = std::string(GDOF_SOURCE_DIR) + "/examples/lightfield/";
    auto r = run_gdof("--lightfield " + quote(dir + "/2067_%02d_%02d.png") + " --lf " + quote(ex + "lf.json") +
                      " --stack " + quote(ex + "stack.json") + " -o " + quote(d.file("stack/ref.####.exr")));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    auto m = gdof::parse_stack_manifest(read_text(d.file("stack/manifest.json")), d.file("stack"));
    ASSERT_TRUE(m) << m.message();
    EXPECT_GE(m->references.size(), 4u);
    EXPECT_EQ(m->width, 552);
    EXPECT_EQ(m->height, 383);
    for (const auto& ref : m->references) EXPECT_TRUE(fs::exists(ref.path)) << ref.path;
}
