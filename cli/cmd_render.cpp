// --render (method 1: nonlinear distributed ray tracing, gdof/raytrace.h).
//   gdof --render scene.json [--blurfield field.json] [--spp 64] [--min-spp 4]
//        [--adaptive-threshold 0.01] [--light-samples 2] [--pinhole] [--deep]
//        [--aovs=albedo,Z,P,N,id] -o beauty.exr
//   gdof --render scene.json --stack stack.json [...] -o stack/ref.####.exr
//        (a focus/aperture stack for method 2, gdof/render_stack.h)
// The render runs when the next other step comes (usually -o), so options and
// --blurfield may follow --render. It pushes one multilayer image (beauty +
// AOVs + camera attributes). Without --blurfield the scene camera's thin
// lens is used (pinhole when the scene gives no f_number / focus_distance).
#include <chrono>
#include <cstdio>

#include "cli.h"
#include "gdof/raytrace.h"
#include "gdof/render_stack.h"
#include "gdof/scene.h"

namespace gdof::cli {

namespace {

Scene load_render_scene(Frame& f, const std::string& path) {
    StageTimer t(f.session->stats, "scene");
    Result<Scene> scene = load_scene(path);
    if (!scene) runtime_error("--render: " + scene.message());
    return std::move(scene).value();
}

RenderOptions render_settings(const Frame::PendingRender& o) {
    RenderOptions rs;
    rs.spp = o.spp;
    rs.min_spp = o.min_spp;
    rs.pinhole = o.pinhole;
    rs.adaptive_threshold = o.adaptive_threshold;
    rs.light_samples = o.light_samples;
    rs.straight_thin_lens = o.straight_thin_lens;
    rs.aovs = o.aovs;
    return rs;
}

// --stats: the library's report and the yardstick, Embree's raw
// rtcIntersect1 throughput on the same scene measured now.
void report_render(Session& s, const std::string& what, const RayTracer& tracer, const RenderStats& stats) {
    if (!s.global.stats && !s.global.verbose) return;
    std::string raw;
    if (s.global.stats) {
        char buf[160];
        std::snprintf(buf, sizeof buf, "  raw rtcIntersect1  %.2f Mrays/s (pinhole primary rays, no shading)\n",
                      raw_primary_mrays(tracer, 4, s.exec));
        raw = buf;
    }
    s.progress.message("gdof: " + what + ":\n" + stats.report() + raw);
}

std::shared_ptr<const RayTracer> build_tracer(Frame& f, const Scene& scene, const std::string& path) {
    StageTimer t(f.session->stats, "scene");
    auto tracer = RayTracer::build(scene);
    if (!tracer) runtime_error("--render '" + path + "': " + tracer.message());
    return tracer.value();
}

void run_render(Frame& f) {
    Session& s = *f.session;
    Frame::PendingRender& o = f.render;
    const std::string scene_path = o.scene;
    o.scene.clear();
    const Scene scene = load_render_scene(f, scene_path);
    const auto tracer = build_tracer(f, scene, scene_path);
    RenderOptions rs = render_settings(o);
    std::optional<BlurField> field;  // --blurfield (field_for returns it when one was given)
    if (f.blur && !o.pinhole) {
        field = field_for(f, scene.camera, "--render", "'" + scene_path + "'");
        rs.blur_field = &*field;
    }
    RenderStats stats;
    StackEntry e;
    Status st;
    {
        StageTimer t(s.stats, "render");
        s.progress.begin("render");
        if (o.deep) {
            Result<DeepImage> d = render_deep(*tracer, rs, &stats, s.exec);
            if (d) e.images.parts.emplace_back(std::move(d).value());
            st = d.status();
        } else {
            Result<Image> img = render(*tracer, rs, &stats, s.exec);
            if (img) e.images.parts.emplace_back(std::move(img).value());
            st = img.status();
        }
        s.progress.end();
    }
    check_interrupted();
    if (!st) runtime_error("--render '" + scene_path + "': " + st.message());
    const Roi& d = scene.camera.display_window();
    report_render(s, "--render " + scene_path + " (" + std::to_string(scene.triangle_count()) + " triangles, " +
                         std::to_string(d.width()) + "x" + std::to_string(d.height()) + (o.deep ? ", deep" : "") + ")",
                  *tracer, stats);
    e.source = "";
    f.stack.push_back(std::move(e));
}

}  // namespace

void do_render_stack_output(Frame& f, const std::string& pattern) {
    Session& s = *f.session;
    Frame::PendingRender& o = f.render;
    const std::string scene_path = o.scene, spec_path = o.stack_spec;
    o.scene.clear();
    o.stack_spec.clear();
    check_stack_pattern(pattern, "a rendered focus/aperture stack");
    if (f.blur) usage_error("--render --stack: each reference is the scene camera's thin lens; drop --blurfield");
    if (o.pinhole || o.deep) usage_error("--render --stack: --pinhole and --deep do not apply to a stack");
    const RenderStackOptions spec = take(parse_render_stack_options(read_text("--stack", "file", spec_path), "'" + spec_path + "'"), "--stack");
    const Scene scene = load_render_scene(f, scene_path);
    // Plan first: bad references fail before any file is written.
    const FocalStack plan = take(plan_render_stack(scene.camera, spec), "--stack '" + spec_path + "'");
    const StackOutput out(f, pattern, plan.references.size());
    const auto tracer = build_tracer(f, scene, scene_path);
    out.create_folder();
    const std::size_t n = plan.references.size();
    auto label = [&](std::size_t i) {
        char b[128];
        std::snprintf(b, sizeof b, "reference %zu/%zu (focus %g, f/%g)", i + 1, n, plan.references[i].focus_distance,
                      plan.references[i].f_number);
        return std::string(b);
    };
    double t_write = 0;
    auto sink = [&](std::size_t i, Image&& image) -> Status {
        s.progress.end();
        const auto t0 = std::chrono::steady_clock::now();
        Status st = out.write(i, std::move(image));
        t_write += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        if (st && (s.progress.enabled() || s.global.verbose)) s.progress.message("gdof: " + label(i) + " -> " + out.name(i));
        if (st && i + 1 < n) s.progress.begin("render " + label(i + 1));
        return st;
    };
    RenderStats stats;
    Status st;
    const auto t0 = std::chrono::steady_clock::now();
    s.progress.begin("render " + label(0));
    st = render_stack(*tracer, plan, render_settings(o), sink, &stats, s.exec);
    s.progress.end();
    s.stats.add("render", std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() - t_write);
    s.stats.add("write", t_write);
    check_interrupted();
    if (!st) runtime_error("--render '" + scene_path + "' --stack '" + spec_path + "': " + st.message());
    {
        StageTimer t(s.stats, "write");
        out.write_manifest(plan);
    }
    report_render(s, "--render " + scene_path + " --stack " + spec_path + " (" + std::to_string(n) + " references)",
                  *tracer, stats);
}

namespace {

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
        Frame::PendingRender& o = f.render;
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
        if (n == "--deep") return o.deep = true, true;
        if (n == "--aovs" && !o.scene.empty()) {
            if (!step->args.empty()) {
                auto aovs = parse_render_aovs(a);
                if (!aovs) usage_error(step->flag + ": " + aovs.message());
                o.aovs = aovs.value();
            } else {
                o.aovs = RenderAov::All;
            }
            return true;
        }
        if (n == "--stack" && !o.scene.empty()) return o.stack_spec = a, true;
        if (n == "-o" && step->stack_output && !o.stack_spec.empty()) {
            do_render_stack_output(f, a);
            return true;
        }
        if (n == "--straight-thin-lens") return o.straight_thin_lens = true, true;
        if (n == "--blurfield" || n == "--threads") return false;  // loaded by the usual handler first
    }
    if (!f.render.scene.empty()) run_render(f);
    return false;
}

}  // namespace gdof::cli
