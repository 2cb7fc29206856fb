// -o after --render scene.json --stack stack.json: renders a focus/aperture
// stack for method 2 (gdof/render_stack.h), each reference the scene camera
// with one (focus distance, f-number), written as it finishes (StackOutput).
#include <chrono>
#include <cstdio>

#include "cli.h"
#include "gdof/render_stack.h"
#include "ops/ops.h"
#include "ops/render_common.h"
#include "stack_output.h"

namespace gdof::cli {

void do_render_stack_output(Frame& f, const std::string& pattern) {
    Session& s = *f.session;
    PendingRender& o = f.render;
    const std::string scene_path = o.scene, spec_path = o.stack_spec;
    o.scene.clear();
    o.stack_spec.clear();
    check_stack_pattern(pattern, "a rendered focus/aperture stack");
    if (f.blur) usage_error("--render --stack: each reference is the scene camera's thin lens; drop --blurfield");
    if (o.options.pinhole || o.deep) usage_error("--render --stack: --pinhole and --deep do not apply to a stack");
    const RenderStackOptions spec =
        take(parse_render_stack_options(read_flag_file("--stack", "file", spec_path), "'" + spec_path + "'"), "--stack");
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
        const auto t0 = std::chrono::steady_clock::now();
        Status st = out.write(i, std::move(image));
        t_write += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        if (st && (s.progress.enabled() || s.global.verbose)) s.progress.message("gdof: " + label(i) + " -> " + out.name(i));
        return st;
    };
    RenderStats stats;
    Status st;
    const auto t0 = std::chrono::steady_clock::now();
    s.progress.begin("render");
    RenderOptions options = o.options;
    if (!o.aperture_given) options.aperture = with_kernel_image(f, scene.aperture, "'" + scene_path + "': camera.aperture");
    st = render_stack(*tracer, plan, options, sink, &stats, s.exec);
    s.stats.add("render", std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() - t_write);
    s.stats.add("write", t_write);
    check_interrupted();
    if (!st) runtime_error("--render '" + scene_path + "' --stack '" + spec_path + "': " + message_naming_flag(st));
    {
        StageTimer t(s.stats, "write");
        out.write_manifest(plan);
    }
    report_render(s, "--render " + scene_path + " --stack " + spec_path + " (" + std::to_string(n) + " references)",
                  *tracer, stats);
}

}  // namespace gdof::cli
