#include "gdof/exec.h"

#include <algorithm>
#include <atomic>
#include <mutex>

#include <tbb/blocked_range.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

namespace gdof {

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
        tbb::task_arena arena(exec.nthreads > 0 ? std::min(exec.nthreads, cores) : tbb::task_arena::automatic);
        arena.execute([&] { tbb::parallel_for(tbb::blocked_range<long>(0, n, std::size_t(grain)), body); });
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
