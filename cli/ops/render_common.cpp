// What --render and --render --stack share (render_common.h).
#include "ops/render_common.h"

#include <cstdio>

#include "cli.h"

namespace gdof::cli {

Scene load_render_scene(Frame& f, const std::string& path) {
    StageTimer t(f.session->stats, "scene");
    Result<Scene> scene = load_scene(path);
    if (!scene) runtime_error("--render: " + scene.message());
    return std::move(scene).value();
}

std::shared_ptr<const RayTracer> build_tracer(Frame& f, const Scene& scene, const std::string& path) {
    StageTimer t(f.session->stats, "scene");
    auto tracer = RayTracer::build(scene);
    if (!tracer) runtime_error("--render '" + path + "': " + tracer.message());
    return tracer.value();
}

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

}  // namespace gdof::cli
