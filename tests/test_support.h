// Shared helpers for gdof tests: scratch folders, the shared real-data path,
// and running the CLI.
#pragma once

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <string>
#include <sys/wait.h>
#include <unistd.h>

namespace gdof::test {

namespace fs = std::filesystem;

// A fresh folder per test, removed afterwards unless GDOF_KEEP_TEST_FILES is set.
class ScratchDir {
public:
    ScratchDir() {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        std::string name = info ? std::string(info->test_suite_name()) + "." + info->name() : "gdof";
        for (char& ch : name)
            if (ch == '/') ch = '_';
        path_ = fs::temp_directory_path() / ("gdof_test_" + std::to_string(::getpid()) + "_" + name);
        fs::remove_all(path_);
        fs::create_directories(path_);
    }
    ~ScratchDir() {
        if (!std::getenv("GDOF_KEEP_TEST_FILES")) {
            std::error_code ec;
            fs::remove_all(path_, ec);
        }
    }
    const fs::path& path() const { return path_; }
    std::string file(const std::string& name) const { return (path_ / name).string(); }

private:
    fs::path path_;
};

// The shared real-data folder ($GDOF_SHARED_DATA overrides the build-time path).
inline fs::path shared_data() {
    if (const char* env = std::getenv("GDOF_SHARED_DATA")) return env;
    return GDOF_SHARED_DATA;
}

// Path of a shared data file, or "" when absent (callers skip with a message).
inline std::string shared_file(const std::string& rel) {
    fs::path p = shared_data() / rel;
    return fs::exists(p) ? p.string() : std::string();
}

// Under CI=true nothing may skip for lack of shared data or Embree: CI must
// run every test, so a missing prerequisite fails there.
inline bool ci_runs_everything() {
    const char* ci = std::getenv("CI");
    return ci && std::string(ci) == "true";
}
#define GDOF_SKIP_OR_FAIL(message)                                            \
    do {                                                                      \
        std::ostringstream gdof_skip_os_;                                     \
        gdof_skip_os_ << message;                                             \
        if (::gdof::test::ci_runs_everything())                               \
            GTEST_FAIL() << "CI=true, so this may not skip: " << gdof_skip_os_.str(); \
        else                                                                  \
            GTEST_SKIP() << gdof_skip_os_.str();                              \
    } while (0)

#define GDOF_REQUIRE_SHARED(var, rel)                                                                 \
    std::string var = ::gdof::test::shared_file(rel);                                               \
    if (var.empty())                                                                                \
    GDOF_SKIP_OR_FAIL("shared test data '" << (rel) << "' not found under " << ::gdof::test::shared_data() \
                                           << " (set GDOF_SHARED_DATA); skipping")

struct CommandResult {
    int exit_code = -1;
    std::string output;  // stdout and stderr together
};

// Runs a shell command, capturing stdout+stderr.
inline CommandResult run_command(const std::string& cmd) {
    CommandResult r;
    FILE* p = ::popen((cmd + " 2>&1").c_str(), "r");
    if (!p) return r;
    char buf[4096];
    std::size_t n;
    while ((n = std::fread(buf, 1, sizeof buf, p)) > 0) r.output.append(buf, n);
    int st = ::pclose(p);
    r.exit_code = WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
    return r;
}

// Runs the gdof CLI with the given arguments (already shell-quoted as needed).
inline CommandResult run_gdof(const std::string& args) {
    return run_command(std::string("'") + GDOF_CLI_PATH + "' " + args);
}

inline std::string quote(const std::string& s) {
    std::string q = "'";
    for (char c : s) {
        if (c == '\'') q += "'\\''";
        else q += c;
    }
    return q + "'";
}

}  // namespace gdof::test
