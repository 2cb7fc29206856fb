// Ray-traced focus/aperture stacks: spec parsing, planning (depth of field
// per reference) and rendering reference by reference.
#include "gdof/render_stack.h"

#include <cmath>

#include "common/json_read.h"

namespace gdof {

namespace {

using json_read::Object;
using json_read::Value;

std::vector<double> positive_list(const Value& v) {
    std::vector<double> out;
    for (const Value& x : v.non_empty_array("numbers")) out.push_back(x.positive());
    return out;
}

// count focus distances from near to far, evenly spaced in 1/distance (as
// depth of field is: equal steps of defocus).
std::vector<double> focus_range(const Value& v) {
    const Object o = v.object({"near", "far", "count"}, {"near", "far", "count"});
    const double near = o.get("near").positive(), far = o.get("far").positive();
    if (!(near < far))
        o.fail("near must be < far, got " + json_read::format_number(near) + " and " + json_read::format_number(far));
    const Value count = o.get("count");
    if (!count.raw().is_number_integer() || count.raw().get<long>() < 1 || count.raw().get<long>() > 4096)
        count.fail("must be an integer from 1 to 4096, got " + count.raw().dump());
    const int n = count.raw().get<int>();
    std::vector<double> out;
    for (int i = 0; i < n; ++i) {
        const double t = n == 1 ? 0.5 : double(i) / (n - 1);
        out.push_back(1.0 / ((1 - t) / near + t / far));
    }
    return out;
}

RenderStackOptions read_options(const Value& root) {
    const Object o = root.object({"coc_px", "focus_distances", "focus_range", "f_numbers", "references", "comment"});
    RenderStackOptions spec;
    if (const auto v = o.find("coc_px")) spec.coc_px = v->positive();
    if (o.has("focus_distances") && o.has("focus_range"))
        json_read::fail("focus_range", "give focus_distances or focus_range, not both");
    std::vector<double> focus;
    if (const auto v = o.find("focus_distances")) focus = positive_list(*v);
    if (const auto v = o.find("focus_range")) focus = focus_range(*v);
    const bool grid = !focus.empty();
    if (grid) o.require("f_numbers", "with focus_distances / focus_range");
    if (!grid && o.has("f_numbers")) json_read::fail("f_numbers", "needs focus_distances or focus_range to pair with");
    if (grid)
        for (double fd : focus)
            for (double n : positive_list(o.get("f_numbers"))) spec.references.push_back({fd, n});
    if (const auto refs = o.find("references"))
        for (const Value& r : refs->array()) {
            const Object ro = r.object({"focus_distance", "f_number", "comment"}, {"focus_distance", "f_number"});
            spec.references.push_back({ro.get("focus_distance").positive(), ro.get("f_number").positive()});
        }
    if (spec.references.empty())
        json_read::fail("references", "no references (give references, or focus_distances / focus_range with f_numbers)",
                        StatusCode::NotFound);
    for (std::size_t i = 0; i < spec.references.size(); ++i)
        for (std::size_t k = 0; k < i; ++k)
            if (spec.references[i].focus_distance == spec.references[k].focus_distance &&
                spec.references[i].f_number == spec.references[k].f_number)
                json_read::fail("references", "reference " + std::to_string(i + 1) + " repeats reference " +
                                                  std::to_string(k + 1) + " (focus " +
                                                  json_read::format_number(spec.references[i].focus_distance) + ", f/" +
                                                  json_read::format_number(spec.references[i].f_number) + ")");
    return spec;
}

}  // namespace

Result<RenderStackOptions> parse_render_stack_options(const std::string& text, const std::string& where) {
    return json_read::read_document(text, where, read_options);
}

Result<FocalStack> plan_render_stack(const Camera& camera, const RenderStackOptions& spec) {
    const LensInfo& lens = camera.lens();
    if (!std::isfinite(lens.focal_length_mm) || !std::isfinite(lens.sensor_width_mm))
        return Status::error("the camera needs focal_length_mm and sensor_width_mm for a focus/aperture stack");
    FocalStack stack;
    stack.coc_px = spec.coc_px;
    stack.scene_unit_mm = lens.scene_unit_mm;
    stack.focal_length_mm = lens.focal_length_mm;
    stack.sensor_width_mm = lens.sensor_width_mm;
    stack.width = camera.display_window().width();
    stack.height = camera.display_window().height();
    for (std::size_t i = 0; i < spec.references.size(); ++i) {
        const RenderStackOptions::Reference& r = spec.references[i];
        ThinLens tl;
        tl.focal_length_mm = lens.focal_length_mm;
        tl.sensor_width_mm = lens.sensor_width_mm;
        tl.scene_unit_mm = lens.scene_unit_mm;
        tl.image_width_px = stack.width;
        tl.f_number = r.f_number;
        tl.focus_distance = r.focus_distance;
        if (Status st = tl.validate(); !st) return st.prefix("reference " + std::to_string(i + 1));
        const ThinLens::DofLimits dof = tl.dof_limits(spec.coc_px);
        StackReference ref;
        ref.focus_distance = r.focus_distance;
        ref.f_number = r.f_number;
        ref.near = dof.near;
        ref.far = dof.far;
        stack.references.push_back(ref);
    }
    return stack;
}

Status render_stack(const RayTracer& tracer, const FocalStack& plan, const RenderOptions& settings,
                    const StackSink& sink, RenderStats* stats, const Exec& exec) {
    if (settings.blur_field || settings.pinhole)
        return Status::error("a focus/aperture stack renders each reference's thin lens: no blur field, no pinhole");
    const std::size_t n = plan.references.size();
    RenderStats total;
    for (std::size_t i = 0; i < n; ++i) {
        RenderOptions rs = settings;
        LensInfo lens = tracer.scene().camera.lens();
        lens.f_number = plan.references[i].f_number;
        lens.focus_distance = plan.references[i].focus_distance;
        rs.lens = lens;
        Exec sub = exec;
        if (exec.progress) sub.progress = [&exec, i, n](double f) { exec.report((double(i) + f) / double(n)); };
        RenderStats one;
        Result<Image> img = render(tracer, rs, &one, sub);
        if (!img) return img.status().prefix("reference " + std::to_string(i + 1));
        total.primary_rays += one.primary_rays, total.segments += one.segments;
        total.shadow_rays += one.shadow_rays, total.id_rays += one.id_rays;
        total.sample_cap += one.sample_cap, total.seconds += one.seconds;
        total.camera = one.camera;
        if (Status st = sink(i, std::move(img).value()); !st) return st;
    }
    if (stats) *stats = total;
    return {};
}

}  // namespace gdof
