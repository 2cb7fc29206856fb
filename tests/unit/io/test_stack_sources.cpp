// Stacks described by a frame pattern, with each reference's lens from its
// EXR attributes or from a CSV table, expand to the same stack a listed
// manifest gives (near/far from the thin lens for coc_px).
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "gdof/camera.h"
#include "gdof/io/image_io.h"
#include "gdof/io/stack_sources.h"
#include "test_support.h"

using namespace gdof;
using namespace gdof::test;

namespace {

void write_ref(const std::string& path, double focus, double fnum, bool with_lens = true) {
    Image img = Image::with_channels({"R", "G", "B", "A"}, Roi{0, 0, 64, 32});
    if (with_lens) {
        img.metadata.set_float("focusDistance", focus);
        img.metadata.set_float("fNumber", fnum);
        img.metadata.set_float("focalLength", 50);
        img.metadata.set_float("sensorWidth", 36);
    }
    ASSERT_TRUE(io::write_flat(path, img));
}

void write_text(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

ThinLens::DofLimits expected(double focus, double fnum) {
    ThinLens l;
    l.focal_length_mm = 50;
    l.sensor_width_mm = 36;
    l.focus_distance = focus;
    l.f_number = fnum;
    l.image_width_px = 64;
    return l.dof_limits(0.02);  // small enough on 64 px for finite limits
}

}  // namespace

TEST(stack_sources, PatternWithLensesFromAttributes) {
    ScratchDir dir;
    const double focus[] = {1.0, 2.0, 4.0};
    for (int i = 0; i < 3; ++i) write_ref(dir.file("ref.000" + std::to_string(i + 1) + ".exr"), focus[i], 4.0);
    write_text(dir.file("m.json"), R"({"gdof_stack": 1, "coc_px": 0.02, "pattern": "ref.####.exr", "lens_from": "attributes"})");
    auto s = io::load_stack(dir.file("m.json"));
    ASSERT_TRUE(s) << s.message();
    ASSERT_EQ(s->references.size(), 3u);
    EXPECT_EQ(s->width, 64);
    for (int i = 0; i < 3; ++i) {
        const auto lim = expected(focus[i], 4.0);
        EXPECT_EQ(s->references[std::size_t(i)].file, "ref.000" + std::to_string(i + 1) + ".exr");
        EXPECT_NEAR(s->references[std::size_t(i)].near, lim.near, 1e-9 * lim.near);
        ASSERT_TRUE(std::isfinite(lim.far));
        EXPECT_NEAR(s->references[std::size_t(i)].far, lim.far, 1e-9 * lim.far);
    }
}

TEST(stack_sources, PatternWithATable) {
    ScratchDir dir;
    for (int i = 1; i <= 2; ++i) write_ref(dir.file("shot_0" + std::to_string(i) + ".exr"), 0, 0, false);
    write_text(dir.file("lens.csv"), "# focus sweep\nframe, focus_distance, f_number\n1, 0.529, 8.3\n2, 0.869, 8.3\n");
    write_text(dir.file("m.json"), R"({"gdof_stack": 1, "coc_px": 0.02, "pattern": "shot_%02d.exr", "table": "lens.csv",
                                        "focal_length_mm": 50, "sensor_width_mm": 36})");
    auto s = io::load_stack(dir.file("m.json"));
    ASSERT_TRUE(s) << s.message();
    ASSERT_EQ(s->references.size(), 2u);
    EXPECT_EQ(s->references[1].file, "shot_02.exr");
    const auto lim = expected(0.869, 8.3);
    EXPECT_NEAR(s->references[1].near, lim.near, 1e-9);
    EXPECT_NEAR(s->references[1].far, lim.far, 1e-9);
}

TEST(stack_sources, ErrorsNameTheFileLineOrColumn) {
    ScratchDir dir;
    write_ref(dir.file("ref.0001.exr"), 0, 0, false);  // no lens attributes
    write_text(dir.file("a.json"), R"({"pattern": "ref.####.exr", "lens_from": "attributes"})");
    auto r = io::load_stack(dir.file("a.json"));
    ASSERT_FALSE(r);
    EXPECT_NE(r.message().find("ref.0001.exr"), std::string::npos) << r.message();
    EXPECT_NE(r.message().find("focus"), std::string::npos) << r.message();

    write_text(dir.file("t.csv"), "frame,focus_distance,f_number\n1,abc,2\n");
    write_text(dir.file("t.json"), R"({"pattern": "ref.####.exr", "table": "t.csv", "focal_length_mm": 50, "sensor_width_mm": 36})");
    r = io::load_stack(dir.file("t.json"));
    ASSERT_FALSE(r);
    EXPECT_NE(r.message().find("line 2"), std::string::npos) << r.message();
    EXPECT_NE(r.message().find("focus_distance"), std::string::npos) << r.message();

    write_text(dir.file("u.csv"), "frame,focus,f_number\n1,2,2\n");
    write_text(dir.file("u.json"), R"({"pattern": "ref.####.exr", "table": "u.csv"})");
    r = io::load_stack(dir.file("u.json"));
    ASSERT_FALSE(r);
    EXPECT_NE(r.message().find("'focus'"), std::string::npos) << r.message();

    write_text(dir.file("n.json"), R"({"pattern": "nothing.####.exr", "lens_from": "attributes"})");
    r = io::load_stack(dir.file("n.json"));
    ASSERT_FALSE(r);
    EXPECT_NE(r.message().find("nothing.####.exr"), std::string::npos) << r.message();
    EXPECT_FALSE(io::load_stack(dir.file("missing.json")));
}
