// Photographed focus sweeps: the time of align_sweep and depth_from_focus
// against a plain copy of the sweep's frames in the same run (the memory
// floor of anything that reads every frame), on an analytic sweep
// (tests/unit/focus_sweep/sweep_test_helpers.h) at 1920x1080 and on the real
// keyboard sweep when ../shared/data is there.
//
//   bench_focus_sweep [--reps N] [--frames N] [--size WxH] [--keyboard DIR] [--out DIR]
//
// Writes DIR/focus_sweep.csv and DIR/focus_sweep_table.md. Each measure is
// the median of N runs (default 5); the machine is shared and noisy.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "gdof/focus_sweep.h"
#include "gdof/io/image_io.h"
#include "unit/focus_sweep/sweep_test_helpers.h"

namespace {

double now() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

[[noreturn]] void die(const std::string& m) {
    std::fprintf(stderr, "bench_focus_sweep: %s\n", m.c_str());
    std::exit(1);
}

struct Row {
    std::string input;
    int width = 0, height = 0, frames = 0;
    double copy = 0, align = 0, dff = 0;
};

Row measure(const std::string& input, const std::vector<gdof::Image>& frames, const std::vector<double>& focus, int reps) {
    Row row{input, frames[0].width(), frames[0].height(), int(frames.size())};
    std::vector<double> copies, aligns, dffs;
    for (int r = 0; r < reps; ++r) {
        double t = now();
        std::vector<gdof::Image> copy = frames;
        copies.push_back(now() - t);
        t = now();
        auto a = gdof::align_sweep(copy);
        aligns.push_back(now() - t);
        if (!a) die(input + ": " + a.message());
        t = now();
        auto d = gdof::depth_from_focus(copy, focus);
        dffs.push_back(now() - t);
        if (!d) die(input + ": " + d.message());
    }
    row.copy = median(copies);
    row.align = median(aligns);
    row.dff = median(dffs);
    std::fprintf(stderr, "%s %dx%d x %d: copy %.3f s, align %.3f s (%.0fx), depth from focus %.3f s (%.0fx)\n",
                 input.c_str(), row.width, row.height, row.frames, row.copy, row.align, row.align / row.copy, row.dff,
                 row.dff / row.copy);
    return row;
}

}  // namespace

int main(int argc, char** argv) {
    int reps = 5, nframes = 16, w = 1920, h = 1080;
    std::string keyboard, out = ".";
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto next = [&]() -> std::string {
            if (i + 1 >= argc) die(a + " needs a value");
            return argv[++i];
        };
        if (a == "--reps") reps = std::max(1, std::atoi(next().c_str()));
        else if (a == "--frames") nframes = std::max(3, std::atoi(next().c_str()));
        else if (a == "--size") {
            if (std::sscanf(next().c_str(), "%dx%d", &w, &h) != 2) die("--size WxH");
        } else if (a == "--keyboard") keyboard = next();
        else if (a == "--out") out = next();
        else die("unknown argument " + a);
    }
    std::vector<Row> rows;
    {
        auto s = sweep_test::make_sweep(std::size_t(nframes));
        s.width = w;
        s.height = h;
        s.sigma_per_dioptre = 4.0 * w / 320.0;  // the tests' blur in proportion to the frame
        std::vector<gdof::Image> frames;
        for (std::size_t k = 0; k < s.focus.size(); ++k) frames.push_back(s.frame(k));
        rows.push_back(measure("analytic", frames, s.focus, reps));
    }
    if (!keyboard.empty() && std::filesystem::exists(keyboard + "/00.jpg")) {
        std::vector<gdof::Image> frames;
        for (int k = 0; k < 32; ++k) {
            char name[32];
            std::snprintf(name, sizeof name, "/%02d.jpg", k);
            auto r = gdof::io::read_flat(keyboard + name);
            if (!r) die(r.message());
            frames.push_back(std::move(r).value());
        }
        rows.push_back(measure("keyboard (real, JPEG)", frames, {}, reps));
    }
    std::filesystem::create_directories(out);
    std::ofstream csv(out + "/focus_sweep.csv");
    csv << "input,width,height,frames,copy_seconds,align_seconds,depth_from_focus_seconds\n";
    std::ofstream md(out + "/focus_sweep_table.md");
    md << "| sweep | frames | copy of the frames (s) | align_sweep (s) | x copy | depth_from_focus (s) | x copy | ms per "
          "frame (both) |\n|---|---|---|---|---|---|---|---|\n";
    for (const Row& r : rows) {
        csv << r.input << "," << r.width << "," << r.height << "," << r.frames << "," << r.copy << "," << r.align << ","
            << r.dff << "\n";
        char b[400];
        std::snprintf(b, sizeof b, "| %s %dx%d | %d | %.3f | %.3f | %.0f | %.3f | %.0f | %.0f |\n", r.input.c_str(),
                      r.width, r.height, r.frames, r.copy, r.align, r.align / r.copy, r.dff, r.dff / r.copy,
                      1000.0 * (r.align + r.dff) / r.frames);
        md << b;
    }
    return 0;
}
