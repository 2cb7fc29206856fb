// A focus pull (tests/bench/run --focus-pull): method 3 over a frame
// sequence, as a compositor renders it, against the ray tracer frame by
// frame. Cornell box at 640x360 (the method benchmark's scene, its cached
// all-in-focus plate and deep render), the scene camera's thin lens at the
// method benchmark's aperture, focus pulled from 3.0 to 4.5 m in 0.1 m steps
// (16 frames; each frame's truth at 512 spp, cached). For each input
// (plate + Z at the defaults, the same with one layer, the deep render at
// the defaults): per-frame relative L1 (mean, worst) and how steadily it
// moves in time: each frame's second difference |f(k) - (f(k-1) + f(k+1)) / 2|
// (relative L1), whose largest value over its median shows a frame that
// jumps (a flicker) where its neighbours move smoothly. The truths' own
// sampling noise (about 0.04 relative L1 at 512 spp on this scene) is independent per
// frame, so their second differences are not a reference; one layer, whose
// decomposition never changes, is the smooth baseline.
//
//   bench_focus_pull --out DIR --cache DIR
// Needs the method benchmark's cache (DIR/cornell_640x360/pinhole_q.exr and
// deep_q.exr: bench_methods --sizes 640x360 --scenes cornell). Writes
// DIR/focus_pull_table.md and focus_pull.csv.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "bench_cli.h"
#include "gdof/defocus.h"
#include "gdof/io/image_io.h"
#include "gdof/layers.h"
#include "gdof/raytrace.h"
#include "gdof/scene.h"
#include "methods/bench_metrics.h"
#include "methods/cached_scene.h"
#include "methods/open_aperture.h"

using namespace gdof;
namespace fs = std::filesystem;

[[noreturn]] void gdof::bench::die(const std::string& m) {
    std::fprintf(stderr, "bench_focus_pull: %s\n", m.c_str());
    std::exit(1);
}

namespace {

using bench::die;
using bench::take;

constexpr int kW = 640, kH = 360;

// |mid - (prev + next) / 2| over |mid|, summed over RGB.
double second_difference(const Image& prev, const Image& mid, const Image& next) {
    double d = 0, n = 0;
    for (int c = 0; c < 3; ++c)
        for (std::size_t i = 0; i < mid.npixels(); ++i) {
            const double m = mid.plane(c)[i];
            d += std::fabs(m - 0.5 * (double(prev.plane(c)[i]) + double(next.plane(c)[i])));
            n += std::fabs(m);
        }
    return d / std::max(n, 1e-30);
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const std::size_t m = v.size() / 2;
    return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

}  // namespace

int main(int argc, char** argv) {
    const bench::OutAndCache args = bench::out_and_cache(argc, argv);
    const std::string& out = args.out;
    const bench::CachedScene cached = bench::cached_scene(args.cache, "cornell", kW, kH);
    const Scene& scene = cached.scene;
    const std::string &path = cached.path, &dir = cached.dir;
    const auto tracer = take(RayTracer::build(scene), "building " + path);
    const Camera& cam = scene.camera;
    const Roi frame = cam.display_window();
    const ImageSet &plate = cached.plate, &deep = cached.deep;

    // The method benchmark's thin-lens aperture: 10 px of blur, with the
    // camera's focus, at the nearest depths (the plate's 2nd percentile).
    const Image& p = plate.flat(0);
    ThinLens lens = take(cam.thin_lens(), "scene camera");
    lens.f_number = bench::open_f_number(cam, kW / 640.0, bench::depth_range(p, dir + "/pinhole_q.exr").near);
    const int zc = p.channel_index("Z");
    std::fprintf(stderr, "focus pull: f/%.6g, focus 3.0 .. 4.5 m\n", lens.f_number);

    struct Input {
        std::string name;
        const ImageSet* set;
        LayerSplit split;
        std::vector<Image> frames;
        std::vector<double> err;
    };
    std::vector<Input> inputs{{"plate + Z, defaults", &plate, {}, {}, {}},
                              {"plate + Z, one layer", &plate, take(parse_layer_split("1"), "layers"), {}, {}},
                              {"deep, defaults", &deep, {}, {}, {}}};
    std::ofstream csv(out + "/focus_pull.csv");
    csv << "focus_m,input,rel_l1,edge_rel_l1,away_rel_l1\n";
    const std::vector<char> edges = bench::discontinuity_mask(p.plane(zc), kW, kH, 4);
    const int nframes = 16;
    for (int k = 0; k < nframes; ++k) {
        ThinLens l = lens;
        l.focus_distance = 3.0 + 0.1 * k;
        const BlurField field = take(BlurField::from_thin_lens(l), "thin lens");
        char name[64];
        std::snprintf(name, sizeof name, "/focus_pull_truth_%.2f_%.4g.exr", l.focus_distance, l.f_number);
        const std::string tp = dir + name;
        if (!fs::exists(tp)) {
            std::fprintf(stderr, "  truth at %.2f m: 512 spp ...\n", l.focus_distance);
            RenderOptions rs;
            rs.spp = 512;
            rs.adaptive_threshold = 0;
            rs.blur_field = &field;
            rs.aovs = RenderAov::None;
            ImageSet s;
            s.parts.emplace_back(take(render(*tracer, rs), "truth"));
            if (Status st = io::write_image(tp, s); !st) die(st.message());
        }
        const Image truth = bench::rgba_over(take(io::read_flat(tp), tp), frame);
        for (Input& input : inputs) {
            DefocusOptions o;
            o.split = input.split;
            ImageSet r = take(defocus(*input.set, field, cam, o), input.name);
            Image img = bench::rgba_over(r.flat(0), frame);
            const bench::ErrorMetrics m = bench::compare(img, truth, edges);
            input.err.push_back(m.rel_l1);
            csv << l.focus_distance << ",\"" << input.name << "\"," << m.rel_l1 << "," << m.edge_rel_l1 << ","
                << m.away_rel_l1 << "\n";
            input.frames.push_back(std::move(img));
        }
        std::fprintf(stderr, "  %.2f m: %.4f / %.4f / %.4f\n", l.focus_distance, inputs[0].err.back(),
                     inputs[1].err.back(), inputs[2].err.back());
    }
    std::ostringstream t;
    t << "| input | rel L1, mean | rel L1, worst (focus) | 2nd difference, median | largest (focus) | largest / median |\n"
         "|---|---:|---:|---:|---:|---:|\n";
    for (const Input& input : inputs) {
        std::vector<double> d2;
        for (int k = 1; k + 1 < nframes; ++k)
            d2.push_back(second_difference(input.frames[std::size_t(k - 1)], input.frames[std::size_t(k)],
                                           input.frames[std::size_t(k + 1)]));
        const auto worst = std::max_element(input.err.begin(), input.err.end()) - input.err.begin();
        const auto jump = std::max_element(d2.begin(), d2.end()) - d2.begin();
        double mean = 0;
        for (double e : input.err) mean += e / double(nframes);
        char row[512];
        std::snprintf(row, sizeof row, "| %s | %.4f | %.4f (%.1f m) | %.4f | %.4f (%.1f m) | %.1f |\n", input.name.c_str(),
                      mean, input.err[std::size_t(worst)], 3.0 + 0.1 * double(worst), median(d2), d2[std::size_t(jump)],
                      3.0 + 0.1 * double(jump + 1), d2[std::size_t(jump)] / median(d2));
        t << row;
    }
    std::ofstream(out + "/focus_pull_table.md") << t.str();
    std::fprintf(stderr, "%s", t.str().c_str());
    return 0;
}
