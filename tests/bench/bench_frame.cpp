// One production frame, timed whole (issue: production speed): the post path
// (`defocus()`: layers, blur maps, extension, solve, composite) on a flat
// RGBA + Z frame and on a deep frame, with its peak memory, next to a
// bandwidth reference measured in the same run: one copy of an 8-layer RGBA
// float stack of the frame's size (what a pass over all layers costs at the
// memory's speed), and the first touch of that much fresh memory (each
// configuration faults in its own peak once; on the benchmark's virtual
// machine this ran anywhere from 0.1 to 8 GB/s within an hour, the main
// source of the rows' spread). Every configuration runs in its own child
// process, so its peak resident memory is its own; times are medians of
// --reps runs. Reading the input and writing the result (as the CLI does:
// the input's compression) are timed apart, in the same child.
//
//   bench_frame --flat F.exr --deep D.exr --field FIELD.json --layers 8
//               [--reps 3] [--out DIR] [--rows default,full-res,bokeh]
//
// Rows: "diffusion (default)" (the pyramid), "diffusion full-res"
// (pyramid off: the previous default, once, as the baseline), "bokeh".
// Writes DIR/frame.csv and DIR/frame_table.md.
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "bench_cli.h"
#include "gdof/camera.h"
#include "gdof/defocus.h"
#include "gdof/io/image_io.h"

using namespace gdof;

[[noreturn]] void gdof::bench::die(const std::string& m) {
    std::fprintf(stderr, "bench_frame: %s\n", m.c_str());
    std::exit(2);
}

namespace {

using bench::die;
using bench::take;

double now() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v[v.size() / 2];
}

struct Measure {
    double seconds = 0, peak_mb = 0;
    std::string detail;  // e.g. the stats' solve time
};

// Runs f in a child process; f writes its result to the pipe as text
// "seconds detail"; the child's peak RSS comes from wait4.
template <class F>
Measure in_child(F&& f) {
    int fd[2];
    if (pipe(fd) != 0) die("pipe failed");
    const pid_t pid = fork();
    if (pid < 0) die("fork failed");
    if (pid == 0) {
        close(fd[0]);
        const std::string out = f();
        if (write(fd[1], out.data(), out.size()) < 0) _exit(3);
        close(fd[1]);
        _exit(0);
    }
    close(fd[1]);
    std::string text;
    char buf[512];
    for (ssize_t k; (k = read(fd[0], buf, sizeof buf)) > 0;) text.append(buf, std::size_t(k));
    close(fd[0]);
    int status = 0;
    rusage ru{};
    wait4(pid, &status, 0, &ru);
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) die("a measurement failed: " + text);
    Measure m;
    std::istringstream is(text);
    is >> m.seconds;
    std::getline(is, m.detail);
    if (!m.detail.empty() && m.detail[0] == ' ') m.detail.erase(0, 1);
    m.peak_mb = double(ru.ru_maxrss) / 1024.0;
    return m;
}

struct Options {
    std::string flat, deep, field, layers = "8", out = ".";
    std::string rows = "default,full-res,bokeh";  // which configurations to time
    int reps = 3;
};

}  // namespace

int main(int argc, char** argv) {
    keep_freed_memory();  // as the gdof CLI does
    Options opt;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto next = [&] { return bench::option_value(argc, argv, i); };
        if (a == "--flat") opt.flat = next();
        else if (a == "--deep") opt.deep = next();
        else if (a == "--field") opt.field = next();
        else if (a == "--layers") opt.layers = next();
        else if (a == "--reps") opt.reps = std::max(1, std::atoi(next().c_str()));
        else if (a == "--out") opt.out = next();
        else if (a == "--rows") opt.rows = next();
        else die("unknown argument '" + a + "'");
    }
    if (opt.flat.empty() || opt.deep.empty() || opt.field.empty()) die("--flat, --deep and --field are required");
    std::ifstream fj(opt.field);
    if (!fj) die("cannot read " + opt.field);
    std::stringstream fs;
    fs << fj.rdbuf();
    const std::string field_text = fs.str();
    const int nlayers = std::atoi(opt.layers.c_str());

    // The frame's size, from the flat input's header.
    // (Released before any child starts, so no child inherits its pages.)
    const Roi frame = take(io::read_image(opt.flat), opt.flat).flat(0).display_window();
    const int W = frame.width(), H = frame.height();

    // Bandwidth references: one copy of an nlayers x RGBA float stack, and
    // the first touch of such a stack's fresh memory (the kernel maps and
    // zeroes each page on its first write; on a virtual machine the host may
    // back it only then, so its speed varies from run to run, and every
    // configuration below pays it once for its peak).
    const std::size_t stack_floats = std::size_t(std::max(1, nlayers)) * 4 * frame.npixels();
    const Measure copy = in_child([&] {
        const double t_touch = now();
        std::vector<float> a(stack_floats, 1.0f);
        const double touch = now() - t_touch;
        std::vector<float> b(stack_floats, 0.0f);
        std::vector<double> t;
        for (int r = 0; r < 5; ++r) {
            const double t0 = now();
            std::memcpy(b.data(), a.data(), stack_floats * sizeof(float));
            t.push_back(now() - t0);
        }
        return std::to_string(median(t)) + " " + std::to_string(touch) + " " + std::to_string(b[stack_floats / 2]);
    });
    double touch_seconds = 0;
    std::istringstream(copy.detail) >> touch_seconds;
    const double gb = double(stack_floats) * sizeof(float) / 1e9;
    const double touch_gbs = gb / std::max(touch_seconds, 1e-9);
    std::fprintf(stderr, "copy of a %d-layer RGBA float stack (%.2f GB): %.3f s (%.1f GB/s); first touch of its fresh memory: %.3f s (%.2f GB/s)\n",
                 nlayers, gb, copy.seconds, 2.0 * gb / copy.seconds, touch_seconds, touch_gbs);

    struct Config {
        std::string key, name;
        bool pyramid;
        DefocusFilter filter;
        int reps;
    };
    std::vector<Config> configs;
    for (const Config& c : {Config{"default", "diffusion (default)", true, DefocusFilter::Diffusion, opt.reps},
                            Config{"full-res", "diffusion full-res (previous default)", false, DefocusFilter::Diffusion, 1},
                            Config{"bokeh", "bokeh", true, DefocusFilter::Bokeh, opt.reps}})
        if (("," + opt.rows + ",").find("," + c.key + ",") != std::string::npos) configs.push_back(c);
    if (configs.empty()) die("--rows names none of default, full-res, bokeh");
    std::ofstream csv(opt.out + "/frame.csv");
    csv << "input,method,size,layers,seconds,copy_seconds,x_copy,peak_mb,max_radius,solve_seconds,layers_seconds,read_seconds,"
           "write_seconds\n";
    std::ostringstream md;
    md << "| input | method | s | x copy | peak MB | solve s | layers s | max blur px | read s | write s |\n"
          "|---|---|---|---|---|---|---|---|---|---|\n";
    for (const std::string input : {"flat+Z", "deep"}) {
        const std::string path = input == "deep" ? opt.deep : opt.flat;
        for (const Config& c : configs) {
            std::vector<double> secs, reads, writes;
            Measure last;
            double peak = 0, solve = 0, lay = 0, rmax = 0;
            for (int r = 0; r < c.reps; ++r) {
                last = in_child([&] {
                    const double t_read = now();
                    const ImageSet set = take(io::read_image(path), path);
                    const double read_s = now() - t_read;
                    const Roi display = set.is_deep(0) ? set.deep(0).display_window() : set.flat(0).display_window();
                    const Camera cam = take(resolve_camera(set.metadata(0), display), "camera");
                    const BlurField field = take(BlurField::parse(field_text), opt.field);
                    DefocusOptions s;
                    s.filter = c.filter;
                    s.diffusion.pyramid = c.pyramid;
                    s.split = take(parse_layer_split(opt.layers), "--layers");
                    DefocusStats st;
                    const double t0 = now();
                    const ImageSet out = take(defocus(set, field, cam, s, &st), "defocus");
                    const double t = now() - t0;
                    // The result written as the CLI writes it (the input's
                    // compression), then removed.
                    const std::string written = opt.out + "/frame_" + c.key + (input == "deep" ? "_deep" : "_flat") + ".exr";
                    const double t_write = now();
                    if (Status w = io::write_image(written, out); !w) die(w.message());
                    const double write_s = now() - t_write;
                    std::remove(written.c_str());
                    char d[200];
                    std::snprintf(d, sizeof d, "%.3f %.3f %.2f %.3f %.3f", st.t_diffuse, st.t_layers, st.max_radius_px, read_s,
                                  write_s);
                    return std::to_string(t) + " " + d;
                });
                secs.push_back(last.seconds);
                peak = std::max(peak, last.peak_mb);
                double rd = 0, wr = 0;  // the stats columns are the last run's
                std::istringstream(last.detail) >> solve >> lay >> rmax >> rd >> wr;
                reads.push_back(rd);
                writes.push_back(wr);
            }
            const double t = median(secs), read_s = median(reads), write_s = median(writes);
            std::fprintf(stderr, "%s %s: %.2f s (%.0fx copy), peak %.0f MB, solve %.2f s, layers %.2f s; read %.2f s, write %.2f s\n",
                         input.c_str(), c.name.c_str(), t, t / copy.seconds, peak, solve, lay, read_s, write_s);
            csv << input << "," << c.name << "," << W << "x" << H << "," << opt.layers << "," << t << "," << copy.seconds << ","
                << t / copy.seconds << "," << peak << "," << rmax << "," << solve << "," << lay << "," << read_s << ","
                << write_s << "\n";
            char row[400];
            std::snprintf(row, sizeof row, "| %s | %s | %.2f | %.0f | %.0f | %.2f | %.2f | %.1f | %.2f | %.2f |\n", input.c_str(),
                          c.name.c_str(), t, t / copy.seconds, peak, solve, lay, rmax, read_s, write_s);
            md << row;
        }
    }
    std::ofstream(opt.out + "/frame_table.md") << md.str() << "\nBandwidth reference: one copy of a " << nlayers
                                               << "-layer RGBA float stack at " << W << "x" << H << " (" << gb << " GB) took "
                                               << copy.seconds << " s in the same run; the first touch of that much fresh memory "
                                               << touch_seconds << " s (" << touch_gbs << " GB/s).\n";
    return 0;
}
