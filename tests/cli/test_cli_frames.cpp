// gdof CLI: frame sequences (--frames, ####, %04d, @, frames on disk).
#include <cstdio>

#include "cli/cli_test_helpers.h"

using namespace gdof::test;

namespace {

std::string frame_name(const ScratchDir& dir, const std::string& stem, int frame) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%s.%04d.exr", stem.c_str(), frame);
    return dir.file(buf);
}

void write_frames(const ScratchDir& dir, const std::vector<int>& frames) {
    for (int f : frames)
        write_exr(frame_name(dir, "in", f), 4, 3, {"R", "G", "B"}, [f](int x, int y, int c) {
            return float(f) + 0.01f * float(x + 4 * y) + 0.001f * float(c);
        });
}

float first_value(const std::string& path) {
    auto px = read_pixels(path);
    return px.empty() ? -1.f : px[0];
}

}  // namespace

TEST(cli_frames, FramesRangeProducesOneOutputPerFrame) {
    ScratchDir dir;
    write_frames(dir, {1, 2, 3});
    auto r = run_gdof("--frames 1-3 " + quote(dir.file("in.####.exr")) + " -o " + quote(dir.file("out.####.exr")));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    for (int f = 1; f <= 3; ++f) {
        ASSERT_TRUE(fs::exists(frame_name(dir, "out", f))) << f;
        EXPECT_FLOAT_EQ(first_value(frame_name(dir, "out", f)), float(f));
    }
}

TEST(cli_frames, StepAndPrintfPattern) {
    ScratchDir dir;
    write_frames(dir, {1, 2, 3, 4, 5});
    auto r = run_gdof("--frames 1-5x2 " + quote(dir.file("in.%04d.exr")) + " -o " + quote(dir.file("out.%04d.exr")));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_FALSE(fs::exists(frame_name(dir, "out", 2)));
    EXPECT_FALSE(fs::exists(frame_name(dir, "out", 4)));
    for (int f : {1, 3, 5}) EXPECT_FLOAT_EQ(first_value(frame_name(dir, "out", f)), float(f)) << f;
}

TEST(cli_frames, WithoutFramesAPatternUsesTheFramesOnDisk) {
    ScratchDir dir;
    write_frames(dir, {10, 12, 13});
    auto r = run_gdof(quote(dir.file("in.####.exr")) + " -o " + quote(dir.file("out.####.exr")));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_FALSE(fs::exists(frame_name(dir, "out", 11)));
    for (int f : {10, 12, 13}) EXPECT_FLOAT_EQ(first_value(frame_name(dir, "out", f)), float(f)) << f;
}

TEST(cli_frames, FailingFrameNamesItsFileAndEarlierFramesStay) {
    ScratchDir dir;
    write_frames(dir, {1, 3});  // frame 2 is missing
    auto r = run_gdof("--frames 1-3 " + quote(dir.file("in.####.exr")) + " -o " + quote(dir.file("out.####.exr")));
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_TRUE(contains(r.output, "in.0002.exr")) << r.output;
    EXPECT_TRUE(fs::exists(frame_name(dir, "out", 1)));
    EXPECT_FLOAT_EQ(first_value(frame_name(dir, "out", 1)), 1.f);
    EXPECT_FALSE(fs::exists(frame_name(dir, "out", 2)));
    EXPECT_FALSE(fs::exists(frame_name(dir, "out", 3)));  // stops at the first failure
    // Only inputs and the one good output: no temporary files.
    EXPECT_EQ(list_dir(dir.path().string()),
              (std::vector<std::string>{"in.0001.exr", "in.0003.exr", "out.0001.exr"}));
}

TEST(cli_frames, SkipBadFramesGoesOn) {
    ScratchDir dir;
    write_frames(dir, {1, 3});
    auto r = run_gdof("--skip-bad-frames --frames 1-3 " + quote(dir.file("in.####.exr")) + " -o " +
                      quote(dir.file("out.####.exr")));
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_TRUE(contains(r.output, "in.0002.exr")) << r.output;
    EXPECT_TRUE(contains(r.output, "1 of 3 frames failed")) << r.output;
    EXPECT_FLOAT_EQ(first_value(frame_name(dir, "out", 1)), 1.f);
    EXPECT_FALSE(fs::exists(frame_name(dir, "out", 2)));
    EXPECT_FLOAT_EQ(first_value(frame_name(dir, "out", 3)), 3.f);
}

TEST(cli_frames, ProgressShowsFrameCounter) {
    ScratchDir dir;
    write_frames(dir, {1, 2});
    auto r = run_gdof("--progress --frames 1-2 " + quote(dir.file("in.####.exr")) + " -o " +
                      quote(dir.file("out.####.exr")));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_TRUE(contains(r.output, "gdof: progress frame 1 (1/2) done 100%")) << r.output;
    EXPECT_TRUE(contains(r.output, "gdof: progress frame 2 (2/2) done 100%")) << r.output;
}

TEST(cli_frames, BadFrameRangeIsUsageError) {
    ScratchDir dir;
    auto r = run_gdof("--frames 1-x " + quote(dir.file("in.####.exr")) + " -o " + quote(dir.file("out.####.exr")));
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_TRUE(contains(r.output, "--frames")) << r.output;
}

TEST(cli_frames, OutputPatternWithoutFramesIsAnError) {
    ScratchDir dir;
    write_exr(dir.file("single.exr"), 2, 2, {"R", "G", "B"}, [](int, int, int) { return 1.f; });
    auto r = run_gdof(quote(dir.file("single.exr")) + " -o " + quote(dir.file("out.####.exr")));
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_TRUE(contains(r.output, "out.####.exr")) << r.output;
    EXPECT_EQ(list_dir(dir.path().string()), std::vector<std::string>{"single.exr"});
}

TEST(cli_frames, NoFramesOnDiskIsAnError) {
    ScratchDir dir;
    auto r = run_gdof(quote(dir.file("none.####.exr")) + " -o " + quote(dir.file("out.####.exr")));
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_TRUE(contains(r.output, "none.####.exr")) << r.output;
}

TEST(cli_frames, LensTablePullsFocusFrameByFrame) {
    // A plate (a red bar at depth 2 over a wall at 5) over three frames, the
    // lens from a table with rows at frames 1 and 3: each frame equals a
    // single run with that frame's lens given as flags, frame 2 the rows
    // interpolated (focus in 1/distance: 1 / ((1/2 + 1/4) / 2), f-number
    // linearly: 1.5). A lens flag after the table replaces its column.
    ScratchDir dir;
    for (int f = 1; f <= 3; ++f)
        write_exr(frame_name(dir, "in", f), 48, 32, {"R", "G", "B", "A", "Z"}, [](int x, int y, int c) {
            const bool bar = x >= 14 && x < 22;
            if (c == 4) return bar ? 2.0f : 5.0f;
            if (c == 3) return 1.0f;
            return bar ? (c == 0 ? 1.0f : 0.0f) : 0.2f + 0.1f * float((x / 3 + y / 3 + c) % 3);
        });
    write_text(dir.file("lens.csv"), "# a focus pull\nframe,focus_distance,f_number\n3,4,2\n1,2,1\n");
    const std::string cam = " --focal-length-mm 35 --sensor-width-mm 36 ";
    auto r = run_gdof("--frames 1-3 " + quote(dir.file("in.####.exr")) + cam + "--lens-table " +
                      quote(dir.file("lens.csv")) + " --diffuse -o " + quote(dir.file("out.####.exr")));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    char mid[64];
    std::snprintf(mid, sizeof mid, "%.17g", 1.0 / ((0.5 + 0.25) / 2.0));
    const std::pair<int, std::string> lens[] = {{1, "--focus-distance 2 --f-number 1"},
                                                {2, std::string("--focus-distance ") + mid + " --f-number 1.5"},
                                                {3, "--focus-distance 4 --f-number 2"}};
    std::vector<float> first;
    for (const auto& [f, flags] : lens) {
        const std::string ref = dir.file("ref" + std::to_string(f) + ".exr");
        auto one = run_gdof(quote(frame_name(dir, "in", f)) + cam + flags + " --diffuse -o " + quote(ref));
        ASSERT_EQ(one.exit_code, 0) << one.output;
        const std::vector<float> got = read_pixels(frame_name(dir, "out", f)), want = read_pixels(ref);
        ASSERT_EQ(got.size(), want.size());
        EXPECT_TRUE(got == want) << "frame " << f << ": " << flags;
        if (f == 1) first = got;
        else EXPECT_FALSE(got == first) << "frame " << f << " did not change the lens";
    }
    auto later = run_gdof("--frames 2 " + quote(dir.file("in.####.exr")) + cam + "--lens-table " +
                          quote(dir.file("lens.csv")) + " --f-number 8 --diffuse -o " + quote(dir.file("f8.####.exr")));
    ASSERT_EQ(later.exit_code, 0) << later.output;
    auto f8 = run_gdof(quote(frame_name(dir, "in", 2)) + cam + "--focus-distance " + mid + " --f-number 8 --diffuse -o " +
                       quote(dir.file("f8.exr")));
    ASSERT_EQ(f8.exit_code, 0) << f8.output;
    EXPECT_TRUE(read_pixels(frame_name(dir, "f8", 2)) == read_pixels(dir.file("f8.exr")));
    // A bad cell stops the run before any frame, naming the line and column;
    // without a sequence the table has no frame to read.
    write_text(dir.file("bad.csv"), "frame,focus_distance\n1,2\n3,far\n");
    auto bad = run_gdof("--frames 1-3 " + quote(dir.file("in.####.exr")) + cam + "--f-number 2 --lens-table " +
                        quote(dir.file("bad.csv")) + " --diffuse -o " + quote(dir.file("bad.####.exr")));
    EXPECT_EQ(bad.exit_code, 1);
    EXPECT_TRUE(contains(bad.output, "line 3 column 'focus_distance'")) << bad.output;
    EXPECT_FALSE(fs::exists(frame_name(dir, "bad", 1)));
    auto single = run_gdof(quote(frame_name(dir, "in", 1)) + cam + "--lens-table " + quote(dir.file("lens.csv")) +
                           " --diffuse -o " + quote(dir.file("s.exr")));
    EXPECT_EQ(single.exit_code, 2);
    EXPECT_TRUE(contains(single.output, "needs a sequence")) << single.output;
    EXPECT_FALSE(fs::exists(dir.file("s.exr")));
}
