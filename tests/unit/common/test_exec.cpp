// parallel_run: work that can fail, in parallel; the error does not depend
// on the thread count; read_text's errors name the file.
#include <gtest/gtest.h>

#include <atomic>
#include <fstream>

#include "gdof/exec.h"
#include "gdof/text_file.h"
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

}  // namespace
}  // namespace gdof
