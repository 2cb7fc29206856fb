// gdof CLI under injected faults (docs/reliability.md, "Fault injection"): a
// full disk, a file-size limit, an unwritable folder, a folder removed during
// the work, an input truncated while it is read, kill -9 during a write. In
// every case the target keeps its old content (or stays absent), no temporary
// file is left after a clean error, and the message names the file and the
// cause.
#include "cli/cli_test_helpers.h"
#include "fault_support.h"

using namespace gdof::test;

namespace {

// A float RGBA image of w x h, different in every pixel (compresses badly).
void write_noise(const std::string& path, int w, int h, const std::string& compression = "none") {
    write_exr(path, w, h, {"R", "G", "B", "A"},
              [](int x, int y, int c) { return float((x * 7919 + y * 104729 + c * 31) % 65521) / 65521.f; },
              [&](OIIO::ImageSpec& s) { s.attribute("compression", compression); });
}

std::string gdof_path() { return GDOF_CLI_PATH; }

}  // namespace

TEST(cli_faults, FullDiskKeepsOldFrameAndNamesTheCause) {
    ScratchDir dir;
    SmallTmpfs disk(dir.file("disk"), 1 << 20);
    if (!disk.mounted()) GTEST_SKIP() << disk.why() << "; the file-size-limit test covers the same path";
    write_noise(dir.file("in.exr"), 512, 512);  // 4 MB of float RGBA, uncompressed
    const std::string out = dir.file("disk/out.exr");
    write_text(out, "old frame");
    auto r = run_gdof(quote(dir.file("in.exr")) + " --compression none -o " + quote(out));
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_TRUE(contains(r.output, "out.exr")) << r.output;
    EXPECT_TRUE(contains(r.output, "No space left on device")) << r.output;
    EXPECT_EQ(read_text(out), "old frame");
    EXPECT_EQ(list_dir(dir.file("disk")), std::vector<std::string>{"out.exr"});
}

TEST(cli_faults, FileSizeLimitFailsCleanlyWithoutSigxfsz) {
    ScratchDir dir;
    write_noise(dir.file("in.exr"), 512, 512);
    const std::string out = dir.file("out.exr");
    const std::string log = dir.file("log.txt");
    // ulimit -f 1024 (1 MiB): a write beyond it raises SIGXFSZ, which gdof ignores to get EFBIG.
    ChildOptions o;
    o.log = log;
    o.file_size_limit = 1 << 20;
    const int code = wait_exit(spawn(gdof_path(), {dir.file("in.exr"), "--compression", "none", "-o", out}, o));
    const std::string text = read_text(log);
    EXPECT_EQ(code, 1) << text;
    EXPECT_TRUE(contains(text, "out.exr")) << text;
    EXPECT_TRUE(contains(text, "File too large")) << text;
    EXPECT_FALSE(fs::exists(out));
    EXPECT_EQ(list_dir(dir.path().string()), (std::vector<std::string>{"in.exr", "log.txt"}));
}

TEST(cli_faults, UnwritableFolderFailsBeforeAnyWork) {
    ScratchDir dir;
    write_noise(dir.file("in.exr"), 64, 64);
    fs::create_directories(dir.file("ro"));
    fs::permissions(dir.file("ro"), fs::perms::owner_read | fs::perms::owner_exec | fs::perms::group_read |
                                        fs::perms::group_exec | fs::perms::others_read | fs::perms::others_exec);
    const std::string log = dir.file("log.txt");
    ChildOptions o;
    o.log = log;
    o.as_nobody = true;  // root would write through the permission bits
    // The input does not exist either: the output is checked first, so its error comes.
    const int code =
        wait_exit(spawn(gdof_path(), {dir.file("missing.exr"), "--diffuse", "-o", dir.file("ro/out.exr")}, o));
    const std::string text = read_text(log);
    EXPECT_EQ(code, 1) << text;
    EXPECT_TRUE(contains(text, "ro/out.exr")) << text;
    EXPECT_TRUE(contains(text, "Permission denied")) << text;
    EXPECT_FALSE(contains(text, "missing.exr")) << text;
    EXPECT_TRUE(list_dir(dir.file("ro")).empty());
}

TEST(cli_faults, FolderRemovedDuringTheWork) {
    ScratchDir dir;
    auto r = run_command(std::string("'") + GDOF_EXAMPLE_SCENE_PATH + "' --size 960x540 -o " +
                         quote(dir.file("scene.exr")));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    fs::create_directories(dir.file("shot"));
    const std::string log = dir.file("log.txt");
    ChildOptions o;
    o.log = log;
    const pid_t pid = spawn(gdof_path(), {"--threads", "1", dir.file("scene.exr"), "--diffuse", "-o",
                                          dir.file("shot/out.exr")},
                            o);
    // Once the defocus reports progress, pause it, remove the folder, let it go on.
    ASSERT_TRUE(wait_for([&] { return contains(read_text(log), "gdof: progress"); })) << read_text(log);
    ::kill(pid, SIGSTOP);
    fs::remove_all(dir.file("shot"));
    ::kill(pid, SIGCONT);
    const int code = wait_exit(pid);
    const std::string text = read_text(log);
    EXPECT_EQ(code, 1) << text;
    EXPECT_TRUE(contains(text, "shot/out.exr")) << text;
    EXPECT_TRUE(contains(text, "does not exist")) << text;
    EXPECT_FALSE(fs::exists(dir.file("shot")));  // not made again
    EXPECT_EQ(list_dir(dir.path().string()), (std::vector<std::string>{"log.txt", "scene.exr"}));
}

TEST(cli_faults, InputTruncatedWhileRead) {
    ScratchDir dir;
    const std::string in = dir.file("in.exr");
    write_noise(in, 2048, 2048, "zip");  // slow enough to read that the truncation lands mid-read
    const std::string log = dir.file("log.txt");
    ChildOptions o;
    o.log = log;
    const pid_t pid = spawn(gdof_path(), {"--threads", "1", in, "-o", dir.file("out.exr")}, o);
    ASSERT_TRUE(wait_for([&] { return has_open(pid, in); })) << read_text(log);
    ::kill(pid, SIGSTOP);
    fs::resize_file(in, fs::file_size(in) / 3);
    ::kill(pid, SIGCONT);
    const int code = wait_exit(pid);
    const std::string text = read_text(log);
    EXPECT_EQ(code, 1) << text;
    EXPECT_TRUE(contains(text, "in.exr")) << text;
    EXPECT_FALSE(fs::exists(dir.file("out.exr")));
    EXPECT_TRUE(temp_files(dir.path().string()).empty());
}

TEST(cli_faults, KillNineDuringWriteLeavesOldFrameAndANamedTempThatTheNextRunRemoves) {
    ScratchDir dir;
    write_noise(dir.file("in.exr"), 2048, 2048);
    const std::string out = dir.file("out.exr");
    write_text(out, "old frame");
    const pid_t pid = spawn(gdof_path(), {"--threads", "1", dir.file("in.exr"), "--compression", "zip", "-o", out});
    ASSERT_TRUE(wait_for([&] { return !temp_files(dir.path().string()).empty(); }));
    ::kill(pid, SIGKILL);
    EXPECT_EQ(wait_exit(pid), 128 + SIGKILL);
    EXPECT_EQ(read_text(out), "old frame");
    // The temporary file says what it is and whose: .out.exr.gdof-tmp-HOST-PID-N.exr
    const auto temps = temp_files(dir.path().string());
    ASSERT_EQ(temps.size(), 1u);
    EXPECT_EQ(temps[0].rfind(".out.exr.gdof-tmp-", 0), 0u) << temps[0];
    EXPECT_TRUE(contains(temps[0], "-" + std::to_string(pid) + "-")) << temps[0];
    EXPECT_EQ(fs::path(temps[0]).extension(), ".exr") << temps[0];

    // The next write of the same output removes it (its process is gone).
    write_noise(dir.file("small.exr"), 16, 16);
    auto r = run_gdof(quote(dir.file("small.exr")) + " -o " + quote(out));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_TRUE(temp_files(dir.path().string()).empty());
    OIIO::ImageSpec spec;
    read_pixels(out, &spec);
    EXPECT_EQ(spec.width, 16);
}
