// gdof CLI: outputs are all-or-nothing. A failed write or a failing
// operation after loading leaves no output and no temporary file, and an
// existing output is left untouched.
#include "cli/cli_test_helpers.h"

using namespace gdof::test;

namespace {

void write_rgb(const std::string& path) {
    write_exr(path, 8, 8, {"R", "G", "B"}, [](int x, int y, int c) { return float(x * y + c); });
}

}  // namespace

TEST(cli_atomic, MissingOutputFolderLeavesNothing) {
    ScratchDir dir;
    write_rgb(dir.file("in.exr"));
    const std::string out = dir.file("no_such_folder/out.exr");
    auto r = run_gdof(quote(dir.file("in.exr")) + " -o " + quote(out));
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_TRUE(contains(r.output, "out.exr")) << r.output;
    EXPECT_FALSE(fs::exists(out));
    EXPECT_FALSE(fs::exists(dir.file("no_such_folder")));
    EXPECT_EQ(list_dir(dir.path().string()), std::vector<std::string>{"in.exr"});
}

TEST(cli_atomic, FailingOperationAfterLoadLeavesNoOutput) {
    ScratchDir dir;
    write_rgb(dir.file("in.exr"));
    const std::string out = dir.file("out.exr");
    // The blur field does not exist: fails after the input is loaded, before -o.
    auto r = run_gdof(quote(dir.file("in.exr")) + " --blurfield " + quote(dir.file("missing.json")) +
                      " --eval-blur -o " + quote(out));
    EXPECT_NE(r.exit_code, 0) << r.output;
    EXPECT_TRUE(contains(r.output, "missing.json")) << r.output;
    EXPECT_FALSE(fs::exists(out));
    EXPECT_EQ(list_dir(dir.path().string()), std::vector<std::string>{"in.exr"});
}

TEST(cli_atomic, ExistingOutputUntouchedOnFailure) {
    ScratchDir dir;
    write_rgb(dir.file("in.exr"));
    const std::string out = dir.file("out.exr");
    write_text(out, "previous good output");
    // An unknown colour space fails the run before anything is written.
    auto r = run_gdof(quote(dir.file("in.exr")) + " --colorconvert linear NoSuchSpace -o " + quote(out));
    EXPECT_NE(r.exit_code, 0) << r.output;
    EXPECT_TRUE(contains(r.output, "NoSuchSpace")) << r.output;
    EXPECT_EQ(read_text(out), "previous good output");

    // A read failure of a second input (after the first has loaded).
    r = run_gdof(quote(dir.file("in.exr")) + " " + quote(dir.file("gone.exr")) + " -o " + quote(out));
    EXPECT_NE(r.exit_code, 0) << r.output;
    EXPECT_TRUE(contains(r.output, "gone.exr")) << r.output;
    EXPECT_EQ(read_text(out), "previous good output");
    EXPECT_EQ(list_dir(dir.path().string()), (std::vector<std::string>{"in.exr", "out.exr"}));
}

TEST(cli_atomic, OutputIsADirectoryFailsCleanly) {
    ScratchDir dir;
    write_rgb(dir.file("in.exr"));
    fs::create_directories(dir.file("taken.exr"));
    auto r = run_gdof(quote(dir.file("in.exr")) + " -o " + quote(dir.file("taken.exr")));
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_TRUE(contains(r.output, "taken.exr")) << r.output;
    EXPECT_TRUE(fs::is_directory(dir.file("taken.exr")));
    EXPECT_EQ(list_dir(dir.path().string()), (std::vector<std::string>{"in.exr", "taken.exr"}));
    EXPECT_TRUE(list_dir(dir.file("taken.exr")).empty());
}

TEST(cli_atomic, OverwritingSucceedsAndReplacesWholeFile) {
    ScratchDir dir;
    write_rgb(dir.file("in.exr"));
    const std::string out = dir.file("out.exr");
    write_text(out, "old");
    auto r = run_gdof(quote(dir.file("in.exr")) + " -o " + quote(out));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    OIIO::ImageSpec s;
    auto px = read_pixels(out, &s);
    EXPECT_EQ(s.width, 8);
    EXPECT_EQ(list_dir(dir.path().string()), (std::vector<std::string>{"in.exr", "out.exr"}));
}
