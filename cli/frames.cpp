// The frame-sequence driver: without a sequence the steps run once; with
// --frames (or an input pattern such as in.####.exr, which then expands to
// the frames on disk) every file name with a frame pattern is substituted
// and the whole command line runs once per frame. Several frames written to
// one name without a frame pattern is a usage error (each would overwrite
// the last).
#include <unistd.h>

#include <iostream>

#include "cli.h"
#include "gdof/io/sequence.h"

namespace gdof::cli {

namespace {

std::vector<int> choose_frames(const Program& p, bool& is_sequence) {
    is_sequence = false;
    if (!p.global.frames.empty()) {
        is_sequence = true;
        auto r = io::parse_frame_range(p.global.frames);
        if (!r) usage_error("--frames '" + p.global.frames + "': " + r.message());
        if (r.value().empty()) usage_error("--frames '" + p.global.frames + "': no frames");
        return r.value();
    }
    // The first input with a pattern decides which frames exist.
    for (const Step& s : p.steps) {
        if (!s.is_input() || !io::has_frame_pattern(s.args[0])) continue;
        is_sequence = true;
        auto r = io::frames_on_disk(s.args[0]);
        if (!r) runtime_error("input sequence '" + s.args[0] + "': " + r.message());
        if (r.value().empty()) runtime_error("input sequence '" + s.args[0] + "': no frames on disk match it");
        return r.value();
    }
    // A pattern elsewhere (an output) needs a frame list.
    for (const Step& s : p.steps) {
        if (s.is_input() || s.stack_output) continue;  // a stack's pattern numbers references
        for (int k : s.def->file_args)
            if (io::has_frame_pattern(s.args[std::size_t(k)]))
                usage_error(s.flag + " '" + s.args[std::size_t(k)] +
                            "' has a frame pattern: give --frames or an input sequence");
    }
    return {};
}

// Every -o of a sequence of several frames needs a frame pattern.
void check_output_patterns(const Program& p, std::size_t nframes) {
    if (nframes < 2) return;
    const std::string runs = p.global.frames.empty() ? std::to_string(nframes) + " frames of the input sequence"
                                                     : std::to_string(nframes) + " frames (--frames " + p.global.frames + ")";
    for (const Step& s : p.steps) {
        if (s.is_input() || s.stack_output || s.name() != "-o") continue;
        if (!io::has_frame_pattern(s.args[0]))
            usage_error(s.flag + " '" + s.args[0] + "': " + runs +
                        " would all be written to this one file; put a frame pattern in the name (####, @, %04d)");
    }
}

int count_progress_stages(const Program& p) {
    int n = 0;
    for (const Step& s : p.steps)
        if (!s.is_input() && s.def->progress_stage) ++n;
    return n;
}

}  // namespace

int run_program(Program& program, Session& session) {
    bool is_sequence = false;
    const std::vector<int> frames = choose_frames(program, is_sequence);
    check_output_patterns(program, frames.size());
    const int stages = count_progress_stages(program);
    if (!is_sequence) {
        session.progress.begin_frame(std::nullopt, 0, 1, stages);
        run_steps(session, program.steps, std::nullopt);
        session.progress.end_frame();
        session.stats.add_frame();
        return kOk;
    }
    int failed = 0;
    const int n = int(frames.size());
    for (int i = 0; i < n; ++i) {
        check_interrupted();
        const int frame = frames[std::size_t(i)];
        if (!session.progress.enabled() && session.global.verbose)
            session.progress.message("frame " + std::to_string(i + 1) + "/" + std::to_string(n) + " (" +
                                     std::to_string(frame) + ")");
        session.progress.begin_frame(frame, i, n, stages);
        try {
            run_steps(session, program.steps, frame);
            session.progress.end_frame();
            session.stats.add_frame();
        } catch (const CliError& e) {
            if (e.code == kInterrupted || e.code == kTerminated) throw;
            const std::string msg = "frame " + std::to_string(frame) + ": " + e.what();
            if (!session.global.skip_bad_frames) throw CliError(e.code, msg);
            session.progress.finish();
            std::cerr << "gdof: error: " << msg << "\n";
            ++failed;
        }
    }
    if (failed > 0)
        runtime_error(std::to_string(failed) + " of " + std::to_string(n) + " frames failed");
    return kOk;
}

}  // namespace gdof::cli
