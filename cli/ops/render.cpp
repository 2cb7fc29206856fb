// --render (method 1: nonlinear distributed ray tracing, gdof/raytrace.h).
//   gdof --render scene.json [--blurfield field.json] [--spp 64] [--min-spp 4]
//        [--adaptive-threshold 0.01] [--light-samples 2] [--pinhole] [--deep]
//        [--aovs=albedo,Z,P,N,id] -o beauty.exr
//   gdof --render scene.json --stack stack.json [...] -o stack/ref.####.exr
//        (a focus/aperture stack for method 2: render_stack.cpp)
// The render runs when the next other step comes (usually -o), so options and
// --blurfield may follow --render. It pushes one multilayer image (beauty +
// AOVs + camera attributes). Without --blurfield the scene camera's thin
// lens is used (pinhole when the scene gives no f_number / focus_distance).
#include "camera_field.h"
#include "cli.h"
#include "ops/ops.h"
#include "ops/render_common.h"

namespace gdof::cli {

namespace {

void run_render(Frame& f) {
    Session& s = *f.session;
    PendingRender& o = f.render;
    const std::string scene_path = o.scene;
    o.scene.clear();
    const Scene scene = load_render_scene(f, scene_path);
    const auto tracer = build_tracer(f, scene, scene_path);
    RenderOptions rs = o.options;
    if (!o.aperture_given) rs.aperture = with_kernel_image(f, scene.aperture, "'" + scene_path + "': camera.aperture");
    std::optional<BlurField> field;  // --blurfield (field_for returns it when one was given)
    if (f.blur && !rs.pinhole) {
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
    }
    check_interrupted();
    if (!st) runtime_error("--render '" + scene_path + "': " + message_naming_flag(st));
    const Roi& d = scene.camera.display_window();
    report_render(s, "--render " + scene_path + " (" + std::to_string(scene.triangle_count()) + " triangles, " +
                         std::to_string(d.width()) + "x" + std::to_string(d.height()) + (o.deep ? ", deep" : "") + ")",
                  *tracer, stats);
    e.source = "";
    f.stack.push_back(std::move(e));
}

// --spp, --min-spp, --light-samples: at least one.
int count(const Step& s) { return parse_count(s.flag, s.args[0], 1); }

// A render option: sets a field of the pending render's options.
Command option(std::vector<std::string> names, std::string args, std::string help,
               std::function<void(Frame&, const Step&)> run) {
    return {.names = std::move(names), .args = std::move(args), .kind = Kind::Modifier,
            .group = "Render (method 1: ray tracing)", .help = std::move(help), .run = std::move(run),
            .lets_wait = render_option_waits};
}

}  // namespace

void run_pending_render(Frame& f) {
    if (f.render.pending()) run_render(f);
}

void set_render_aovs(Frame& f, const Step& step) {
    if (step.args.empty()) {
        f.render.options.aovs = RenderAov::All;
        return;
    }
    auto aovs = parse_render_aovs(step.args[0]);
    if (!aovs) usage_error(step.flag + ": " + aovs.message());
    f.render.options.aovs = aovs.value();
}

std::vector<Command> render_commands() {
    std::vector<Command> t;
    Command render = option(
        {"--render"}, "SCENE",
        "ray-trace a scene JSON (docs/scene.md): beauty + albedo, Z, P, N, id; lens from --blurfield or the scene camera",
        [](Frame& f, const Step& s) {
            run_pending_render(f);
            f.render.scene = s.args[0];
        });
    render.kind = Kind::Action;
    render.file_args = {0};
    render.stack = StackUse::PushesImage;
    render.progress_stage = true;
    t.push_back(std::move(render));
    t.push_back(option({"--spp"}, "N", "--render: aperture samples per pixel, the cap (default 64)",
                       [](Frame& f, const Step& s) { f.render.options.spp = count(s); }));
    t.push_back(option({"--min-spp"}, "N", "--render: samples every pixel gets before adaptive stopping (default 16)",
                       [](Frame& f, const Step& s) { f.render.options.min_spp = count(s); }));
    t.push_back(option({"--adaptive-threshold"}, "E",
                       "--render: stop a pixel when its luminance standard error <= E * mean (default 0.01; 0: "
                       "always --spp)",
                       [](Frame& f, const Step& s) {
                           const double e = parse_double(s.flag, s.args[0]);
                           if (!(e >= 0)) usage_error(s.flag + ": must be >= 0, got '" + s.args[0] + "'");
                           f.render.options.adaptive_threshold = e;
                       }));
    t.push_back(option({"--light-samples"}, "N", "--render: area-light samples per hit (default 2)",
                       [](Frame& f, const Step& s) { f.render.options.light_samples = count(s); }));
    t.push_back(option({"--pinhole"}, "", "--render: all in focus (pinhole camera), ignoring the lens",
                       [](Frame& f, const Step&) { f.render.options.pinhole = true; }));
    t.push_back(option({"--straight-thin-lens"}, "",
                       "--render: trace the scene's thin lens with straight rays (reference for the polyline camera)",
                       [](Frame& f, const Step&) { f.render.options.straight_thin_lens = true; }));
    t.push_back(option({"--deep"}, "",
                       "--render: write a deep image instead (one sample per surface seen in a pixel: the input "
                       "method 3 wants)",
                       [](Frame& f, const Step&) { f.render.deep = true; }));
    // After --render, the stack to render; otherwise the references a --lightfield extracts.
    Command stack = option(
        {"--stack"}, "FILE",
        "stack JSON: after --render, the focus distances x f-numbers to render; with --lightfield, the "
        "(focus, aperture) references to extract; the next -o (with ####) writes one image per reference + "
        "manifest.json",
        [](Frame& f, const Step& s) {
            if (f.render.pending()) f.render.stack_spec = s.args[0];
            else f.lightfield.stack_spec = s.args[0];
        });
    stack.file_args = {0};
    stack.lets_wait = [](const Frame& f, const Step&) -> unsigned {
        return f.render.pending() ? kRenderWaits | kCompositeWaits : kRenderWaits;
    };
    t.push_back(std::move(stack));
    return t;
}

}  // namespace gdof::cli
