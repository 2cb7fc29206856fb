// keep_freed_memory (gdof/exec.h): frame-sized blocks come from the heap and
// stay there when freed, from the main thread and from worker threads alike.
// Measured through glibc's own accounting (mallinfo2); elsewhere, and under
// sanitizers (which replace the allocator), the policy is a no-op to test.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstddef>
#include <thread>
#include <vector>

#include "gdof/exec.h"

#include "sanitized.h"

#if defined(__GLIBC__) && !defined(GDOF_TEST_SANITIZED)
#include <malloc.h>

namespace {

// A 4K frame's float plane is 33 MB; glibc maps blocks above 128 KiB to
// 32 MiB (adaptive) by default. A worker thread's arena holds at most 64 MiB
// per heap, so a larger block there is mapped whatever the policy: the
// library's frame-sized buffers are planes (33 MB at 4K) or are allocated
// on the calling thread.
constexpr std::size_t kMainFloats = std::size_t(24) << 20;    // 96 MiB
constexpr std::size_t kWorkerFloats = std::size_t(12) << 20;  // 48 MiB

std::size_t mapped_bytes() { return mallinfo2().hblkhd; }

// Allocates and fills a block (so it is really touched), returns the mapped
// bytes seen while it lived.
std::size_t mapped_while_holding_a_block(std::size_t floats) {
    std::vector<float> block(floats, 1.0f);
    const std::size_t mapped = mapped_bytes();
    EXPECT_EQ(block[floats / 2], 1.0f);
    return mapped;
}

}  // namespace

TEST(KeepFreedMemory, FrameSizedBlocksAreNeverMapped) {
    gdof::keep_freed_memory();
    const std::size_t before = mapped_bytes();
    EXPECT_EQ(mapped_while_holding_a_block(kMainFloats), before) << "a 96 MiB block on the main thread was mapped";
    std::size_t in_worker = 0;
    std::thread worker([&] {
        for (int i = 0; i < 3; ++i) in_worker = std::max(in_worker, mapped_while_holding_a_block(kWorkerFloats));
    });
    worker.join();
    EXPECT_EQ(in_worker, before) << "a 48 MiB block on a worker thread was mapped";
}

TEST(KeepFreedMemory, AFreedBlockStaysInTheHeap) {
    gdof::keep_freed_memory();
    (void)mapped_while_holding_a_block(kMainFloats);  // allocated, filled and freed
    // Not trimmed back to the system: the next frame's buffers reuse it
    // instead of faulting in zeroed pages again.
    EXPECT_GE(mallinfo2().fordblks, kMainFloats * sizeof(float));
}

#else

TEST(KeepFreedMemory, FrameSizedBlocksAreNeverMapped) {
    GTEST_SKIP() << "glibc's allocator only (a sanitizer or another C library replaces it)";
}

#endif
