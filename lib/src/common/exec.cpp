#include "gdof/exec.h"

#include <algorithm>
#include <atomic>
#include <map>
#include <memory>
#include <mutex>

#include <tbb/blocked_range.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

// ThreadSanitizer sees no order between the caller of parallel_for and TBB's
// workers: Debian's libtbb is not instrumented, so the hand-off of the loop
// and its join, made with libtbb's own atomics, are invisible to it, and it
// reported the caller's writes before the loop (the body's closure, the
// Exec) and its frees after it as races with the chunks. Two annotations give
// TSan those two edges and no others: what the caller did before the loop
// happens before every chunk, and every chunk before the loop returns.
// Chunks stay unordered among themselves, so a race between them reports.
#if defined(__SANITIZE_THREAD__)
#define GDOF_TSAN_ANNOTATE 1
#elif defined(__has_feature)
#if __has_feature(thread_sanitizer)
#define GDOF_TSAN_ANNOTATE 1
#endif
#endif
#ifdef GDOF_TSAN_ANNOTATE
extern "C" void __tsan_acquire(void* addr);
extern "C" void __tsan_release(void* addr);
#endif

namespace gdof {

namespace {

// The edges' addresses only name them; nothing is stored there.
struct LoopEdges {
    char start = 0, end = 0;
    void before_loop() { release(&start); }
    void chunk_starts() { acquire(&start); }
    void chunk_ends() { release(&end); }
    void after_loop() { acquire(&end); }

  private:
#ifdef GDOF_TSAN_ANNOTATE
    static void release(char* p) { __tsan_release(p); }
    static void acquire(char* p) { __tsan_acquire(p); }
#else
    static void release(char*) {}
    static void acquire(char*) {}
#endif
};

// The arena for loops on `nthreads` (fewer than the cores), made once per
// count and kept until exit. A tbb::task_arena made and destroyed per loop
// cost about 75 us in oneTBB 2021.8 (Debian bookworm) and left about 7 KB
// behind, and every later loop took longer: one process defocusing a
// 640x360 plate frame after frame took 0.13 s for the first, twice that by
// the twentieth, and grew 1.7 MB a frame, with another process busy on one
// of the two cores (docs/reliability.md, "Long runs").
tbb::task_arena& arena_for(int nthreads) {
    static std::mutex mu;
    // Never freed: a loop may run during static destruction.
    static auto* arenas = new std::map<int, std::unique_ptr<tbb::task_arena>>();
    std::lock_guard<std::mutex> lock(mu);
    std::unique_ptr<tbb::task_arena>& a = (*arenas)[nthreads];
    if (!a) a = std::make_unique<tbb::task_arena>(nthreads);
    return *a;
}

}  // namespace

bool parallel_for(const Exec& exec, long n, const std::function<void(long, long)>& f, long grain) {
    if (n <= 0) return !exec.is_cancelled();
    std::atomic<bool> stop{false};
    auto body = [&](const tbb::blocked_range<long>& r) {
        if (stop.load(std::memory_order_relaxed)) return;
        if (exec.is_cancelled()) {
            stop = true;
            return;
        }
        f(r.begin(), r.end());
    };
    if (exec.nthreads == 1) {
        // Same chunking as the parallel path would use is not required: kernels
        // never depend on chunk boundaries.
        for (long b = 0; b < n && !stop; b += grain) body(tbb::blocked_range<long>(b, std::min(n, b + grain)));
    } else {
        // More threads than cores only adds overhead (and TBB warns); results never depend on it.
        const int cores = tbb::info::default_concurrency();
        const int want = exec.nthreads > 0 ? std::min(exec.nthreads, cores) : cores;
        LoopEdges edges;
        auto chunk = [&](const tbb::blocked_range<long>& r) {
            edges.chunk_starts();
            body(r);
            edges.chunk_ends();
        };
        // Isolated: a thread waiting for this loop's chunks takes none of an
        // enclosing loop's (as in an arena of its own), so a chunk never runs
        // inside another chunk of the same loop on one thread.
        auto loop = [&] {
            tbb::this_task_arena::isolate(
                [&] { tbb::parallel_for(tbb::blocked_range<long>(0, n, std::size_t(grain)), chunk); });
        };
        edges.before_loop();
        // All cores, or already within an arena of at most `want` threads (a
        // nested loop): here; else in the arena of that many threads.
        if (want >= cores || tbb::this_task_arena::max_concurrency() <= want)
            loop();
        else
            arena_for(want).execute(loop);
        edges.after_loop();
    }
    return !stop && !exec.is_cancelled();
}

Status parallel_run(const Exec& exec, long n, const std::function<Status(long, long)>& f, long grain,
                    const std::string& what) {
    std::mutex mu;
    long failed_at = -1;  // begin of the lowest failing chunk
    Status first;
    std::atomic<bool> failed{false};
    const bool finished = parallel_for(
        exec, n,
        [&](long b, long e) {
            if (failed.load(std::memory_order_relaxed)) {
                // Still run chunks before the failure: one of them may fail
                // too, and the lowest failing chunk decides the message.
                std::lock_guard<std::mutex> lock(mu);
                if (b > failed_at) return;
            }
            Status st = f(b, e);
            if (st) return;
            std::lock_guard<std::mutex> lock(mu);
            if (failed_at < 0 || b < failed_at) {
                failed_at = b;
                first = std::move(st);
            }
            failed = true;
        },
        grain);
    if (failed) return first;
    if (!finished) return Status::cancelled(what);
    return Status::ok();
}

}  // namespace gdof
