// Focus/aperture stack manifests (focal_stack.h): JSON <-> FocalStack.
// Read with json_read: errors name the key path ("stack manifest:
// references[3].f_number: must be > 0, got -2"); malformed JSON gives the
// line and column.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "gdof/camera.h"
#include "gdof/focal_stack.h"
#include "common/json_read.h"

namespace gdof {

namespace {

using json_read::Infinity;
using json_read::Object;
using json_read::Value;
using json_read::fail;
std::string num(double v) { return format_number(v); }

int dimension(const Value& v) {
    const long long n = v.integer();
    if (n < 0 || n > 1000000) v.fail("must be 0 (unknown) to 1000000, got " + std::to_string(n));
    return int(n);
}

bool same(double a, double b) {
    if (std::isnan(a) || std::isnan(b)) return std::isnan(a) && std::isnan(b);
    return std::abs(a - b) <= 1e-9 * std::max(std::abs(a), std::abs(b));
}

std::string join_path(const std::string& base, const std::string& file) {
    namespace fs = std::filesystem;
    const fs::path p(file);
    if (p.is_absolute() || base.empty()) return p.lexically_normal().string();
    return (fs::path(base) / p).lexically_normal().string();
}

StackReference parse_reference(const Value& v, const FocalStack& stack) {
    const Object o = v.object({"file", "focus_distance", "f_number", "focal_length_mm", "sensor_width_mm", "near", "far",
                               "focus_disparity", "aperture_radius_views", "comment"},
                              {"file"});
    const std::string& path = o.path();
    auto key = [&](const char* k) { return o.path(k); };
    StackReference r;
    const Value file = o.get("file");
    if (!file.raw().is_string() || file.raw().get<std::string>().empty())
        file.fail("must be a non-empty string, got " + json_read::type_name(file.raw()));
    r.file = file.string();
    r.path = join_path(stack.base_dir, r.file);

    if (const auto x = o.find("focus_distance")) r.focus_distance = x->positive();
    if (const auto x = o.find("f_number")) r.f_number = x->positive();
    if (const auto x = o.find("focal_length_mm")) r.focal_length_mm = x->positive();
    if (const auto x = o.find("sensor_width_mm")) r.sensor_width_mm = x->positive();
    if (const auto x = o.find("near")) r.near = x->non_negative();
    if (const auto x = o.find("far")) r.far = x->non_negative(Infinity::Allowed);
    if (const auto x = o.find("focus_disparity")) r.focus_disparity = x->number();
    if (const auto x = o.find("aperture_radius_views")) r.aperture_radius_views = x->non_negative();

    const bool explicit_limits = !std::isnan(r.near) && !std::isnan(r.far);
    if (!explicit_limits) {
        // From the thin lens: everything it needs must be known.
        const char* why = "needed to compute near/far from the thin lens";
        if (std::isnan(r.focus_distance)) o.require("focus_distance", why);
        if (std::isnan(r.f_number)) o.require("f_number", why);
        ThinLens lens;
        lens.focus_distance = r.focus_distance;
        lens.f_number = r.f_number;
        lens.focal_length_mm = std::isnan(r.focal_length_mm) ? stack.focal_length_mm : r.focal_length_mm;
        lens.sensor_width_mm = std::isnan(r.sensor_width_mm) ? stack.sensor_width_mm : r.sensor_width_mm;
        lens.scene_unit_mm = stack.scene_unit_mm;
        lens.image_width_px = stack.width;
        if (std::isnan(lens.focal_length_mm))
            fail(key("focal_length_mm"),
                 "missing (give it here or at the top level, or give \"near\" and \"far\" explicitly)",
                 StatusCode::NotFound);
        if (std::isnan(lens.sensor_width_mm))
            fail(key("sensor_width_mm"),
                 "missing (give it here or at the top level, or give \"near\" and \"far\" explicitly)",
                 StatusCode::NotFound);
        if (stack.width <= 0)
            fail("width", "missing or 0: the image width in pixels is needed to compute " + path +
                              ".near/far from the thin lens for coc_px",
                 StatusCode::NotFound);
        if (Status s = lens.validate(); !s) fail(path, "thin lens: " + s.message(), s.code());
        const ThinLens::DofLimits lim = lens.dof_limits(stack.coc_px);
        if (std::isnan(r.near)) r.near = lim.near;
        if (std::isnan(r.far)) r.far = lim.far;
    }
    if (r.near > r.far) fail(path, "near (" + num(r.near) + ") is beyond far (" + num(r.far) + ")");
    return r;
}

// Duplicates: same focus and aperture, as (focus_distance, f_number, focal
// length) when known, else as the light-field (focus_disparity, aperture_radius_views).
void check_duplicates(const FocalStack& s) {
    for (std::size_t i = 0; i < s.references.size(); ++i)
        for (std::size_t k = 0; k < i; ++k) {
            const StackReference& a = s.references[k];
            const StackReference& b = s.references[i];
            const bool lens_known = !std::isnan(a.focus_distance) && !std::isnan(a.f_number) &&
                                    !std::isnan(b.focus_distance) && !std::isnan(b.f_number);
            bool dup = false;
            std::string what;
            if (lens_known) {
                const double fa = std::isnan(a.focal_length_mm) ? s.focal_length_mm : a.focal_length_mm;
                const double fb = std::isnan(b.focal_length_mm) ? s.focal_length_mm : b.focal_length_mm;
                dup = same(a.focus_distance, b.focus_distance) && same(a.f_number, b.f_number) && same(fa, fb);
                what = "focus_distance " + num(a.focus_distance) + ", f_number " + num(a.f_number);
            } else if (!std::isnan(a.focus_disparity) && !std::isnan(b.focus_disparity)) {
                dup = same(a.focus_disparity, b.focus_disparity) &&
                      same(a.aperture_radius_views, b.aperture_radius_views);
                what = "focus_disparity " + num(a.focus_disparity) + ", aperture_radius_views " +
                       num(a.aperture_radius_views);
            }
            if (dup)
                fail("references[" + std::to_string(i) + "]",
                     "duplicate of references[" + std::to_string(k) + "] ('" + b.file + "' and '" + a.file +
                         "' both have " + what + ")");
        }
}

void put(nlohmann::ordered_json& j, const char* key, double v) {
    if (std::isnan(v)) return;
    if (std::isinf(v)) j[key] = "inf";
    else j[key] = v;
}

}  // namespace

Result<FocalStack> parse_stack_manifest(const std::string& text, const std::string& base_dir) {
    return json_read::read_document(text, "stack manifest", [&](const Value& root) {
        if (!root.raw().is_object())
            root.fail("must be an object {\"gdof_stack\": 1, \"references\": [...]}, got " + json_read::type_name(root.raw()));
        const Object o = root.object({"gdof_stack", "coc_px", "scene_unit_mm", "focal_length_mm", "sensor_width_mm",
                                      "width", "height", "references", "comment", "source"});
        FocalStack s;
        s.base_dir = base_dir;
        if (const auto v = o.find("gdof_stack"); v && (!v->raw().is_number_integer() || v->raw().get<long long>() != 1))
            v->fail("unsupported manifest version " + v->raw().dump() + " (this gdof reads version 1)");
        if (const auto v = o.find("coc_px")) s.coc_px = v->non_negative();
        if (const auto v = o.find("scene_unit_mm")) s.scene_unit_mm = v->positive();
        if (const auto v = o.find("focal_length_mm")) s.focal_length_mm = v->positive();
        if (const auto v = o.find("sensor_width_mm")) s.sensor_width_mm = v->positive();
        if (const auto v = o.find("width")) s.width = dimension(*v);
        if (const auto v = o.find("height")) s.height = dimension(*v);
        const Value refs = o.get("references");
        const std::vector<Value> list = refs.array();
        if (list.empty()) refs.fail("must list at least one reference image");
        for (const Value& r : list) s.references.push_back(parse_reference(r, s));
        check_duplicates(s);
        return s;
    });
}

std::string format_stack_manifest(const FocalStack& stack) {
    using ojson = nlohmann::ordered_json;
    ojson j = ojson::object();
    j["gdof_stack"] = 1;
    j["coc_px"] = stack.coc_px;
    j["scene_unit_mm"] = stack.scene_unit_mm;
    put(j, "focal_length_mm", stack.focal_length_mm);
    put(j, "sensor_width_mm", stack.sensor_width_mm);
    if (stack.width > 0) j["width"] = stack.width;
    if (stack.height > 0) j["height"] = stack.height;
    ojson refs = ojson::array();
    for (const StackReference& r : stack.references) {
        ojson e = ojson::object();
        e["file"] = r.file;
        put(e, "focus_distance", r.focus_distance);
        put(e, "f_number", r.f_number);
        put(e, "focal_length_mm", r.focal_length_mm);
        put(e, "sensor_width_mm", r.sensor_width_mm);
        put(e, "near", r.near);
        put(e, "far", r.far);
        put(e, "focus_disparity", r.focus_disparity);
        put(e, "aperture_radius_views", r.aperture_radius_views);
        refs.push_back(std::move(e));
    }
    j["references"] = std::move(refs);
    return j.dump(2) + "\n";
}

}  // namespace gdof
