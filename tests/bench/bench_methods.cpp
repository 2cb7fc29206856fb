// Run time against error for the three methods (issue: one benchmark across
// the methods). For each scene, resolution and blur field:
//   ground truth   the ray tracer at a high fixed sample count (cached)
//   raytrace       fixed 4..1024 spp and adaptive (caps 16..256)
//   diffusion      adi / explicit on the renderer's deep output and on its
//                  flat image + Z (the live-action path), several layer counts
//   bokeh          the same pipeline with the bokeh filter (disc): deep, flat + Z, degraded Z
//   vibrate        method 4, the PSF field's `defocus` kind (disc) on the same layers: deep and
//                  flat + Z, 16..256 aperture samples and automatic (640x360 only)
//   compositing    stacks of 4..48 ray-traced references, hard pick / soft 3
//   gaussian       cv::GaussianBlur per depth slice (the naive baseline)
// Every result is compared with the ground truth (PSNR, relative L1 / L2,
// SSIM, relative L1 near depth discontinuities) and written as a CSV row.
// Post-process times exclude producing their inputs (pinhole / deep renders,
// stacks), as a compositor receives them; they are the best of 2 runs.
//
//   bench_methods --out DIR --cache DIR [--full] [--prepare] [--scenes a,b]
//                 [--fields a,b] [--methods raytrace,diffusion,bokeh,vibrate,compositing,gaussian]
//                 [--sizes 640x360,1920x1080]
//
// --full adds 1920x1080 (ground truth 256 spp, inputs at 256 spp, a 24
// reference stack at 32 spp, fewer settings: see run_scene) and 1024 spp at
// 640x360. --prepare renders the cache (inputs, stack, ground truths) and
// stops. Scenes: "generated" (examples/render: thin poles in front of a
// checker wall) and "cornell" (Cornell box + bunny from ../shared/data/meshes,
// skipped when absent).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <map>
#include <sstream>

#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "bench_cli.h"
#include "gdof/compositing.h"
#include "gdof/defocus.h"
#include "gdof/focus_surfaces.h"
#include "gdof/io/image_io.h"
#include "gdof/layers.h"
#include "gdof/raytrace.h"
#include "gdof/render_stack.h"
#include "gdof/scene.h"
#include "methods/bench_metrics.h"
#include "methods/degraded_depth.h"
#include "methods/gaussian_layers.h"
#include "methods/one_sample_deep.h"
#include "methods/open_aperture.h"

using namespace gdof;
namespace fs = std::filesystem;
using json = nlohmann::json;

[[noreturn]] void gdof::bench::die(const std::string& what) {
    std::fprintf(stderr, "bench_methods: error: %s\n", what.c_str());
    std::exit(1);
}

namespace {

struct Options {
    std::string out = "bench_out", cache = "bench_cache";
    bool full = false, prepare = false;
    std::vector<std::string> scenes{"generated", "cornell"}, fields{"thin_lens", "two_planes", "region"};
    std::vector<std::string> methods{"raytrace", "diffusion", "bokeh", "vibrate", "compositing", "gaussian"};
    std::vector<std::string> sizes;  // "WxH" (640x360, 1920x1080); empty: by --full
    bool runs(const std::string& m) const { return std::find(methods.begin(), methods.end(), m) != methods.end(); }
};

std::vector<std::string> split(const std::string& s) {
    std::vector<std::string> v;
    std::stringstream ss(s);
    for (std::string t; std::getline(ss, t, ',');) v.push_back(t);
    return v;
}

using bench::die;
using bench::open_f_number;
using bench::take;

double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Best of `n` runs of f (which must produce the same result each time).
template <class F>
double best_time(int n, F&& f) {
    double best = 1e300;
    for (int i = 0; i < n; ++i) {
        const auto t0 = std::chrono::steady_clock::now();
        f();
        best = std::min(best, seconds_since(t0));
    }
    return best;
}

// The scene JSON with another resolution (parsed from its own folder).
Scene load_scene_at(const std::string& path, int w, int h) {
    std::ifstream in(path);
    if (!in) die("cannot read " + path);
    json j = json::parse(in);
    j["camera"]["resolution"] = {w, h};
    return take(parse_scene(j.dump(), fs::path(path).parent_path().string()), path);
}

// Blur fields per scene: the camera's thin lens (physical), two focal planes,
// a sphere of focus. Max blurs scale with the image width.
// The thin lens keeps the scene camera's focus with open_f_number's aperture.
std::string field_json(const std::string& scene, const std::string& field, const Camera& cam, double scale,
                       double znear) {
    const LensInfo& l = cam.lens();
    char b[1024];
    if (field == "thin_lens") {
        const double n = open_f_number(cam, scale, znear);
        std::snprintf(b, sizeof b,
                      R"({"blurfield": {"kind": "thin_lens", "focal_length_mm": %g, "f_number": %g, "focus_distance": %g, "sensor_width_mm": %g}})",
                      l.focal_length_mm, n, l.focus_distance, l.sensor_width_mm);
    } else if (field == "two_planes") {
        // generated: the poles (~3.6) and the checker wall (~10); cornell: the bunny (~3.3) and the back wall (~4.9).
        const bool gen = scene == "generated";
        std::snprintf(b, sizeof b, R"({"blurfield": {"kind": "focal_planes", "depths": [%g, %g], "max_blur": %g, "interpolation": "smooth"}})",
                      gen ? 3.7 : 3.3, gen ? 9.5 : 4.9, 10 * scale);
    } else {
        // A sphere of focus around the middle of the scene; blur outside.
        const bool gen = scene == "generated";
        std::snprintf(b, sizeof b,
                      R"({"blurfield": {"kind": "region", "shape": "sphere", "center": [%g, %g, %g], "radius": %g, "mode": "focus", "blur": %g, "falloff": %g}})",
                      gen ? 0.0 : 0.33, gen ? 0.8 : 0.9, gen ? 0.0 : 0.3, gen ? 1.5 : 0.3, 10 * scale, gen ? 1.5 : 0.4);
    }
    return b;
}

struct Row {
    std::string scene, field, method, setting;
    int w = 0, h = 0;
    double seconds = 0;
    bench::ErrorMetrics m;
    std::uint64_t rays = 0;
};

class Csv {
public:
    explicit Csv(const std::string& path) : out_(path) {
        out_ << "scene,width,height,field,method,setting,seconds,psnr,rel_l1,rel_l2,ssim,edge_rel_l1,away_rel_l1,primary_rays\n";
    }
    void add(const Row& r) {
        char b[512];
        std::snprintf(b, sizeof b, "%s,%d,%d,%s,%s,%s,%.6g,%.4f,%.6g,%.6g,%.5f,%.6g,%.6g,%llu\n", r.scene.c_str(), r.w,
                      r.h, r.field.c_str(), r.method.c_str(), r.setting.c_str(), r.seconds, r.m.psnr, r.m.rel_l1,
                      r.m.rel_l2, r.m.ssim, r.m.edge_rel_l1, r.m.away_rel_l1, (unsigned long long)r.rays);
        out_ << b;
        out_.flush();
        std::fprintf(stderr, "  %-28s %-22s %8.3f s  rel L1 %.4f  edge %.4f  away %.4f  PSNR %.2f  SSIM %.4f\n",
                     r.method.c_str(), r.setting.c_str(), r.seconds, r.m.rel_l1, r.m.edge_rel_l1, r.m.away_rel_l1,
                     r.m.psnr, r.m.ssim);
    }

private:
    std::ofstream out_;
};

// A cached image (EXR in the cache folder) or made now and cached.
Image cached_flat(const std::string& path, const std::function<Image()>& make) {
    if (fs::exists(path)) return take(io::read_flat(path), path);
    Image img = make();
    ImageSet set;
    set.parts.push_back(img);
    if (Status st = io::write_image(path, set); !st) die(st.message());
    return img;
}

struct Picture {  // for the error-map grid
    std::string label;
    Image image;
};

void write_grid(const std::string& png, const Image& truth, const std::vector<Picture>& pics, double scale) {
    auto label = [](cv::Mat m, const std::string& text) {
        cv::putText(m, text, {6, 20}, cv::FONT_HERSHEY_SIMPLEX, 0.55, {255, 255, 255}, 2);
        cv::putText(m, text, {6, 20}, cv::FONT_HERSHEY_SIMPLEX, 0.55, {0, 0, 0}, 1);
        return m;
    };
    std::vector<cv::Mat> top{label(bench::preview(truth), "ground truth")};
    std::vector<cv::Mat> bottom{cv::Mat::zeros(top.back().size(), top.back().type())};
    cv::putText(bottom.back(), "|error|, 0 .. " + std::to_string(scale).substr(0, 4), {6, 20}, cv::FONT_HERSHEY_SIMPLEX,
                0.55, {255, 255, 255}, 1);
    for (const Picture& p : pics) {
        top.push_back(label(bench::preview(p.image), p.label));
        bottom.push_back(bench::error_map(p.image, truth, scale));
    }
    cv::Mat a, b, all;
    cv::hconcat(top, a);
    cv::hconcat(bottom, b);
    cv::vconcat(a, b, all);
    if (all.cols > 2400) cv::resize(all, all, {}, 2400.0 / all.cols, 2400.0 / all.cols, cv::INTER_AREA);
    cv::imwrite(png, all);
}

void run_scene(const Options& opt, const std::string& name, const std::string& path, int W, int H, Csv& csv) {
    std::fprintf(stderr, "== %s %dx%d\n", name.c_str(), W, H);
    const Scene scene = load_scene_at(path, W, H);
    const auto tracer = take(RayTracer::build(scene), "building " + path);
    const Camera& cam = scene.camera;
    const double scale = W / 640.0;
    const bool big = W > 1000;  // 1920x1080: fewer, cheaper settings (see the header)
    const int reps = big ? 1 : 2;  // best of `reps` runs for post-process timings
    const std::string cdir = opt.cache + "/" + name + "_" + std::to_string(W) + "x" + std::to_string(H);
    fs::create_directories(cdir);

    // Inputs of the post-process methods: the all-in-focus render (flat + Z/P) and its deep form.
    // Inputs as clean as the ground truth (a compositor's plates are not noisy).
    RenderOptions in;
    in.pinhole = true;
    in.spp = big ? 256 : 1024;
    in.adaptive_threshold = 0.002;
    in.min_spp = big ? 16 : 64;
    const Image pinhole = cached_flat(cdir + "/pinhole_q.exr", [&] { return take(render(*tracer, in), "pinhole"); });
    DeepImage deep;
    {
        const std::string dp = cdir + "/deep_q.exr";
        if (!fs::exists(dp)) {
            ImageSet s;
            s.parts.emplace_back(take(render_deep(*tracer, in), "deep"));
            if (Status st = io::write_image(dp, s); !st) die(st.message());
        }
        deep = take(io::read_image(dp), dp).deep(0);
    }
    const int zc = pinhole.channel_index("Z");
    const std::vector<char> edges = bench::discontinuity_mask(pinhole.plane(zc), W, H, int(std::lround(4 * scale)));

    // The stack: 12 focus distances (evenly in 1/distance over the scene's
    // depth range) x 4 f-numbers (the thin-lens field's open aperture N and
    // 2N, 4N, 8N), rendered once; smaller stacks are subsets. 1920x1080: the
    // first two f-numbers only (24 references).
    const auto [znear, zfar] = bench::depth_range(pinhole, "pinhole render");
    const double n0 = open_f_number(cam, scale, znear);
    const int nf = big ? 2 : 4;
    RenderStackOptions spec;
    for (int i = 0; i < 12; ++i)
        for (int k = 0; k < nf; ++k) {
            const double t = i / 11.0;
            spec.references.push_back({1.0 / ((1 - t) / znear + t / zfar), n0 * (1 << k)});
        }
    const FocalStack plan = take(plan_render_stack(cam, spec), "stack plan");
    std::vector<Image> refs;
    if (opt.runs("compositing")) {  // --prepare --methods diffusion,... renders no stack
        RenderOptions rs;
        rs.spp = big ? 32 : 128;
        rs.min_spp = big ? 8 : 16;
        rs.adaptive_threshold = 0.01;
        rs.aovs = RenderAov::None;
        for (std::size_t i = 0; i < plan.references.size(); ++i) {
            const std::string p = cdir + "/stack_f" + std::to_string(nf) + "_" + std::to_string(i) + ".exr";
            refs.push_back(cached_flat(p, [&] {
                RenderOptions r = rs;
                LensInfo l = cam.lens();
                l.f_number = plan.references[i].f_number;
                l.focus_distance = plan.references[i].focus_distance;
                r.lens = l;
                return take(render(*tracer, r), "stack reference");
            }));
        }
    }

    for (const std::string& fname : opt.fields) {
        std::fprintf(stderr, "-- field %s\n", fname.c_str());
        const std::string fj = field_json(name, fname, cam, scale, znear);
        std::fprintf(stderr, "   %s\n", fj.c_str());
        const BlurField field = take(BlurField::parse(fj), fname);
        const int gt_spp = big ? 256 : 1024;
        const std::string key = std::to_string(std::hash<std::string>{}(fj) % 1000000007u);  // the cache follows the field
        const Roi frame = cam.display_window();
        // The field traced at `spp` (threshold 0: fixed), colour only.
        auto traced = [&](int spp, double threshold, int min_spp) {
            RenderOptions rs;
            rs.spp = spp;
            rs.adaptive_threshold = threshold;
            rs.min_spp = min_spp;
            rs.blur_field = &field;
            rs.aovs = RenderAov::None;
            return rs;
        };
        const Image truth = bench::rgba_over(cached_flat(cdir + "/truth_" + fname + "_" + key + ".exr", [&] {
            std::fprintf(stderr, "  ground truth: %d spp ...\n", gt_spp);
            RenderOptions rs = traced(gt_spp, 0, RenderOptions{}.min_spp);
            rs.seed = 0x5eed;
            return take(render(*tracer, rs), "ground truth");
        }), frame);
        if (opt.prepare) continue;
        auto row = [&](const std::string& method, const std::string& setting, double secs, const Image& img,
                       std::uint64_t rays = 0) {
            Row r{name, fname, method, setting, W, H, secs, bench::compare(bench::rgba_over(img, frame), truth, edges), rays};
            csv.add(r);
        };
        std::map<std::string, Image> best;  // for the picture grid

        // Ray tracing.
        std::vector<int> fixed = {4, 16, 64, 256};
        if (opt.full) fixed.push_back(1024);
        if (!opt.runs("raytrace")) fixed.clear();
        for (int spp : fixed) {
            if (big ? spp >= gt_spp : spp > gt_spp) continue;  // 1024 at 640x360 (--full): the ground truth's own noise
            RenderStats st;
            Image img = take(render(*tracer, traced(spp, 0, RenderOptions{}.min_spp), &st), "raytrace");
            row("raytrace fixed", "spp=" + std::to_string(spp), st.seconds, img, st.primary_rays);
        }
        for (int cap : {16, 64, 256}) {
            if (!opt.runs("raytrace") || (big && cap > 64)) continue;
            RenderStats st;
            Image img = take(render(*tracer, traced(cap, RenderOptions{}.adaptive_threshold, RenderOptions{}.min_spp), &st),
                             "raytrace adaptive");  // the product's stop rule and defaults
            row("raytrace adaptive", "cap=" + std::to_string(cap), st.seconds, img, st.primary_rays);
            if (cap == 64) best["raytrace adaptive 64"] = bench::rgba_over(img, frame);
        }

        // Diffusion (method 3) on the deep render and on flat + Z.
        ImageSet deep_set, flat_set, degraded_set;
        deep_set.parts.emplace_back(deep);
        flat_set.parts.emplace_back(pinhole);
        // Live action as it comes from a sensor: the same plate with a
        // degraded depth map (holes, noise, uint16 millimetres).
        bench::DegradedDepthStats dstats;
        degraded_set.parts.emplace_back(bench::degraded_depth(pinhole, scale, 0xdefec7, &dstats));
        // What a perfect plate holds (methods/one_sample_deep.h), through the deep path.
        ImageSet one_sample_set;
        one_sample_set.parts.emplace_back(bench::one_sample_deep(deep));
        std::fprintf(stderr, "   degraded depth: %.1f%% holes\n", 100.0 * dstats.hole_fraction);
        // Settings: ADI sub-steps K (0 = automatic) or the explicit solver's
        // safety factor on its iteration count (1 = the stability limit).
        struct Diff {
            std::string input, layers;
            DiffusionSolver solver;
            int adi_steps = 0;
            double safety = 0;  // 0: the default
            bool big = true;    // also run at 1920x1080
            bool bokeh = false; // --bokeh (disc aperture, as the ground truth's lens) instead of diffusion
            bool full_res = false;  // auto without the pyramid: the previous default, as a baseline of the same run
        };
        const auto Adi = DiffusionSolver::Adi;
        const auto Exp = DiffusionSolver::Explicit;
        const auto Auto = DiffusionSolver::Auto;  // the default: per layer, the cheaper of the two
        std::vector<Diff> diffs = {
            {"deep", "auto", Auto},         {"deep", "8", Auto},                {"flat+Z", "auto", Auto},
            {"deep", "auto", Adi},          {"deep", "auto:gaps", Adi, 0, 0, false}, {"deep", "auto", Adi, 4, 0, false}, {"deep", "auto", Adi, 16, 0, false},
            {"deep", "4", Adi},             {"deep", "8", Adi},                 {"deep", "16", Adi, 0, 0, false},
            {"deep", "auto", Exp, 0, 0, false}, {"deep", "8", Exp, 0, 1.0, false},  {"deep", "8", Exp},
            {"deep", "8", Exp, 0, 2.0, false},
            {"flat+Z", "auto", Adi},        {"flat+Z", "auto:blur", Adi, 0, 0, false}, {"flat+Z", "8", Adi},               {"flat+Z", "16", Adi, 0, 0, false},
            {"flat+Z", "8", Exp, 0, 0, false},
            {"flat+Z", "1", Auto},  // one layer: what a continuous surface looks like uncut (seams)
            {"degraded Z", "auto", Auto},
            {"one-sample deep", "auto", Auto},
            // The previous default (every layer at full resolution) beside today's.
            {"deep", "auto", Auto, 0, 0, true, false, true}, {"flat+Z", "auto", Auto, 0, 0, true, false, true},
            {"degraded Z", "auto", Auto, 0, 0, true, false, true},
            // The same pipeline with the bokeh filter (the truth's aperture is a disc).
            {"deep", "auto", Auto, 0, 0, true, true}, {"flat+Z", "auto", Auto, 0, 0, true, true},
            {"degraded Z", "auto", Auto, 0, 0, true, true},
        };
        for (const Diff& d : diffs) {
            if (big && !d.big) continue;
            if (!opt.runs(d.bokeh ? "bokeh" : "diffusion")) continue;
            DefocusOptions ds;
            if (d.bokeh) ds.filter = DefocusFilter::Bokeh;
            ds.diffusion.solver = d.solver;
            // The adi / explicit rows measure the solvers themselves, at full
            // resolution; auto rows run the default pyramid unless full_res.
            ds.diffusion.pyramid = d.solver == Auto && !d.full_res;
            ds.diffusion.adi_steps = d.adi_steps;
            if (d.safety > 0) ds.diffusion.explicit_safety = d.safety;
            ds.split = take(parse_layer_split(d.layers), "layers");
            const ImageSet* input = d.input == "deep"              ? &deep_set
                                    : d.input == "flat+Z"          ? &flat_set
                                    : d.input == "one-sample deep" ? &one_sample_set
                                                                   : &degraded_set;
            if (input == &degraded_set) ds.source.depth_decode = DepthDecode{DepthEncoding::Scaled, 1.0 / 1000.0};
            ImageSet result;
            const double secs = best_time(reps, [&] { result = take(defocus(*input, field, cam, ds), "defocus"); });
            const std::string method = d.bokeh ? "bokeh (" + d.input + ")"
                                               : std::string("diffusion ") + to_string(d.solver) +
                                                     (d.full_res ? " full-res" : "") + " (" + d.input + ")";
            char safety[32] = "";
            if (d.safety > 0) std::snprintf(safety, sizeof safety, " s=%g", d.safety);
            const std::string setting =
                "layers=" + d.layers + (d.adi_steps ? " K=" + std::to_string(d.adi_steps) : "") + safety;
            row(method, setting, secs, result.flat(0));
            if (d.bokeh || d.full_res) continue;
            if (d.input == "deep" && d.layers == "auto" && d.solver == Auto && d.adi_steps == 0)
                best["diffusion auto (deep)"] = bench::rgba_over(result.flat(0), frame);
            if (d.input != "deep" && d.layers == "auto")
                best["diffusion auto (" + d.input + ")"] = bench::rgba_over(result.flat(0), frame);
        }

        // Method 4: the PSF field's thin-lens special case (`defocus`, disc)
        // against sample count; at 640x360 only (its cost grows with the
        // samples times every layer's pixels).
        for (const std::string input : {"deep", "flat+Z"}) {
            if (big || !opt.runs("vibrate")) continue;
            for (int n : {16, 64, 256, 0}) {
                DefocusOptions ds;
                ds.filter = DefocusFilter::Vibrate;
                ds.vibrate.samples = n;
                const ImageSet* src = input == "deep" ? &deep_set : &flat_set;
                ImageSet result;
                DefocusStats st;
                const double secs = best_time(reps, [&] { result = take(defocus(*src, field, cam, ds, &st), "vibrate"); });
                row("vibrate (" + input + ")", "samples=" + (n ? std::to_string(n) : "auto:" + std::to_string(st.vibrate.samples)),
                    secs, result.flat(0));
            }
        }

        // Compositing (method 2): desired near/far from the field and the pinhole Z.
        BlurFocusOptions bfs;
        bfs.coc_px = plan.coc_px;
        const DesiredFocus desired = take(desired_from_blur_field(field, cam, pinhole, bfs), "desired focus");
        for (int n : {4, 8, 16, 24, 48}) {
            if (!opt.runs("compositing") || n > 12 * nf) continue;
            // Subsets: n <= 12: n focus distances at the scene's f-number;
            // more: 12 distances x the first n / 12 f-numbers.
            std::vector<int> pick;
            if (n <= 12) {
                for (int k = 0; k < n; ++k) pick.push_back(nf * int(std::lround(k * 11.0 / std::max(1, n - 1))));
            } else {
                for (int i = 0; i < 12; ++i)
                    for (int f = 0; f < n / 12; ++f) pick.push_back(nf * i + f);
            }
            std::vector<DepthInterval> iv;
            std::vector<const Image*> imgs;
            for (int k : pick) iv.push_back({plan.references[std::size_t(k)].near, plan.references[std::size_t(k)].far}),
                imgs.push_back(&refs[std::size_t(k)]);
            const StackIndex index = take(StackIndex::build(iv), "stack index");
            for (int soft : {1, 3}) {
                CompositeOptions cs;
                cs.soft_k = soft;
                Image out;
                const double secs = best_time(reps, [&] {
                    MemoryStackPixels px(imgs);
                    StackSelection sel = take(select_references(index, desired, cs), "select");
                    out = take(composite_stack(sel, px, cs), "composite");
                });
                row(soft == 1 ? "compositing hard" : "compositing soft3", "refs=" + std::to_string(n), secs, out);
                if (n == 48 && soft == 1) best["compositing 48 hard"] = bench::rgba_over(out, frame);
            }
        }

        // The naive baseline: per-slice Gaussian blur.
        for (int slices : {4, 8, 16}) {
            if (!opt.runs("gaussian")) break;
            Image out;
            const double secs =
                best_time(reps, [&] { out = take(bench::gaussian_layers(pinhole, field, cam, slices), "gaussian"); });
            row("gaussian layers (cv)", "slices=" + std::to_string(slices), secs, out);
            if (slices == 8) best["gaussian 8 slices"] = bench::rgba_over(out, frame);
        }

        if (!big) {
            std::vector<Picture> pics;
            for (const char* k : {"raytrace adaptive 64", "diffusion auto (deep)", "diffusion auto (flat+Z)",
                                  "diffusion auto (degraded Z)", "compositing 48 hard", "gaussian 8 slices"})
                if (best.count(k)) pics.push_back({k, best[k]});
            write_grid(opt.out + "/errors_" + name + "_" + fname + ".png", truth, pics, 0.1);
        }
    }
}

}  // namespace

int main(int argc, char** argv) {
    Options opt;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto next = [&] { return bench::option_value(argc, argv, i); };
        if (a == "--out") opt.out = next();
        else if (a == "--cache") opt.cache = next();
        else if (a == "--full") opt.full = true;
        else if (a == "--prepare") opt.prepare = true;
        else if (a == "--methods") opt.methods = split(next());
        else if (a == "--sizes") opt.sizes = split(next());
        else if (a == "--scenes") opt.scenes = split(next());
        else if (a == "--fields") opt.fields = split(next());
        else die("unknown argument '" + a + "' (--out DIR --cache DIR [--full] [--prepare] [--scenes a,b] [--fields a,b] [--methods a,b] [--sizes WxH,...])");
    }
    fs::create_directories(opt.out);
    fs::create_directories(opt.cache);
    Csv csv(opt.out + "/results.csv");
    const std::string examples = GDOF_SOURCE_DIR "/examples/render/";
    std::vector<std::pair<int, int>> sizes = {{640, 360}};
    if (opt.full) sizes.push_back({1920, 1080});
    if (!opt.sizes.empty()) {
        sizes.clear();
        for (const std::string& t : opt.sizes) {
            int w = 0, h = 0;
            if (std::sscanf(t.c_str(), "%dx%d", &w, &h) != 2 || w < 16 || h < 16 || w > 8192 || h > 8192)
                die("--sizes: '" + t + "' is not WxH (16..8192)");
            sizes.push_back({w, h});
        }
    }
    for (const std::string& s : opt.scenes) {
        const std::string path = examples + s + ".json";
        if (s == "cornell" && !fs::exists(GDOF_SOURCE_DIR "/../shared/data/meshes/CornellBox-Original.obj")) {
            std::fprintf(stderr, "skipping cornell: ../shared/data/meshes is absent\n");
            continue;
        }
        for (auto [w, h] : sizes) run_scene(opt, s, path, w, h, csv);
    }
    return 0;
}
