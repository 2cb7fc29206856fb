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
