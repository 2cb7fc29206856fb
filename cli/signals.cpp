// Ctrl-C: the first SIGINT (or SIGTERM) sets a flag that Exec::cancelled
// reports, so long work stops at the next row/tile and no output is written.
// The handler then reverts to the default, so a second Ctrl-C ends the
// process at once.
#include <csignal>

#include "cli.h"

namespace gdof::cli {

namespace {
volatile std::sig_atomic_t g_interrupted = 0;

extern "C" void on_signal(int sig) {
    g_interrupted = 1;
    std::signal(sig, SIG_DFL);
}
}  // namespace

void install_signal_handlers() {
    // A signal ignored by the parent (nohup, some farm wrappers) stays ignored.
    for (int sig : {SIGINT, SIGTERM}) {
        auto previous = std::signal(sig, on_signal);
        if (previous == SIG_IGN) std::signal(sig, SIG_IGN);
    }
}

bool interrupted() { return g_interrupted != 0; }

void check_interrupted() {
    if (interrupted()) throw CliError(kInterrupted, "interrupted");
}

}  // namespace gdof::cli
