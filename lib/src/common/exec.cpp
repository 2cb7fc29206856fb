#include "gdof/exec.h"

#include <atomic>

#include <algorithm>

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

}  // namespace gdof
