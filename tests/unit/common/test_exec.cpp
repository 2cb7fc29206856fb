// parallel_run: work that can fail, in parallel; the error does not depend
// on the thread count; loops leave nothing behind (a process defocuses frame
// after frame); read_text's errors name the file.
#include <gtest/gtest.h>

#include <atomic>
#include <fstream>
#include <string>

#include "gdof/exec.h"
#include "gdof/text_file.h"
#include "sanitized.h"
#include "test_support.h"

namespace gdof {
namespace {

TEST(exec, ParallelRunReturnsTheLowestFailingChunkForAnyThreadCount) {
    for (int threads : {1, 2, 8}) {
        Exec exec;
        exec.nthreads = threads;
        std::atomic<long> ran{0};
        Status st = parallel_run(
            exec, 1000,
            [&](long b, long e) -> Status {
                for (long i = b; i < e; ++i) {
                    ++ran;
                    if (i == 617 || i == 830) return Status::error("item " + std::to_string(i), StatusCode::InvalidArgument);
                }
                return Status::ok();
            },
            7);
        ASSERT_FALSE(st);
        EXPECT_EQ(st.message(), "item 617") << threads << " threads";
        EXPECT_EQ(st.code(), StatusCode::InvalidArgument);
        EXPECT_GE(ran.load(), 618);
    }
    Exec ok;
    long sum = 0;
    EXPECT_TRUE(parallel_run(ok, 10, [&](long b, long e) { sum += e - b; return Status::ok(); }, 10));
    EXPECT_EQ(sum, 10);
    Exec cancel;
    cancel.cancelled = [] { return true; };
    Status c = parallel_run(cancel, 10, [](long, long) { return Status::ok(); }, 1, "blur map");
    EXPECT_EQ(c.code(), StatusCode::Cancelled);
    EXPECT_EQ(c.message(), "blur map cancelled");
}

TEST(exec, ReadTextNamesTheFile) {
    test::ScratchDir dir;
    const std::string f = dir.file("a.json");
    std::ofstream(f) << "{\"k\": 1}\n";
    auto t = read_text(f);
    ASSERT_TRUE(t) << t.message();
    EXPECT_EQ(*t, "{\"k\": 1}\n");
    auto missing = read_text(dir.file("nope.json"));
    ASSERT_FALSE(missing);
    EXPECT_EQ(missing.status().code(), StatusCode::NotFound);
    EXPECT_NE(missing.message().find("nope.json' not found"), std::string::npos) << missing.message();
    auto folder = read_text(dir.path().string());
    ASSERT_FALSE(folder);
    EXPECT_EQ(folder.status().code(), StatusCode::Io);
}

// The process's resident memory, KB (Linux; -1 elsewhere).
long resident_kb() {
    std::ifstream f("/proc/self/status");
    for (std::string line; std::getline(f, line);)
        if (line.rfind("VmRSS:", 0) == 0) return std::stol(line.substr(6));
    return -1;
}

// A loop is cheap and leaves nothing behind, however many ran before it: a
// render farm's process defocuses a sequence frame after frame, an OpenFX
// host for a whole session, each frame thousands of loops. With a TBB arena
// made and dropped per loop (oneTBB 2021.8), each left about 7 KB behind
// and took longer than the last (a 640x360 plate's frame 0.13 s alone,
// 0.26 s by the twentieth in one process beside another job): the 10200
// loops below (600, each running 16 nested) grew the process by 73 MB.
TEST(exec, ManyLoopsLeaveNothingBehind) {
#ifdef GDOF_TEST_SANITIZED
    GTEST_SKIP() << "sanitizers keep freed memory (quarantine): resident size says nothing here";
#else
    if (resident_kb() < 0) GTEST_SKIP() << "no /proc/self/status";
    std::atomic<long> sum{0};
    auto loops = [&](int count, const Exec& exec) {
        for (int i = 0; i < count; ++i)
            parallel_for(exec, 64, [&](long b, long e) {
                // A nested loop, as the pipeline's per-layer work runs loops in loops.
                parallel_for(exec, 4, [&](long bb, long ee) { sum += (ee - bb) * (e - b); });
            }, 4);
    };
    Exec all;  // every core
    Exec two;
    two.nthreads = 2;
    loops(200, all);  // the workers' stacks and TBB's own setup
    loops(200, two);
    const long before = resident_kb();
    loops(300, all);
    loops(300, two);
    const long grown = resident_kb() - before;
    EXPECT_EQ(sum.load(), 1000L * 64 * 4);
    EXPECT_LT(grown, 8 * 1024) << "KB more resident after 10200 loops";
#endif
}

}  // namespace
}  // namespace gdof
