// Ray-traced focus/aperture stacks: spec parsing, planning (depth of field
// per reference) and rendering reference by reference.
#include "gdof/render_stack.h"

#include <cmath>

#include "common/json_util.h"

namespace gdof {

namespace {

using json_util::fail;
using json_util::json;
using json_util::type_name;

double positive(const json& j, const std::string& key) {
    if (!j.is_number()) fail(key, "must be a number, got " + type_name(j));
    const double v = j.get<double>();
    if (!(v > 0) || !std::isfinite(v)) fail(key, "must be a positive finite number, got " + j.dump());
    return v;
}

std::vector<double> positive_list(const json& j, const std::string& key) {
    if (!j.is_array() || j.empty()) fail(key, "must be a non-empty array of numbers");
    std::vector<double> v;
    for (std::size_t i = 0; i < j.size(); ++i) v.push_back(positive(j[i], key + "[" + std::to_string(i) + "]"));
    return v;
}

void allow_only(const json& j, const std::string& path, const std::vector<std::string>& keys) {
    if (!j.is_object()) fail(path, "must be an object, got " + type_name(j));
    for (auto it = j.begin(); it != j.end(); ++it) {
        bool ok = false;
        for (const std::string& k : keys) ok = ok || k == it.key();
        if (!ok) fail(path == "top level" ? it.key() : path + "." + it.key(), "unknown key (expected one of " + json_util::join(keys) + ")");
    }
}

// count focus distances from near to far, evenly spaced in 1/distance (as
// depth of field is: equal steps of defocus).
std::vector<double> focus_range(const json& j) {
    allow_only(j, "focus_range", {"near", "far", "count"});
    for (const char* k : {"near", "far", "count"})
        if (!j.contains(k)) fail(std::string("focus_range.") + k, "missing");
    const double near = positive(j["near"], "focus_range.near"), far = positive(j["far"], "focus_range.far");
    if (!(near < far)) fail("focus_range", "near must be < far, got " + j["near"].dump() + " and " + j["far"].dump());
    if (!j["count"].is_number_integer() || j["count"].get<long>() < 1 || j["count"].get<long>() > 4096)
        fail("focus_range.count", "must be an integer from 1 to 4096, got " + j["count"].dump());
    const int n = j["count"].get<int>();
    std::vector<double> v;
    for (int i = 0; i < n; ++i) {
        const double t = n == 1 ? 0.5 : double(i) / (n - 1);
        v.push_back(1.0 / ((1 - t) / near + t / far));
    }
    return v;
}

}  // namespace

Result<RenderStackOptions> parse_render_stack_options(const std::string& text, const std::string& where) {
    try {
        const json j = json::parse(text);
        allow_only(j, "top level", {"coc_px", "focus_distances", "focus_range", "f_numbers", "references", "comment"});
        RenderStackOptions spec;
        if (j.contains("coc_px")) spec.coc_px = positive(j["coc_px"], "coc_px");
        if (j.contains("focus_distances") && j.contains("focus_range"))
            fail("focus_range", "give focus_distances or focus_range, not both");
        std::vector<double> focus;
        if (j.contains("focus_distances")) focus = positive_list(j["focus_distances"], "focus_distances");
        if (j.contains("focus_range")) focus = focus_range(j["focus_range"]);
        const bool grid = !focus.empty();
        if (grid && !j.contains("f_numbers")) fail("f_numbers", "required with focus_distances / focus_range");
        if (!grid && j.contains("f_numbers")) fail("f_numbers", "needs focus_distances or focus_range to pair with");
        if (grid)
            for (double fd : focus)
                for (double n : positive_list(j["f_numbers"], "f_numbers")) spec.references.push_back({fd, n});
        if (j.contains("references")) {
            const json& a = j["references"];
            if (!a.is_array()) fail("references", "must be an array, got " + type_name(a));
            for (std::size_t i = 0; i < a.size(); ++i) {
                const std::string key = "references[" + std::to_string(i) + "]";
                allow_only(a[i], key, {"focus_distance", "f_number", "comment"});
                for (const char* k : {"focus_distance", "f_number"})
                    if (!a[i].contains(k)) fail(key + "." + k, "missing");
                spec.references.push_back({positive(a[i]["focus_distance"], key + ".focus_distance"),
                                           positive(a[i]["f_number"], key + ".f_number")});
            }
        }
        if (spec.references.empty())
            fail("references", "no references (give references, or focus_distances / focus_range with f_numbers)");
        for (std::size_t i = 0; i < spec.references.size(); ++i)
            for (std::size_t k = 0; k < i; ++k)
                if (spec.references[i].focus_distance == spec.references[k].focus_distance &&
                    spec.references[i].f_number == spec.references[k].f_number)
                    fail("references", "reference " + std::to_string(i + 1) + " repeats reference " + std::to_string(k + 1) +
                                           " (focus " + json_util::format_number(spec.references[i].focus_distance) +
                                           ", f/" + json_util::format_number(spec.references[i].f_number) + ")");
        return spec;
    } catch (const json::exception& e) {
        return Status::error(where + ": invalid JSON: " + e.what());
    } catch (const json_util::JsonError& e) {
        return Status::error(where + ": " + e.message);
    }
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
