// --render (method 1: nonlinear distributed ray tracing, gdof/raytrace.h).
//   gdof --render scene.json [--blurfield field.json] [--spp 64] [--min-spp 4]
//        [--adaptive-threshold 0.01] [--light-samples 2] [--pinhole] -o beauty.exr
// The render runs when the next other step comes (usually -o), so options and
// --blurfield may follow --render. It pushes one multilayer image (beauty +
// AOVs + camera attributes). Without --blurfield the scene camera's thin
// lens is used (pinhole when the scene gives no f_number / focus_distance).
#include <cstdio>

#include "cli.h"
#include "gdof/raytrace.h"
#include "gdof/scene.h"

namespace gdof::cli {

namespace {

void run_render(Frame& f) {
    Session& s = *f.session;
    Frame::RenderOptions& o = f.render;
    const std::string scene_path = o.scene;
    o.scene.clear();
    Result<Scene> scene = Scene{};
    {
        StageTimer t(s.stats, "scene");
        scene = load_scene(scene_path);
    }
    if (!scene) runtime_error("--render: " + scene.message());
    RenderSettings rs;
    rs.spp = o.spp;
    rs.min_spp = o.min_spp;
    rs.pinhole = o.pinhole;
    rs.adaptive_threshold = o.adaptive_threshold;
    rs.light_samples = o.light_samples;
    rs.straight_thin_lens = o.straight_thin_lens;
    std::optional<BlurField> field;  // --blurfield (field_for returns it when one was given)
    if (f.blur && !o.pinhole) {
        field = field_for(f, scene->camera, "--render", "'" + scene_path + "'");
        rs.blur_field = &*field;
    }
    RenderStats stats;
    Result<Image> img = Image{};
    {
        StageTimer t(s.stats, "render");
        s.progress.begin("render");
        img = render(scene.value(), rs, &stats, s.exec);
        s.progress.end();
    }
    check_interrupted();
    if (!img) runtime_error("--render '" + scene_path + "': " + img.message());
    if (s.global.stats || s.global.verbose) {
        std::string raw;
        if (s.global.stats) {  // the yardstick: Embree's raw rtcIntersect1 throughput on this scene
            auto tracer = RayTracer::build(scene.value());
            if (tracer) {
                char buf[160];
                std::snprintf(buf, sizeof buf, "  raw rtcIntersect1  %.2f Mrays/s (pinhole primary rays, no shading)\n",
                              raw_primary_mrays(*tracer.value(), 4, s.exec));
                raw = buf;
            }
        }
        s.progress.message("gdof: --render " + scene_path + " (" + std::to_string(scene->triangle_count()) +
                           " triangles, " + std::to_string(img->width()) + "x" + std::to_string(img->height()) +
                           "):\n" + stats.report() + raw);
    }
    StackEntry e;
    e.images.parts.emplace_back(std::move(img).value());
    e.source = "";
    f.stack.push_back(std::move(e));
}

int parse_count(const std::string& flag, const std::string& v, int lo) {
    double d = parse_double(flag, v);
    if (d != double(long(d)) || d < lo || d > 1e6)
        usage_error(flag + ": expected an integer >= " + std::to_string(lo) + ", got '" + v + "'");
    return int(d);
}

}  // namespace

bool render_step(Frame& f, const Step* step) {
    if (step && !step->is_input()) {
        const std::string& n = step->name();
        Frame::RenderOptions& o = f.render;
        const std::string& a = step->args.empty() ? std::string() : step->args[0];
        if (n == "--render") {
            if (!o.scene.empty()) run_render(f);
            o.scene = a;
            return true;
        }
        if (n == "--spp") return o.spp = parse_count(step->flag, a, 1), true;
        if (n == "--min-spp") return o.min_spp = parse_count(step->flag, a, 1), true;
        if (n == "--light-samples") return o.light_samples = parse_count(step->flag, a, 1), true;
        if (n == "--adaptive-threshold") {
            o.adaptive_threshold = parse_double(step->flag, a);
            if (!(o.adaptive_threshold >= 0)) usage_error(step->flag + ": must be >= 0, got '" + a + "'");
            return true;
        }
        if (n == "--pinhole") return o.pinhole = true, true;
        if (n == "--straight-thin-lens") return o.straight_thin_lens = true, true;
        if (n == "--blurfield" || n == "--threads") return false;  // loaded by the usual handler first
    }
    if (!f.render.scene.empty()) run_render(f);
    return false;
}

}  // namespace gdof::cli
