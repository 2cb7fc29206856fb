// What --render and --render --stack share (render_common.cpp): loading the
// scene, building the tracer, the --stats / -v report.
#pragma once

#include <memory>
#include <string>

#include "frame.h"
#include "gdof/raytrace.h"
#include "gdof/scene.h"

namespace gdof::cli {

Scene load_render_scene(Frame& f, const std::string& path);
std::shared_ptr<const RayTracer> build_tracer(Frame& f, const Scene& scene, const std::string& path);
// --stats: the library's report and the yardstick, Embree's raw
// rtcIntersect1 throughput on the same scene measured now.
void report_render(Session& s, const std::string& what, const RayTracer& tracer, const RenderStats& stats);

}  // namespace gdof::cli
