// SIGINT (Ctrl-C) and SIGTERM (what farm schedulers send): the first one
// sets a flag that Exec::cancelled reports, so long work stops at the next
// row/tile, a write in progress is abandoned before its rename and no output
// is left; the exit status is 128 + the signal (130, 143). The handler then
// reverts to the default, so a second signal ends the process at once (its
// temporary file, if a write was running, is removed by the next run).
// SIGXFSZ is ignored: a write over the file-size limit (ulimit -f) fails
// with EFBIG and a clean error instead of killing the process.
#include <csignal>

#include "cli.h"

namespace gdof::cli {

namespace {
volatile std::sig_atomic_t g_signal = 0;

extern "C" void on_signal(int sig) {
    g_signal = sig;
    std::signal(sig, SIG_DFL);
}
}  // namespace

void install_signal_handlers() {
    // A signal ignored by the parent (nohup, some farm wrappers) stays ignored.
    for (int sig : {SIGINT, SIGTERM}) {
        auto previous = std::signal(sig, on_signal);
        if (previous == SIG_IGN) std::signal(sig, SIG_IGN);
    }
    std::signal(SIGXFSZ, SIG_IGN);
}

bool interrupted() { return g_signal != 0; }

int interrupt_exit_code() { return g_signal == SIGTERM ? kTerminated : kInterrupted; }

void throw_interrupted() {
    throw CliError(interrupt_exit_code(), g_signal == SIGTERM ? "interrupted (SIGTERM)" : "interrupted (SIGINT)");
}

void check_interrupted() {
    if (interrupted()) throw_interrupted();
}

}  // namespace gdof::cli
