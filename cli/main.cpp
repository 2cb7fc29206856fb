// gdof: the command-line front end. Parses, sets up the session (threads,
// colour config, progress, Ctrl-C), runs the program and turns errors into
// "gdof: error: <what>" on stderr with exit code 1 (runtime) or 2 (usage).
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <iostream>
#include <memory>
#include <new>

#include <tbb/global_control.h>

#include "cli.h"

using namespace gdof::cli;

namespace {

void print_error(const std::string& what) {
    std::cout.flush();
    std::cerr << "gdof: error: " << what << "\n";
    std::cerr.flush();
}

void setup_session(Session& s, const Program& p) {
    s.global = p.global;
    // Colour: --colorconfig, else $OCIO, else built-in.
    if (!p.global.colorconfig.empty()) {
        StageTimer t(s.stats, "colour config");
        auto r = gdof::io::ColourConfig::from_file(p.global.colorconfig);
        if (!r) runtime_error("--colorconfig: " + r.message());
        s.colour = r.value();
    } else {
        auto r = gdof::io::ColourConfig::from_environment();
        if (!r) runtime_error(r.message());
        s.colour = r.value();
    }
    // A terminal gets a bar; a log (a farm, a pipe) whole lines, unless --no-progress.
    const bool tty = ::isatty(STDERR_FILENO) != 0;
    s.progress.set_style(p.global.no_progress ? ProgressStyle::Off : tty ? ProgressStyle::Bar : ProgressStyle::Lines);
    s.exec.nthreads = p.global.threads;
    s.exec.cancelled = [] { return interrupted(); };
    Progress* progress = &s.progress;
    s.exec.progress = [progress](double fraction) { progress->update(fraction); };
}

}  // namespace

int main(int argc, char** argv) {
    const auto t0 = std::chrono::steady_clock::now();
    std::vector<std::string> args(argv + 1, argv + argc);
    if (args.empty()) {
        std::cerr << short_usage_text();
        return kUsageError;
    }
    install_signal_handlers();
    gdof::keep_freed_memory();  // frame-sized buffers freed layer after layer are reused, not re-faulted
    Session session;
    int code = kOk;
    try {
        int exit_code = kOk;
        std::optional<Program> program = parse_args(args, exit_code);
        if (!program) return exit_code;
        setup_session(session, *program);
        // --threads also bounds work done without an Exec (I/O, colour).
        std::unique_ptr<tbb::global_control> thread_limit;
        if (program->global.threads > 0)
            thread_limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                                 std::size_t(program->global.threads));
        preflight(session, program->steps);
        code = run_program(*program, session);
    } catch (const CliError& e) {
        session.progress.finish();
        print_error(e.what());
        code = e.code;
    } catch (const std::bad_alloc&) {
        session.progress.finish();
        print_error("out of memory");
        code = kRuntimeError;
    } catch (const std::exception& e) {
        session.progress.finish();
        print_error(std::string("unexpected: ") + e.what());
        code = kRuntimeError;
    }
    if (session.global.stats) {
        const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        std::cerr << session.stats.report(total);
    }
    return code;
}
