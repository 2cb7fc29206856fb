// gdof CLI: Ctrl-C (SIGINT) stops the run with exit code 130; finished
// outputs stay complete and no partial or temporary file is left behind.
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>

#include <chrono>
#include <thread>

#include "cli/cli_test_helpers.h"

extern char** environ;

using namespace gdof::test;

TEST(cli_signals, InterruptLeavesOnlyCompleteOutputs) {
    ScratchDir dir;
    write_exr(dir.file("in.exr"), 1024, 1024, {"R", "G", "B", "Z"},
              [](int x, int y, int c) { return c == 3 ? 1.f + 0.001f * float(x + y) : 0.5f; },
              [](OIIO::ImageSpec& s) {
                  const float m[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
                  s.attribute("worldToCamera", OIIO::TypeMatrix, m);
                  s.attribute("focalLength", 50.f);
                  s.attribute("fNumber", 2.f);
                  s.attribute("focusDistance", 2.f);
              });
    const std::string log = dir.file("log.txt");
    std::vector<std::string> args = {GDOF_CLI_PATH, "--frames", "1-500", dir.file("in.exr"), "--eval-blur",
                                     "-o",          dir.file("out.####.exr")};
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_addopen(&fa, 2, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawnattr_t attr;
    posix_spawnattr_init(&attr);
    sigset_t def;
    sigemptyset(&def);
    sigaddset(&def, SIGINT);
    posix_spawnattr_setsigdefault(&attr, &def);  // not ignored, whatever the test runner does
    posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETSIGDEF);
    pid_t pid = 0;
    ASSERT_EQ(posix_spawn(&pid, argv[0], &fa, &attr, argv.data(), environ), 0);
    posix_spawn_file_actions_destroy(&fa);
    posix_spawnattr_destroy(&attr);

    // Wait until the first output exists, then interrupt.
    const auto t0 = std::chrono::steady_clock::now();
    while (!fs::exists(dir.file("out.0001.exr")) && std::chrono::steady_clock::now() - t0 < std::chrono::seconds(60))
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    std::this_thread::sleep_for(std::chrono::milliseconds(150));
    ::kill(pid, SIGINT);
    int status = 0;
    ASSERT_EQ(::waitpid(pid, &status, 0), pid);
    ASSERT_TRUE(WIFEXITED(status)) << "killed by signal " << (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
    EXPECT_EQ(WEXITSTATUS(status), 130);
    const std::string text = read_text(log);
    EXPECT_TRUE(contains(text, "gdof: error: interrupted")) << text;

    // Every file left is the input, the log or a complete output.
    int outputs = 0;
    for (const std::string& name : list_dir(dir.path().string())) {
        if (name == "in.exr" || name == "log.txt") continue;
        ASSERT_EQ(name.rfind("out.", 0), 0u) << "unexpected file " << name;
        ASSERT_EQ(name.size(), std::string("out.0001.exr").size()) << "unexpected file " << name;
        OIIO::ImageSpec s;
        auto px = read_pixels(dir.file(name), &s);
        EXPECT_EQ(s.width, 1024) << name;
        EXPECT_GE(s.channelindex("blur"), 0) << name;
        ++outputs;
    }
    EXPECT_GE(outputs, 1);
    EXPECT_LT(outputs, 500);
}
