// How a library call runs: thread count, cancellation, progress. Kernels see
// sub-regions, never threads; results never depend on the thread count.
#pragma once

#include <functional>
#include <string>

#include "gdof/export.h"
#include "gdof/status.h"

namespace gdof {

struct Exec {
    int nthreads = 0;                             // 0: all cores
    // Polled per row/tile; true stops the work. Once true it must stay true:
    // a loop stops at the first poll that sees it, and the steps after it
    // check again before they use what the loop left unfinished.
    std::function<bool()> cancelled;
    std::function<void(double fraction)> progress;  // 0..1, called from any thread, throttled

    bool is_cancelled() const { return cancelled && cancelled(); }
    void report(double fraction) const {
        if (progress) progress(fraction);
    }
};

// Runs f(begin, end) over [0, n) in parallel chunks on nthreads (TBB: the
// caller's arena, or one kept per thread count; a loop costs the same however
// many ran before it). Returns false if cancelled. Chunking never affects results.
GDOF_API bool parallel_for(const Exec& exec, long n, const std::function<void(long, long)>& f, long grain = 1);

// The same for work that can fail: f(begin, end) returns a Status. Chunks
// after a failure are skipped; the error returned is the one of the
// lowest-indexed failing chunk, so the message does not depend on the thread
// count. Cancellation gives Status::cancelled(what).
GDOF_API Status parallel_run(const Exec& exec, long n, const std::function<Status(long, long)>& f, long grain = 1,
                             const std::string& what = {});

// Process-wide: keep freed large blocks in the heap for reuse instead of
// returning them to the system (glibc; elsewhere a no-op). For applications
// that own their process (the gdof CLI calls it at start, the benchmarks
// do); a plug-in must leave its host's allocator alone.
GDOF_API void keep_freed_memory();

}  // namespace gdof
