// The cost of --vibrate (method 4, docs/psf_field.md) against its aperture
// sample count and the largest blur radius, on one input: the two layers of
// the cost benchmarks (a textured background, a foreground disc) at WxH
// under a constant blur R, the default defocus field. Baselines on the same
// layers in the same run: --diffuse (defaults) and --bokeh (disc). Medians
// of 3 (--reps).
//
//   bench_vibrate --out DIR [--size WxH] [--reps N] [--machine TEXT]
// Writes DIR/vibrate_cost.csv and DIR/vibrate_table.md.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "bench_cli.h"
#include "gdof/defocus.h"
#include "methods/cost_scene.h"

using namespace gdof;

[[noreturn]] void gdof::bench::die(const std::string& m) {
    std::fprintf(stderr, "bench_vibrate: %s\n", m.c_str());
    std::exit(1);
}

namespace {

using bench::die;
using bench::median_of;
using bench::take;

// The 1-minute load average (/proc/loadavg): how busy the machine was.
std::string load_average() {
    std::ifstream in("/proc/loadavg");
    std::string one;
    return in >> one ? one : "unknown";
}

const int kRadii[] = {8, 16, 32, 60};
const int kSamples[] = {16, 64, 256, 1024};

}  // namespace

int main(int argc, char** argv) {
    std::string out = "bench_out", machine;
    int W = 320, H = 180, reps = 3;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--out") out = bench::option_value(argc, argv, i);
        else if (a == "--machine") machine = bench::option_value(argc, argv, i);
        else if (a == "--reps") reps = std::max(1, std::atoi(bench::option_value(argc, argv, i).c_str()));
        else if (a == "--size") {
            const std::string s = bench::option_value(argc, argv, i);
            if (std::sscanf(s.c_str(), "%dx%d", &W, &H) != 2 || W < 16 || H < 16) die("bad --size '" + s + "'");
        } else die("unknown argument '" + a + "' (--out DIR [--size WxH] [--reps N] [--machine TEXT])");
    }
    std::filesystem::create_directories(out);
    const Roi frame{0, 0, W, H};
    const std::vector<Layer> layers = bench::cost_layers(frame);
    const Camera cam = bench::cost_camera(frame);
    const std::string load_before = load_average();

    std::ofstream csv(out + "/vibrate_cost.csv");
    csv << "radius,diffuse_s,bokeh_s";
    for (int n : kSamples) csv << ",vibrate_" << n << "_s";
    csv << ",samples_used\n";
    std::ostringstream table;
    table << "**Cost of `--vibrate` against samples and blur** (`tests/bench/run --vibrate`"
          << (machine.empty() ? "" : "; " + machine) << "). The two layers of the cost benchmarks at " << W << "x" << H
          << " (a 16 px checker, a disc in front of it), every pixel blurred by R, the default `defocus` field "
             "with a disc; seconds, medians of "
          << reps << ", through `defocus_layers` (the pipeline of the CLI without reading and writing). "
          << "Baselines in the same run on the same layers: `--diffuse` (defaults) and `--bokeh` (disc).\n\n"
          << "| R (px) | --diffuse | --bokeh |";
    for (int n : kSamples) table << " --vibrate " << n << " |";
    table << " ms per sample (1024) | 1024 / --bokeh |\n|---:|---:|---:|";
    for (std::size_t i = 0; i < std::size(kSamples); ++i) table << "---:|";
    table << "---:|---:|\n";

    for (int R : kRadii) {
        const BlurField field = bench::constant_blur(R);
        auto time = [&](const DefocusOptions& o, DefocusStats* stats = nullptr) {
            return median_of(reps, [&] { take(defocus_layers(layers, field, cam, o, stats), "defocus"); });
        };
        DefocusOptions diffuse, bokeh;
        bokeh.filter = DefocusFilter::Bokeh;
        const double td = time(diffuse), tb = time(bokeh);
        csv << R << "," << td << "," << tb;
        char cell[96];
        std::snprintf(cell, sizeof cell, "| %d | %.3f | %.3f |", R, td, tb);
        table << cell;
        std::fprintf(stderr, "R %2d: diffuse %.3f s, bokeh %.3f s", R, td, tb);
        double tv = 0.0;
        std::string used;
        for (int n : kSamples) {
            DefocusOptions v;
            v.filter = DefocusFilter::Vibrate;
            v.vibrate.samples = n;
            DefocusStats stats;
            tv = time(v, &stats);
            used += (used.empty() ? "" : " ") + std::to_string(stats.vibrate.samples);
            csv << "," << tv;
            std::snprintf(cell, sizeof cell, " %.2f |", tv);
            table << cell;
            std::fprintf(stderr, ", vibrate %d: %.2f s", n, tv);
        }
        csv << "," << used << "\n";
        std::snprintf(cell, sizeof cell, " %.1f | %.0f |\n", 1000.0 * tv / kSamples[std::size(kSamples) - 1], tv / tb);
        table << cell;
        std::fprintf(stderr, " (samples used: %s)\n", used.c_str());
    }
    table << "\nLoad average (1 minute) at the start " << load_before << ", at the end " << load_average()
          << " on its cores (above the core count, other work shared them and the times are inflated).\n";
    table << "\nThe lattice keeps the sample count nearest the one asked for (`vibrate_cost.csv` has the counts used). "
             "Cost grows with the samples (each moves every source pixel once) and with R through the sources: a "
             "layer's content grown by twice its displacement and the footprint's reach.\n";
    std::ofstream(out + "/vibrate_table.md") << table.str();
    std::fprintf(stderr, "wrote %s/vibrate_table.md\n", out.c_str());
    return 0;
}
