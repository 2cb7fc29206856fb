// The bokeh benchmark (tests/bench/run): --bokeh against the ray tracer
// with the same aperture, and its cost against the blur radius.
//
//  1. Highlights scene (examples/render/highlights.json: HDR emitters near,
//     in focus and far, a pole hiding some): the deep all-in-focus render is
//     the input; the ground truths are the ray tracer's thin-lens renders
//     with a disc and with a 6-blade polygon (rotation 15 degrees), 2048 spp. --diffuse
//     (defaults) and --bokeh with each aperture run on the deep input and are
//     compared with each truth: relative L1, and near / away from depth
//     discontinuities. Post-process times: best of 2.
//  2. Cost against R at 1920x1080: two layers (a textured background and a
//     foreground disc) blurred by a constant R in 4 .. 64 px, --diffuse
//     (defaults) against --bokeh disc and hexagon, and a copy of the layers
//     (the memory floor) measured in the same run: medians of 3.
//
//   bench_bokeh --out DIR --cache DIR [--size WxH]
// Writes DIR/bokeh_table.md, bokeh_accuracy.csv, bokeh_cost.csv and
// bokeh_*.png (images and |error| maps).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <numbers>
#include <iomanip>
#include <sstream>

#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "bench_cli.h"
#include "gdof/defocus.h"
#include "gdof/io/image_io.h"
#include "gdof/raytrace.h"
#include "gdof/scene.h"
#include "methods/bench_metrics.h"
#include "methods/cost_scene.h"

using namespace gdof;
namespace fs = std::filesystem;
using json = nlohmann::json;

[[noreturn]] void gdof::bench::die(const std::string& m) {
    std::fprintf(stderr, "bench_bokeh: %s\n", m.c_str());
    std::exit(1);
}

namespace {

using bench::best_of;
using bench::die;
using bench::median_of;
using bench::take;

Image cached(const std::string& path, const std::function<ImageSet()>& make) {
    if (!fs::exists(path)) {
        ImageSet s = make();
        if (Status st = io::write_image(path, s); !st) die(st.message());
    }
    return take(io::read_image(path), path).flat(0);
}

Aperture hexagon() {
    Aperture a;
    a.kind = Aperture::Kind::Polygon;
    a.blades = 6;
    a.rotation_deg = 15.0;
    return a;
}

// Preview with an exposure (highlights are HDR), sRGB-encoded, 8-bit BGR.
cv::Mat exposed(const Image& img, double exposure) {
    Image e = img;
    for (int c = 0; c < 3; ++c)
        for (std::size_t i = 0; i < e.npixels(); ++i) e.plane(c)[i] *= float(exposure);
    return bench::preview(e);
}

void accuracy(const std::string& out, const std::string& cache, int W, int H, std::ostream& table) {
    const std::string path = GDOF_SOURCE_DIR "/examples/render/highlights.json";
    std::ifstream in(path);
    if (!in) die("cannot read " + path);
    json j = json::parse(in);
    j["camera"]["resolution"] = {W, H};
    const Scene scene = take(parse_scene(j.dump(), fs::path(path).parent_path().string()), path);
    const auto tracer = take(RayTracer::build(scene), "building " + path);
    const Camera& cam = scene.camera;
    const Roi frame = cam.display_window();
    const std::string dir = cache + "/highlights_" + std::to_string(W) + "x" + std::to_string(H);
    fs::create_directories(dir);
    std::fprintf(stderr, "== highlights %dx%d\n", W, H);

    RenderOptions pin;
    pin.pinhole = true;
    pin.spp = 256;
    pin.min_spp = 16;
    pin.adaptive_threshold = 0.002;
    const std::string deep_path = dir + "/deep.exr";
    if (!fs::exists(deep_path)) {
        ImageSet s;
        s.parts.emplace_back(take(render_deep(*tracer, pin), "deep input"));
        if (Status st = io::write_image(deep_path, s); !st) die(st.message());
    }
    const ImageSet deep = take(io::read_image(deep_path), deep_path);
    const Image flat = cached(dir + "/pinhole.exr", [&] {
        ImageSet s;
        s.parts.emplace_back(take(render(*tracer, pin), "pinhole"));
        return s;
    });
    const std::vector<char> edges = bench::discontinuity_mask(flat.plane(flat.channel_index("Z")), W, H, 4 * W / 640);

    struct Truth {
        std::string name;
        Aperture aperture;
        Image image;
    };
    std::vector<Truth> truths{{"disc", Aperture{}, {}}, {"hexagon", hexagon(), {}}};
    for (Truth& t : truths) {
        t.image = bench::rgba_over(cached(dir + "/truth_" + t.name + ".exr", [&] {
            std::fprintf(stderr, "  ground truth (%s): 2048 spp ...\n", t.name.c_str());
            RenderOptions r;
            r.spp = 2048;
            r.min_spp = 256;
            r.adaptive_threshold = 0.002;
            r.aperture = t.aperture;
            r.aovs = RenderAov::None;
            r.seed = 0x5eed;
            ImageSet s;
            s.parts.emplace_back(take(render(*tracer, r), "ground truth"));
            return s;
        }), frame);
    }

    const BlurField field = take(BlurField::from_thin_lens(take(cam.thin_lens(), "camera")), "thin lens");
    struct Method {
        std::string name;
        DefocusOptions options;
    };
    std::vector<Method> methods(3);
    methods[0].name = "--diffuse";
    methods[1].name = "--bokeh disc";
    methods[1].options.filter = DefocusFilter::Bokeh;
    methods[2].name = "--bokeh polygon:6:15";
    methods[2].options.filter = DefocusFilter::Bokeh;
    methods[2].options.aperture = hexagon();

    std::ofstream csv(out + "/bokeh_accuracy.csv");
    csv << "width,height,truth,method,seconds,rel_l1,edge_rel_l1,away_rel_l1,psnr\n";
    table << "### Bokeh against the ray tracer with the same aperture\n\n"
          << "Highlights scene (`examples/render/highlights.json`), " << W << "x" << H
          << ", thin lens, deep input; truth: `--render` with the aperture at 2048 spp. Relative L1 (overall / near "
             "depth discontinuities / away from them); time: best of 2.\n\n"
          << "| truth aperture | method | time (s) | rel L1 | edge | away |\n|---|---|---:|---:|---:|---:|\n";
    std::vector<std::pair<std::string, Image>> pics;
    for (const Truth& t : truths) {
        for (const Method& m : methods) {
            ImageSet result;
            const double secs = best_of(2, [&] { result = take(defocus(deep, field, cam, m.options), m.name); });
            const Image img = bench::rgba_over(result.flat(0), frame);
            const bench::ErrorMetrics e = bench::compare(img, t.image, edges);
            char row[512];
            std::snprintf(row, sizeof row, "| %s | %s | %.2f | %.4f | %.4f | %.4f |\n", t.name.c_str(), m.name.c_str(),
                          secs, e.rel_l1, e.edge_rel_l1, e.away_rel_l1);
            table << row;
            csv << W << "," << H << "," << t.name << "," << m.name << "," << secs << "," << e.rel_l1 << ","
                << e.edge_rel_l1 << "," << e.away_rel_l1 << "," << e.psnr << "\n";
            std::fprintf(stderr, "  truth %-8s %-22s %.2f s  rel L1 %.4f  edge %.4f  away %.4f\n", t.name.c_str(),
                         m.name.c_str(), secs, e.rel_l1, e.edge_rel_l1, e.away_rel_l1);
            if ((t.name == "disc" && m.name != "--bokeh polygon:6:15") || (t.name == "hexagon" && m.name == "--bokeh polygon:6:15"))
                pics.push_back({t.name + ": " + m.name, img});
        }
    }
    table << "\n";
    // Pictures: truths and results at an exposure that shows the shapes, and
    // the |error| of the disc results.
    auto label = [](cv::Mat m, const std::string& text) {
        cv::putText(m, text, {6, 20}, cv::FONT_HERSHEY_SIMPLEX, 0.55, {255, 255, 255}, 2);
        cv::putText(m, text, {6, 20}, cv::FONT_HERSHEY_SIMPLEX, 0.55, {0, 0, 0}, 1);
        return m;
    };
    const double ex = 1.0;
    std::vector<cv::Mat> top{label(exposed(truths[0].image, ex), "truth: disc"), label(exposed(pics[0].second, ex), "--diffuse"),
                             label(exposed(pics[1].second, ex), "--bokeh disc")};
    std::vector<cv::Mat> bottom{label(exposed(truths[1].image, ex), "truth: polygon:6:15"),
                                label(bench::error_map(pics[0].second, truths[0].image, 0.1), "|error| --diffuse vs disc"),
                                label(exposed(pics[2].second, ex), "--bokeh polygon:6:15")};
    cv::Mat a, b, all;
    cv::hconcat(top, a);
    cv::hconcat(bottom, b);
    cv::vconcat(a, b, all);
    cv::imwrite(out + "/bokeh_highlights.png", all);
}

void cost(const std::string& out, std::ostream& table) {
    const Roi frame{0, 0, 1920, 1080};
    std::fprintf(stderr, "== cost against R, %dx%d\n", frame.width(), frame.height());
    const std::vector<Layer> layers = bench::cost_layers(frame);
    const Camera cam = bench::cost_camera(frame);
    // The memory floor: one copy of the two layers' R, G, B, A.
    std::vector<float> dst(4 * 2 * frame.npixels());
    const double copy = median_of(5, [&] {
        std::size_t o = 0;
        for (const Layer& l : layers)
            for (int c = 0; c < 4; ++c) {
                std::copy_n(l.image.plane(c), frame.npixels(), dst.begin() + std::ptrdiff_t(o));
                o += frame.npixels();
            }
    });
    std::ofstream csv(out + "/bokeh_cost.csv");
    csv << "radius,diffuse_s,bokeh_disc_s,bokeh_hexagon_s,copy_s\n";
    table << "### Bokeh: cost against the blur radius\n\n"
          << "Two full-frame layers at " << frame.width() << "x" << frame.height()
          << " (a textured background, a foreground disc), every pixel blurred by R; medians of 3. A copy of the "
             "layers' RGBA (the memory floor) takes "
          << (std::ostringstream() << std::fixed << std::setprecision(3) << copy * 1000).str()
          << " ms in the same run.\n\n| R (px) | --diffuse (s) | --bokeh disc (s) | --bokeh polygon:6 (s) | bokeh / diffuse |\n"
             "|---:|---:|---:|---:|---:|\n";
    for (int R : {4, 8, 16, 24, 32, 48, 64}) {
        const BlurField field = bench::constant_blur(R);
        DefocusOptions diff, disc, hex;
        disc.filter = hex.filter = DefocusFilter::Bokeh;
        hex.aperture = hexagon();
        auto time = [&](const DefocusOptions& o) {
            return median_of(3, [&] { take(defocus_layers(layers, field, cam, o), "defocus"); });
        };
        const double td = time(diff), tb = time(disc), th = time(hex);
        csv << R << "," << td << "," << tb << "," << th << "," << copy << "\n";
        char row[256];
        std::snprintf(row, sizeof row, "| %d | %.2f | %.2f | %.2f | %.2f |\n", R, td, tb, th, tb / td);
        table << row;
        std::fprintf(stderr, "  R %2d  diffuse %.2f s  bokeh disc %.2f s  hexagon %.2f s\n", R, td, tb, th);
    }
    table << "\n";
}

}  // namespace

int main(int argc, char** argv) {
    std::string out = "bench_out", cache = "bench_cache";
    int W = 640, H = 360;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto next = [&]() -> std::string {
            if (i + 1 >= argc) die("missing value after " + a);
            return argv[++i];
        };
        if (a == "--out") out = next();
        else if (a == "--cache") cache = next();
        else if (a == "--size") {
            const std::string s = next();
            if (std::sscanf(s.c_str(), "%dx%d", &W, &H) != 2 || W < 16 || H < 16) die("bad --size '" + s + "'");
        } else die("unknown argument '" + a + "' (--out DIR --cache DIR [--size WxH])");
    }
    fs::create_directories(out);
    fs::create_directories(cache);
    std::ostringstream table;
    accuracy(out, cache, W, H, table);
    cost(out, table);
    std::ofstream(out + "/bokeh_table.md") << table.str();
    std::fprintf(stderr, "wrote %s/bokeh_table.md\n", out.c_str());
    return 0;
}
