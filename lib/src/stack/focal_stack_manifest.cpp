// Focus/aperture stack manifests (focal_stack.h): JSON <-> FocalStack.
// Errors name the key path ("references[3].f_number: must be > 0, got -2");
// malformed JSON reports nlohmann's byte position.
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "gdof/camera.h"
#include "gdof/focal_stack.h"
#include "common/json_util.h"

namespace gdof {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

using namespace json_util;
const auto& num = format_number;

void allow_only(const json& j, const std::string& path, const std::vector<std::string>& keys) {
    for (auto it = j.begin(); it != j.end(); ++it)
        if (std::find(keys.begin(), keys.end(), it.key()) == keys.end()) {
            std::string list;
            for (const auto& k : keys) list += (list.empty() ? "" : ", ") + k;
            fail(path.empty() ? it.key() : path + "." + it.key(), "unknown key (allowed: " + list + ")");
        }
}

// A finite number, or (allow_inf) the string "inf" / a JSON number that is +inf.
double number(const json& v, const std::string& path, bool allow_inf = false) {
    if (allow_inf && v.is_string() && (v.get<std::string>() == "inf" || v.get<std::string>() == "infinity"))
        return kInf;
    if (!v.is_number()) fail(path, std::string("must be a number") + (allow_inf ? " or \"inf\"" : "") + ", got " + type_name(v));
    const double d = v.get<double>();
    if (!std::isfinite(d)) fail(path, "must be finite, got " + num(d));
    return d;
}

double positive(const json& v, const std::string& path) {
    const double d = number(v, path);
    if (!(d > 0)) fail(path, "must be > 0, got " + num(d));
    return d;
}

int dimension(const json& v, const std::string& path) {
    if (!v.is_number_integer()) fail(path, "must be an integer, got " + type_name(v));
    const long long n = v.get<long long>();
    if (n < 0 || n > 1000000) fail(path, "must be 0 (unknown) to 1000000, got " + std::to_string(n));
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

StackReference parse_reference(const json& j, const std::string& path, const FocalStack& stack) {
    if (!j.is_object()) fail(path, "must be an object, got " + type_name(j));
    allow_only(j, path,
               {"file", "focus_distance", "f_number", "focal_length_mm", "sensor_width_mm", "near", "far",
                "focus_disparity", "aperture_radius_views", "comment"});
    StackReference r;
    auto key = [&](const char* k) { return path + "." + k; };
    if (!j.contains("file")) fail(key("file"), "missing required key");
    if (!j["file"].is_string() || j["file"].get<std::string>().empty())
        fail(key("file"), "must be a non-empty string, got " + type_name(j["file"]));
    r.file = j["file"].get<std::string>();
    r.path = join_path(stack.base_dir, r.file);

    if (j.contains("focus_distance")) r.focus_distance = positive(j["focus_distance"], key("focus_distance"));
    if (j.contains("f_number")) r.f_number = positive(j["f_number"], key("f_number"));
    if (j.contains("focal_length_mm")) r.focal_length_mm = positive(j["focal_length_mm"], key("focal_length_mm"));
    if (j.contains("sensor_width_mm")) r.sensor_width_mm = positive(j["sensor_width_mm"], key("sensor_width_mm"));
    if (j.contains("near")) {
        r.near = number(j["near"], key("near"));
        if (r.near < 0) fail(key("near"), "must be >= 0, got " + num(r.near));
    }
    if (j.contains("far")) {
        r.far = number(j["far"], key("far"), true);
        if (r.far < 0) fail(key("far"), "must be >= 0, got " + num(r.far));
    }
    if (j.contains("focus_disparity")) r.focus_disparity = number(j["focus_disparity"], key("focus_disparity"));
    if (j.contains("aperture_radius_views")) {
        r.aperture_radius_views = number(j["aperture_radius_views"], key("aperture_radius_views"));
        if (r.aperture_radius_views < 0)
            fail(key("aperture_radius_views"), "must be >= 0, got " + num(r.aperture_radius_views));
    }

    const bool explicit_limits = !std::isnan(r.near) && !std::isnan(r.far);
    if (!explicit_limits) {
        // From the thin lens: everything it needs must be known.
        if (std::isnan(r.focus_distance))
            fail(key("focus_distance"), "missing required key (needed to compute near/far from the thin lens)");
        if (std::isnan(r.f_number))
            fail(key("f_number"), "missing required key (needed to compute near/far from the thin lens)");
        ThinLens lens;
        lens.focus_distance = r.focus_distance;
        lens.f_number = r.f_number;
        lens.focal_length_mm = std::isnan(r.focal_length_mm) ? stack.focal_length_mm : r.focal_length_mm;
        lens.sensor_width_mm = std::isnan(r.sensor_width_mm) ? stack.sensor_width_mm : r.sensor_width_mm;
        lens.scene_unit_mm = stack.scene_unit_mm;
        lens.image_width_px = stack.width;
        if (std::isnan(lens.focal_length_mm))
            fail(key("focal_length_mm"),
                 "missing (give it here or at the top level, or give \"near\" and \"far\" explicitly)");
        if (std::isnan(lens.sensor_width_mm))
            fail(key("sensor_width_mm"),
                 "missing (give it here or at the top level, or give \"near\" and \"far\" explicitly)");
        if (stack.width <= 0)
            fail("width", "missing or 0: the image width in pixels is needed to compute " + path +
                              ".near/far from the thin lens for coc_px");
        if (Status s = lens.validate(); !s) fail(path, "thin lens: " + s.message());
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
    json j;
    try {
        j = json::parse(text);
    } catch (const json::exception& e) {
        return Status::error(std::string("stack manifest JSON: ") + e.what());
    }
    try {
        if (!j.is_object()) fail("top level", "must be an object {\"gdof_stack\": 1, \"references\": [...]}, got " + type_name(j));
        allow_only(j, "",
                   {"gdof_stack", "coc_px", "scene_unit_mm", "focal_length_mm", "sensor_width_mm", "width", "height",
                    "references", "comment", "source"});
        FocalStack s;
        s.base_dir = base_dir;
        if (j.contains("gdof_stack")) {
            const json& v = j["gdof_stack"];
            if (!v.is_number_integer() || v.get<long long>() != 1)
                fail("gdof_stack", "unsupported manifest version " + v.dump() + " (this gdof reads version 1)");
        }
        if (j.contains("coc_px")) {
            s.coc_px = number(j["coc_px"], "coc_px");
            if (s.coc_px < 0) fail("coc_px", "must be >= 0, got " + num(s.coc_px));
        }
        if (j.contains("scene_unit_mm")) s.scene_unit_mm = positive(j["scene_unit_mm"], "scene_unit_mm");
        if (j.contains("focal_length_mm")) s.focal_length_mm = positive(j["focal_length_mm"], "focal_length_mm");
        if (j.contains("sensor_width_mm")) s.sensor_width_mm = positive(j["sensor_width_mm"], "sensor_width_mm");
        if (j.contains("width")) s.width = dimension(j["width"], "width");
        if (j.contains("height")) s.height = dimension(j["height"], "height");
        if (!j.contains("references")) fail("references", "missing required key");
        const json& refs = j["references"];
        if (!refs.is_array()) fail("references", "must be an array, got " + type_name(refs));
        if (refs.empty()) fail("references", "must list at least one reference image");
        for (std::size_t i = 0; i < refs.size(); ++i)
            s.references.push_back(parse_reference(refs[i], "references[" + std::to_string(i) + "]", s));
        check_duplicates(s);
        return s;
    } catch (const JsonError& e) {
        return Status::error("stack manifest: " + e.message);
    }
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
