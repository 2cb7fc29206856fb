// General flags: --help, --version, and the global options (verbosity,
// threads, progress, --stats).
#include "cli.h"
#include "ops/ops.h"

namespace gdof::cli {

std::vector<Command> general_commands() {
    const std::string G = "General";
    std::vector<Command> t;
    t.push_back({.names = {"--help", "-h"}, .kind = Kind::Immediate, .group = G, .help = "print this help and exit",
                 .print = usage_text});
    t.push_back({.names = {"--version"}, .kind = Kind::Immediate, .group = G, .help = "print the version and exit",
                 .print = version_text});
    t.push_back({.names = {"-v", "--verbose"}, .kind = Kind::Global, .group = G,
                 .help = "verbose: --info lists every attribute; frame counters",
                 .set = [](GlobalOptions& g, const Step&) { g.verbose = true; }});
    t.push_back({.names = {"--threads"}, .args = "N", .kind = Kind::Global, .group = G,
                 .help = "worker threads (default 0: all cores)",
                 .set = [](GlobalOptions& g, const Step& s) {
                     g.threads = parse_int(s.flag, s.args[0]);
                     if (g.threads < 0) usage_error("--threads: expected 0 (all cores) or more, got '" + s.args[0] + "'");
                 }});
    t.push_back({.names = {"--progress"}, .kind = Kind::Global, .group = G,
                 .help = "show progress on stderr (the default): a bar on a terminal, else lines 'gdof: progress [frame F (I/N)] STAGE P%'",
                 .set = [](GlobalOptions& g, const Step&) { g.progress = true, g.no_progress = false; }});
    t.push_back({.names = {"--no-progress"}, .kind = Kind::Global, .group = G, .help = "show no progress",
                 .set = [](GlobalOptions& g, const Step&) { g.no_progress = true, g.progress = false; }});
    t.push_back({.names = {"--stats"}, .kind = Kind::Global, .group = G,
                 .help = "print the time spent per stage on stderr at the end",
                 .set = [](GlobalOptions& g, const Step&) { g.stats = true; }});
    return t;
}

}  // namespace gdof::cli
