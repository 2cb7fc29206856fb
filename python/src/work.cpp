// Library work from Python (run_work, gdof_python.h): the GIL released while
// the library computes; Ctrl-C and progress callbacks through the Exec.
//
// Python runs signal handlers only on its main thread and only when asked
// (PyErr_CheckSignals), so the cancel callback, which the library polls per
// row or tile from any thread, asks on the calling thread (at most every
// 20 ms, taking the GIL for that moment): a KeyboardInterrupt found there is
// kept and stops the work, and is raised when the call returns. Progress
// callbacks are Python code too: called under the GIL, one at a time, at
// most every 0.1 s; an exception they raise stops the work the same way.
#include <atomic>
#include <chrono>
#include <mutex>
#include <optional>
#include <thread>

#include "gdof_python.h"

namespace gdof::python {

namespace {

using Clock = std::chrono::steady_clock;

struct WorkState {
    std::thread::id caller = std::this_thread::get_id();
    std::atomic<bool> stop{false};
    Clock::time_point last_signal_check = Clock::now();
    std::mutex progress_mu;  // one progress call at a time; the throttle
    Clock::time_point last_progress{};
    std::mutex error_mu;  // the kept Python exception
    std::optional<nb::python_error> error;

    // With the GIL held and a Python exception set: keep it (the first only) and stop.
    void keep_error() {
        std::lock_guard<std::mutex> lock(error_mu);
        if (!error) error.emplace();
        else PyErr_Clear();
        stop = true;
    }
};

}  // namespace

void run_work(const nb::object& progress, int threads, const std::function<Status(const Exec&)>& work) {
    WorkState state;
    Exec exec;
    exec.nthreads = threads;
    exec.cancelled = [&state] {
        if (state.stop) return true;
        if (std::this_thread::get_id() != state.caller) return false;
        const Clock::time_point now = Clock::now();
        if (now - state.last_signal_check < std::chrono::milliseconds(20)) return false;
        state.last_signal_check = now;
        nb::gil_scoped_acquire gil;
        if (PyErr_CheckSignals() != 0) state.keep_error();
        return state.stop.load();
    };
    if (!progress.is_none()) {
        exec.progress = [&state, &progress](double fraction) {
            if (state.stop) return;
            std::lock_guard<std::mutex> lock(state.progress_mu);
            const Clock::time_point now = Clock::now();
            if (fraction < 1.0 && now - state.last_progress < std::chrono::milliseconds(100)) return;
            state.last_progress = now;
            nb::gil_scoped_acquire gil;
            try {
                progress(fraction);
            } catch (nb::python_error& e) {
                e.restore();
                state.keep_error();
            }
        };
    }
    Status status;
    {
        nb::gil_scoped_release release;
        status = work(exec);
    }
    if (state.error) {
        // The KeyboardInterrupt or the callback's exception, as it was raised.
        state.error->restore();
        state.error.reset();
        throw nb::python_error();
    }
    check(status);
}

}  // namespace gdof::python
