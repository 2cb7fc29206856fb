// gdof --render's outputs for the other methods: --deep (method 3's input),
// --stack (method 2's focus/aperture stack, read back by --composite), and
// --aovs selection; their usage errors.
#include <cmath>
#include <cstdio>

#include "cli_test_helpers.h"
#include "gdof/camera.h"
#include "gdof/focal_stack.h"
#include "gdof/io/image_io.h"
#include "../unit/scene_test_helpers.h"

using namespace gdof::test;

namespace {

bool built_without_embree(const CommandResult& r) { return contains(r.output, "without Embree"); }

std::string scene_file(const ScratchDir& dir) {
    write_quad_obj(dir);
    write_text(dir.file("scene.json"), plane_scene_json(R"(, "f_number": 2, "focus_distance": 4)", 40, 30));
    return quote(dir.file("scene.json"));
}

std::vector<std::string> channel_names(const std::string& path) {
    auto set = gdof::io::read_image(path);
    EXPECT_TRUE(set) << set.message();
    std::vector<std::string> names;
    if (!set) return names;
    if (set->is_deep(0))
        for (const auto& c : set->deep(0).channels()) names.push_back(c.name);
    else
        for (const auto& c : set->flat(0).channels()) names.push_back(c.name);
    return names;
}

}  // namespace

TEST(cli_render_outputs, deep_output_is_a_deep_exr_that_diffuse_reads) {
    ScratchDir dir;
    const std::string scene = scene_file(dir);
    auto r = run_gdof("--render " + scene + " --pinhole --deep --spp 8 -o " + quote(dir.file("deep.exr")));
    if (built_without_embree(r)) GDOF_SKIP_OR_FAIL(r.output);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    auto set = gdof::io::read_image(dir.file("deep.exr"));
    ASSERT_TRUE(set) << set.message();
    ASSERT_TRUE(set->is_deep(0));
    EXPECT_GE(set->deep(0).z_channel(), 0);
    EXPECT_GT(set->deep(0).total_samples(), std::size_t(40 * 30 - 1));
    EXPECT_TRUE(set->deep(0).metadata.find("worldToNDC"));
    // Defocused with the scene camera's lens (f/2 focused at 4 on a plane at
    // about 6: under 0.05 px of blur), it is the flat render of the same scene.
    r = run_gdof(quote(dir.file("deep.exr")) + " --diffuse -o " + quote(dir.file("dof.exr")));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    r = run_gdof("--render " + scene + " --pinhole --spp 8 -o " + quote(dir.file("flat.exr")));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const Pixels dof = read_image_pixels(dir.file("dof.exr")), flat = read_image_pixels(dir.file("flat.exr"));
    ASSERT_EQ(dof.spec.width, 40);
    ASSERT_EQ(dof.spec.height, 30);
    ASSERT_EQ(flat.spec.width, 40);
    double worst = 0, peak = 0;
    for (int y = 0; y < 30; ++y)
        for (int x = 0; x < 40; ++x)
            for (int c = 0; c < 4; ++c) {
                worst = std::max(worst, double(std::abs(dof.at(x, y, c) - flat.at(x, y, c))));
                peak = std::max(peak, double(flat.at(x, y, c)));
            }
    std::printf("[ measured ] deep render defocused by the camera lens vs the flat render: worst %.2e of peak %.3f\n",
                worst, peak);
    EXPECT_GT(peak, 0.0);
    EXPECT_LT(worst, 1e-3 * peak) << "measured 8e-4 of a peak of 4 (the lamp)";
}

TEST(cli_render_outputs, aovs_list_picks_channels) {
    ScratchDir dir;
    const std::string scene = scene_file(dir);
    auto r = run_gdof("--render " + scene + " --spp 2 --aovs=Z,id -o " + quote(dir.file("a.exr")));
    if (built_without_embree(r)) GDOF_SKIP_OR_FAIL(r.output);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_EQ(channel_names(dir.file("a.exr")), (std::vector<std::string>{"R", "G", "B", "A", "Z", "id"}));
    r = run_gdof("--render " + scene + " --spp 2 --aovs=none -o " + quote(dir.file("b.exr")));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_EQ(channel_names(dir.file("b.exr")).size(), 4u);
    r = run_gdof("--render " + scene + " --aovs=Z,depth -o " + quote(dir.file("c.exr")));
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_TRUE(contains(r.output, "'depth'")) << r.output;
    EXPECT_FALSE(fs::exists(dir.file("c.exr")));
}

TEST(cli_render_outputs, deep_without_render_is_a_usage_error) {
    ScratchDir dir;
    auto r = run_gdof("--deep --render x.json -o " + quote(dir.file("x.exr")));
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_TRUE(contains(r.output, "--deep")) << r.output;
}

// The stack's manifest gives each reference the thin-lens depth of field,
// and --composite asked for exactly one reference's near/far returns it.
TEST(cli_render_outputs, stack_renders_references_and_a_manifest_composite_reads) {
    ScratchDir dir;
    const std::string scene = scene_file(dir);
    write_text(dir.file("stack.json"), R"({"focus_range": {"near": 3, "far": 8, "count": 3}, "f_numbers": [2, 8],
                                           "coc_px": 0.5})");
    const std::string pattern = dir.file("stack/ref.####.exr");
    auto r = run_gdof("--render " + scene + " --spp 4 --stack " + quote(dir.file("stack.json")) + " -o " + quote(pattern));
    if (built_without_embree(r)) GDOF_SKIP_OR_FAIL(r.output);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const std::string manifest = dir.file("stack/manifest.json");
    auto m = gdof::parse_stack_manifest(read_text(manifest), dir.file("stack"));
    ASSERT_TRUE(m) << m.message();
    ASSERT_EQ(m->references.size(), 6u);
    // Focus distances evenly spaced in 1/distance: 3, 4.36, 8.
    EXPECT_NEAR(m->references[2].focus_distance, 1.0 / (0.5 / 3 + 0.5 / 8), 1e-9);
    for (const auto& ref : m->references) {
        EXPECT_TRUE(fs::exists(ref.path)) << ref.path;
        gdof::ThinLens tl{35, ref.f_number, ref.focus_distance, 36, 40, 1000};
        const auto dof = tl.dof_limits(0.5);
        EXPECT_NEAR(ref.near, dof.near, 1e-9 * dof.near);
        if (std::isfinite(dof.far)) {
            EXPECT_NEAR(ref.far, dof.far, 1e-9 * dof.far);
        }
        auto img = gdof::io::read_image(ref.path);
        ASSERT_TRUE(img) << img.message();
        EXPECT_NEAR(img->flat(0).metadata.get_float("fNumber").value_or(0), ref.f_number, 1e-5);
    }
    // Desired near/far = reference 4's: the composite is reference 4.
    const auto& want = m->references[3];
    write_exr(dir.file("near.exr"), 40, 30, {"near"}, [&](int, int, int) { return float(want.near); });
    write_exr(dir.file("far.exr"), 40, 30, {"far"}, [&](int, int, int) { return float(want.far); });
    r = run_gdof("--composite " + quote(manifest) + " --near-map " + quote(dir.file("near.exr")) + " --far-map " +
                 quote(dir.file("far.exr")) + " -o " + quote(dir.file("comp.exr")));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const auto a = read_pixels(dir.file("comp.exr")), b = read_pixels(want.path);
    ASSERT_FALSE(a.empty());
    OIIO::ImageSpec sa, sb;
    read_pixels(dir.file("comp.exr"), &sa);
    read_pixels(want.path, &sb);
    double maxd = 0;
    for (int i = 0; i < 40 * 30; ++i)
        for (int c = 0; c < 4; ++c) maxd = std::max(maxd, double(std::abs(a[i * sa.nchannels + c] - b[i * sb.nchannels + c])));
    EXPECT_EQ(maxd, 0.0);
}

TEST(cli_render_outputs, bad_stack_spec_writes_nothing) {
    ScratchDir dir;
    const std::string scene = scene_file(dir);
    write_text(dir.file("stack.json"), R"({"focus_distances": [3, 5], "f_numbers": [2, -1]})");
    auto r = run_gdof("--render " + scene + " --stack " + quote(dir.file("stack.json")) + " -o " +
                      quote(dir.file("stack/ref.####.exr")));
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_TRUE(contains(r.output, "f_numbers[1]")) << r.output;
    EXPECT_FALSE(fs::exists(dir.file("stack")));
    // A light-field stack.json given to --render: the unknown key is named.
    write_text(dir.file("lf.json"), R"({"disparities": [0, 1], "apertures": [1]})");
    r = run_gdof("--render " + scene + " --stack " + quote(dir.file("lf.json")) + " -o " + quote(dir.file("s/r.####.exr")));
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_TRUE(contains(r.output, "apertures: unknown key")) << r.output;
    // Without a frame pattern.
    write_text(dir.file("ok.json"), R"({"references": [{"focus_distance": 4, "f_number": 2}]})");
    r = run_gdof("--render " + scene + " --stack " + quote(dir.file("ok.json")) + " -o " + quote(dir.file("one.exr")));
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_TRUE(contains(r.output, "frame pattern")) << r.output;
}
