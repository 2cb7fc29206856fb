// What a process pays before any pixel: the CLI started for nothing
// (`--version`), for an EXR-only job and for a job with a PNG (the first file
// in a format other than EXR loads the OpenImageIO module, gdof_oiio.so, and
// with it OpenImageIO's ~250 libraries), next to the exec floor measured in
// the same run (/bin/true). A farm task pays the start once per frame (or
// per chunk), an OFX host once per session, `import gdof` once. Each command
// runs --reps times in fresh child processes, the commands interleaved
// round by round so the machine's noise falls on all of them; median and
// least wall time, peak resident memory, and the shared objects the dynamic
// loader initialised (LD_DEBUG=files, once).
//
//   bench_startup --cli PATH [--reps 21] [--out DIR]
//
// Writes DIR/startup.csv and DIR/startup_table.md.
#include <fcntl.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "bench_cli.h"
#include "gdof/image.h"
#include "gdof/io/image_io.h"

extern char** environ;

using namespace gdof;

[[noreturn]] void gdof::bench::die(const std::string& m) {
    std::fprintf(stderr, "bench_startup: %s\n", m.c_str());
    std::exit(2);
}

namespace {

namespace fs = std::filesystem;
using bench::die;

struct Run {
    double seconds = 0, peak_mb = 0;
};

// Runs argv in a child (stdout and stderr to `log`, extra environment
// `env`), waits, and returns its wall time and peak resident memory.
Run run(const std::vector<std::string>& argv, const std::string& log, const std::vector<std::string>& env = {}) {
    std::vector<char*> args;
    for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    std::vector<std::string> envs;
    for (char** e = environ; *e; ++e) envs.emplace_back(*e);
    envs.insert(envs.end(), env.begin(), env.end());
    std::vector<char*> envp;
    for (std::string& e : envs) envp.push_back(e.data());
    envp.push_back(nullptr);
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_addopen(&fa, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(&fa, 1, 2);
    const auto t0 = std::chrono::steady_clock::now();
    pid_t pid = 0;
    if (posix_spawn(&pid, args[0], &fa, nullptr, args.data(), envp.data()) != 0) die("cannot start " + argv[0]);
    posix_spawn_file_actions_destroy(&fa);
    int status = 0;
    rusage ru{};
    if (wait4(pid, &status, 0, &ru) != pid) die("lost the child " + argv[0]);
    Run r;
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    r.peak_mb = double(ru.ru_maxrss) / 1024.0;
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
        std::ifstream in(log);
        std::stringstream s;
        s << in.rdbuf();
        die(argv[0] + " failed:\n" + s.str());
    }
    return r;
}

// The shared objects the dynamic loader initialised in one run.
int libraries(const std::vector<std::string>& argv, const std::string& log) {
    run(argv, log, {"LD_DEBUG=files"});
    std::ifstream in(log);
    std::string line;
    int n = 0;
    while (std::getline(in, line))
        if (line.find("calling init:") != std::string::npos) ++n;
    return n;
}

struct Command {
    std::string label, what;
    std::vector<std::string> argv;
    std::vector<double> seconds, peaks;
    int libs = 0;
};

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
    std::string cli, out = ".";
    int reps = 21;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--cli") cli = bench::option_value(argc, argv, i);
        else if (a == "--reps") reps = std::max(1, std::stoi(bench::option_value(argc, argv, i)));
        else if (a == "--out") out = bench::option_value(argc, argv, i);
        else die("unknown option " + a);
    }
    if (cli.empty()) die("--cli PATH is required");
    fs::create_directories(out);
    const std::string dir = out + "/startup_work";
    fs::create_directories(dir);
    // A small frame: the jobs measure the start, not pixels.
    Image img = Image::with_channels({"R", "G", "B", "A"}, Roi{0, 0, 64, 64});
    for (int c = 0; c < 4; ++c)
        for (int y = 0; y < 64; ++y)
            for (int x = 0; x < 64; ++x) img.at(c, x, y) = float((x + y + c) % 7) / 7.0f;
    if (Status st = io::write_flat(dir + "/in.exr", img); !st) die(st.message());
    const std::string in = dir + "/in.exr", log = dir + "/log.txt";

    std::vector<Command> cmds = {
        {"/bin/true", "the exec floor", {"/bin/true"}, {}, {}, 0},
        {"gdof --version", "the CLI started", {cli, "--version"}, {}, {}, 0},
        {"gdof in.exr -o out.exr", "an EXR job (64x64)", {cli, in, "-o", dir + "/out.exr"}, {}, {}, 0},
        {"gdof in.exr -o out.png", "a PNG written: loads the OpenImageIO module", {cli, in, "-o", dir + "/out.png"}, {}, {}, 0},
    };
    for (Command& c : cmds) c.libs = libraries(c.argv, log);
    for (int r = 0; r < reps; ++r)
        for (Command& c : cmds) {
            const Run m = run(c.argv, log);
            c.seconds.push_back(m.seconds);
            c.peaks.push_back(m.peak_mb);
        }

    std::ofstream csv(out + "/startup.csv");
    csv << "command,what,libraries,median_s,min_s,peak_mb\n";
    std::ofstream md(out + "/startup_table.md");
    md << "| command | what | shared objects initialised | median ms | least ms | peak MB |\n|---|---|---|---|---|---|\n";
    for (const Command& c : cmds) {
        const double med = median(c.seconds), least = *std::min_element(c.seconds.begin(), c.seconds.end());
        const double peak = median(c.peaks);
        csv << '"' << c.label << "\",\"" << c.what << "\"," << c.libs << ',' << med << ',' << least << ',' << peak << '\n';
        char row[512];
        std::snprintf(row, sizeof row, "| `%s` | %s | %d | %.1f | %.1f | %.0f |\n", c.label.c_str(), c.what.c_str(), c.libs,
                      med * 1e3, least * 1e3, peak);
        md << row;
        std::fputs(row, stderr);
    }
    const double exr = median(cmds[2].seconds), png = median(cmds[3].seconds);
    char tail[256];
    std::snprintf(tail, sizeof tail, "\nOpenImageIO, loaded for the PNG: +%.0f ms (median over median).\n",
                  (png - exr) * 1e3);
    md << tail;
    std::fputs(tail, stderr);
    fs::remove_all(dir);
    return 0;
}
