// Runs one frame's steps on the image stack: each step runs its row's
// runner, after the deferred --render / --composite it does not let wait.
// The frame's output files are checked first, before any work.
#include "cli.h"
#include "gdof/io/image_io.h"
#include "gdof/io/sequence.h"
#include "ops/ops.h"

namespace gdof::cli {

Frame::Frame(Session& s, std::optional<int> frame_number) : session(&s), frame(frame_number) {
    output.colour = s.colour.get();
    output.cancelled = [] { return interrupted(); };  // a signal during a write drops the file
}

StackEntry& Frame::top(const std::string& flag) {
    if (stack.empty()) usage_error(flag + ": no image on the stack (give an input file before " + flag + ")");
    return stack.back();
}

Step with_frame_number(const Step& step, const Command& command, std::optional<int> frame) {
    Step s = step;
    if (!frame || s.stack_output) return s;
    for (int k : command.file_args) {
        std::string& arg = s.args[std::size_t(k)];
        if (!io::has_frame_pattern(arg)) continue;
        auto r = io::expand_frame_pattern(arg, *frame);
        if (!r) runtime_error("'" + arg + "': " + r.message());
        arg = r.value();
    }
    return s;
}

namespace {

// Runs the pending --render, then the pending --composite, unless `waiting` lets them wait.
void run_deferred(Frame& f, unsigned waiting) {
    if (!(waiting & kRenderWaits)) run_pending_render(f);
    if (!(waiting & kCompositeWaits)) run_pending_composite(f);
}

// A missing or read-only output folder fails now, not after the work.
// (A stack's -o makes its folder.)
void check_outputs(const std::vector<Step>& steps, std::optional<int> frame) {
    for (const Step& s : steps) {
        if (s.is_input() || s.stack_output || s.name() != "-o") continue;
        const Step named = with_frame_number(s, *s.def, frame);
        if (Status st = io::check_output_path(named.args[0]); !st) runtime_error(s.flag + " " + st.message());
    }
}

}  // namespace

void run_steps(Session& session, const std::vector<Step>& steps, std::optional<int> frame) {
    check_outputs(steps, frame);
    Frame f(session, frame);
    for (const Step& step : steps) {
        check_interrupted();
        const Command& command = step.is_input() ? input_command() : *step.def;
        run_deferred(f, command.lets_wait ? command.lets_wait(f, step) : kNothingWaits);
        command.run(f, with_frame_number(step, command, frame));
    }
    run_deferred(f, kNothingWaits);
}

void preflight(const Session& session, const std::vector<Step>& steps) {
    for (const Step& s : steps)
        if (!s.is_input() && s.def->preflight) s.def->preflight(session, s);
}

}  // namespace gdof::cli
