// Frame sequences: --frames and --skip-bad-frames (the driver is frames.cpp).
#include "cli.h"
#include "gdof/io/sequence.h"
#include "ops/ops.h"

namespace gdof::cli {

std::vector<Command> sequence_commands() {
    const std::string S = "Sequences";
    std::vector<Command> t;
    t.push_back({.names = {"--frames"}, .args = "SPEC", .kind = Kind::Global, .group = S,
                 .help = "run once per frame (1-10, 1-10x2, 1,3,7-9, 10-1); #### @ %04d in file names become the frame",
                 .set = [](GlobalOptions& g, const Step& s) {
                     auto r = io::parse_frame_range(s.args[0]);
                     if (!r) usage_error("--frames '" + s.args[0] + "': " + r.message());
                     g.frames = s.args[0];
                 }});
    t.push_back({.names = {"--skip-bad-frames"}, .kind = Kind::Global, .group = S,
                 .help = "report a failing frame and go on with the next (exit 1 at the end)",
                 .set = [](GlobalOptions& g, const Step&) { g.skip_bad_frames = true; }});
    return t;
}

}  // namespace gdof::cli
