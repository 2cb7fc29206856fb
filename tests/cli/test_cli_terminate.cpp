// gdof CLI: SIGTERM (what farm schedulers send) and SIGINT stop a run with
// 143 / 130 and leave no partial output: not during the work, and not
// during the write of an output (the finished temporary file is dropped,
// not renamed; an older frame stays as it was).
#include "cli/cli_test_helpers.h"
#include "fault_support.h"

using namespace gdof::test;

namespace {

void write_noise(const std::string& path, int w, int h) {
    write_exr(path, w, h, {"R", "G", "B", "A"},
              [](int x, int y, int c) { return float((x * 7919 + y * 104729 + c * 31) % 65521) / 65521.f; });
}

}  // namespace

TEST(cli_terminate, SigtermDuringTheWorkExits143WithNoOutput) {
    ScratchDir dir;
    auto r = run_command(std::string("'") + GDOF_EXAMPLE_SCENE_PATH + "' --size 960x540 -o " +
                         quote(dir.file("scene.exr")));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const std::string log = dir.file("log.txt");
    ChildOptions o;
    o.log = log;
    const pid_t pid =
        spawn(GDOF_CLI_PATH, {"--threads", "1", dir.file("scene.exr"), "--diffuse", "-o", dir.file("out.exr")}, o);
    ASSERT_TRUE(wait_for([&] { return contains(read_text(log), "gdof: progress"); })) << read_text(log);
    ::kill(pid, SIGTERM);
    const int code = wait_exit(pid);
    const std::string text = read_text(log);
    EXPECT_EQ(code, 143) << text;
    EXPECT_TRUE(contains(text, "gdof: error: interrupted (SIGTERM)")) << text;
    EXPECT_EQ(list_dir(dir.path().string()), (std::vector<std::string>{"log.txt", "scene.exr"}));
}

TEST(cli_terminate, SignalDuringTheWriteDropsTheFileAndKeepsTheOldOne) {
    for (int sig : {SIGTERM, SIGINT}) {
        ScratchDir dir;
        write_noise(dir.file("in.exr"), 2048, 2048);
        const std::string out = dir.file("out.exr");
        write_text(out, "old frame");
        const std::string log = dir.file("log.txt");
        ChildOptions o;
        o.log = log;
        const pid_t pid =
            spawn(GDOF_CLI_PATH, {"--threads", "1", dir.file("in.exr"), "--compression", "zip", "-o", out}, o);
        // The temporary file exists only while the output is written: pause
        // the write there, signal, let it finish.
        ASSERT_TRUE(wait_for([&] { return !temp_files(dir.path().string()).empty(); }));
        ::kill(pid, SIGSTOP);
        ::kill(pid, sig);
        ::kill(pid, SIGCONT);
        const int code = wait_exit(pid);
        const std::string text = read_text(log);
        EXPECT_EQ(code, 128 + sig) << text;
        EXPECT_TRUE(contains(text, "gdof: error: interrupted")) << text;
        EXPECT_EQ(read_text(out), "old frame");
        EXPECT_TRUE(temp_files(dir.path().string()).empty()) << text;
        EXPECT_EQ(list_dir(dir.path().string()), (std::vector<std::string>{"in.exr", "log.txt", "out.exr"}));
    }
}
