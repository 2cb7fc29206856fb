// A pan (tests/bench/run --pan): method 3 on a picture that moves. The
// generated scene at 640x360 (the method benchmark's cached plate and deep
// render: thin poles in front of a checker wall) is moved right by 1..15 px
// inside its frame (as in a pan; the camera and the blur field stay),
// defocused at the method benchmark's thin lens, and moved back. Away from
// the frame's edges that is an exact translation, so a result that follows
// the picture is the same for every shift. (Moving the data window instead
// moves every grid the pipeline lays from it along with the picture, which
// hides what this measures.) For each input (plate + Z at the defaults, the same with one
// layer, the deep render at the defaults), over the frame less 48 px on every
// side (the frame's edges do move): the mean over shifts of the relative L1
// between the moved-back result and the unmoved one, and over the pixels
// of all shifts the 99th percentile and the largest of |difference| /
// (|value| + 0.02) (RGB summed). One layer continues nothing behind nearer
// ones: what moves there is the solver's pyramid (blurs above 6 px solved
// on coarser levels, whose grids stay with the frame).
//
//   bench_pan --out DIR --cache DIR
// Needs the method benchmark's cache (DIR/generated_640x360/pinhole_q.exr and
// deep_q.exr: bench_methods --sizes 640x360 --scenes generated). Writes
// DIR/pan_table.md and pan.csv.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "bench_cli.h"
#include "gdof/deep.h"
#include "gdof/defocus.h"
#include "gdof/image_set.h"
#include "gdof/layers.h"
#include "methods/cached_scene.h"
#include "methods/open_aperture.h"

using namespace gdof;

[[noreturn]] void gdof::bench::die(const std::string& m) {
    std::fprintf(stderr, "bench_pan: %s\n", m.c_str());
    std::exit(1);
}

namespace {

using bench::die;
using bench::take;

constexpr int kW = 640, kH = 360, kShifts = 16, kMargin = 48;

// The picture moved right by dx px inside the same windows (a pan: the
// frame stays, its content moves); the dx columns that enter on the left
// repeat the first one. Pixel (x, y) shows the source's (max(x - dx, x0), y).
int source_x(int x, int dx, const Roi& d) { return std::max(x - dx, d.x0); }

Image moved(const Image& src, int dx) {
    const Roi d = src.data_window();
    Image out(src.channels(), d, src.display_window());
    for (int c = 0; c < src.nchannels(); ++c)
        for (int y = d.y0; y < d.y1; ++y)
            for (int x = d.x0; x < d.x1; ++x) {
                const std::size_t i = out.offset(x, y), j = src.offset(source_x(x, dx, d), y);
                if (src.plane(c)) out.plane(c)[i] = src.plane(c)[j];
                else if (src.uplane(c)) out.uplane(c)[i] = src.uplane(c)[j];
            }
    out.metadata = src.metadata;
    out.name = src.name;
    return out;
}

DeepImage moved(const DeepImage& src, int dx) {
    const Roi d = src.data_window();
    const auto at = [&](int x, int y) {
        return std::size_t(y - d.y0) * std::size_t(d.width()) + std::size_t(source_x(x, dx, d) - d.x0);
    };
    std::vector<std::uint32_t> counts(d.npixels());
    for (int y = d.y0; y < d.y1; ++y)
        for (int x = d.x0; x < d.x1; ++x)
            counts[std::size_t(y - d.y0) * std::size_t(d.width()) + std::size_t(x - d.x0)] = src.sample_count(at(x, y));
    DeepImage out(src.channels(), d, src.display_window());
    if (Status st = out.set_sample_counts(counts); !st) die(st.message());
    for (int c = 0; c < src.nchannels(); ++c) {
        const bool u = src.channel(c).type == PixelType::UInt;
        std::size_t o = 0;
        for (int y = d.y0; y < d.y1; ++y)
            for (int x = d.x0; x < d.x1; ++x) {
                const std::size_t j = at(x, y), first = src.first_sample(j), n = src.sample_count(j);
                if (u) std::copy_n(src.usamples(c) + first, n, out.usamples(c) + o);
                else std::copy_n(src.samples(c) + first, n, out.samples(c) + o);
                o += n;
            }
    }
    out.metadata = src.metadata;
    out.name = src.name;
    return out;
}

ImageSet moved(const ImageSet& s, int dx) {
    ImageSet out = s;
    for (std::size_t i = 0; i < s.parts.size(); ++i) {
        if (s.is_deep(i)) out.parts[i] = moved(s.deep(i), dx);
        else out.parts[i] = moved(s.flat(i), dx);
    }
    return out;
}

}  // namespace

int main(int argc, char** argv) {
    const bench::OutAndCache args = bench::out_and_cache(argc, argv);
    const std::string& out = args.out;
    const bench::CachedScene cached = bench::cached_scene(args.cache, "generated", kW, kH);
    const Camera& cam = cached.scene.camera;
    const ImageSet &plate = cached.plate, &deep = cached.deep;
    const std::string& dir = cached.dir;

    // The method benchmark's thin lens: 10 px of blur at the nearest depths.
    ThinLens lens = take(cam.thin_lens(), "scene camera");
    lens.f_number =
        bench::open_f_number(cam, kW / 640.0, bench::depth_range(plate.flat(0), dir + "/pinhole_q.exr").near);
    const BlurField field = take(BlurField::from_thin_lens(lens), "thin lens");
    std::fprintf(stderr, "pan: f/%.6g, focus %.3g m, shifts 0..%d px\n", lens.f_number, lens.focus_distance,
                 kShifts - 1);

    struct Input {
        std::string name;
        const ImageSet* set;
        LayerSplit split;
    };
    const std::vector<Input> inputs{{"plate + Z, defaults", &plate, {}},
                                    {"plate + Z, one layer", &plate, take(parse_layer_split("1"), "layers")},
                                    {"deep, defaults", &deep, {}}};
    std::ofstream csv(out + "/pan.csv");
    csv << "input,shift_px,rel_l1\n";
    std::ostringstream t;
    t << "| input | moved back vs unmoved, rel L1 (mean over shifts) | worst shift | pixel p99 | pixel max |\n"
         "|---|---:|---:|---:|---:|\n";
    for (const Input& input : inputs) {
        DefocusOptions o;
        o.split = input.split;
        const Image base = take(defocus(*input.set, field, cam, o), input.name).flat(0);
        std::vector<double> rel(kShifts, 0.0);
        std::vector<float> dev;  // per pixel and shift
        for (int dx = 1; dx < kShifts; ++dx) {
            const Image r = take(defocus(moved(*input.set, dx), field, cam, o), input.name).flat(0);
            double d = 0, n = 0;
            for (int y = kMargin; y < kH - kMargin; ++y)
                for (int x = kMargin; x < kW - kMargin - kShifts; ++x) {
                    double dp = 0, np = 0;
                    for (int c = 0; c < 3; ++c) {
                        const double b = base.sample(c, x, y);  // 0 outside the data window
                        dp += std::fabs(double(r.sample(c, x + dx, y)) - b);
                        np += std::fabs(b);
                    }
                    d += dp;
                    n += np;
                    dev.push_back(float(dp / (np + 0.02)));
                }
            rel[std::size_t(dx)] = d / std::max(n, 1e-30);
            csv << "\"" << input.name << "\"," << dx << "," << rel[std::size_t(dx)] << "\n";
        }
        double mean = 0;
        for (int dx = 1; dx < kShifts; ++dx) mean += rel[std::size_t(dx)] / double(kShifts - 1);
        const auto worst = std::max_element(rel.begin(), rel.end()) - rel.begin();
        std::sort(dev.begin(), dev.end());
        const double p99 = dev[dev.size() * 99 / 100], mx = dev.back();
        char row[512];
        std::snprintf(row, sizeof row, "| %s | %.6f | %.6f (%d px) | %.4f | %.4f |\n", input.name.c_str(), mean,
                      rel[std::size_t(worst)], int(worst), p99, mx);
        t << row;
        std::fprintf(stderr, "%s", row);
    }
    std::ofstream(out + "/pan_table.md") << t.str();
    std::fprintf(stderr, "%s", t.str().c_str());
    return 0;
}
