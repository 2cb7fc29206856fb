// lf.json (light-field geometry) and stack.json (references to extract)
// parsers; formats in docs/lightfield.md. Errors name the file and key.
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "gdof/io/lightfield_io.h"

namespace gdof::io {

namespace {

using json = nlohmann::json;
constexpr double kInf = std::numeric_limits<double>::infinity();

struct Fail {
    std::string message;
};
[[noreturn]] void fail(const std::string& key, const std::string& what) { throw Fail{key + ": " + what}; }

std::string kind(const json& j) {
    if (j.is_string()) return "string \"" + j.get<std::string>() + "\"";
    return j.type_name();
}

void allow_only(const json& obj, const std::string& path, const std::vector<std::string>& keys) {
    if (!obj.is_object()) fail(path.empty() ? "top level" : path, "must be an object, got " + kind(obj));
    for (auto it = obj.begin(); it != obj.end(); ++it) {
        bool ok = false;
        for (const auto& k : keys) ok = ok || k == it.key();
        if (!ok) {
            std::string list;
            for (std::size_t i = 0; i < keys.size(); ++i) list += (i ? ", " : "") + keys[i];
            fail((path.empty() ? "" : path + ".") + it.key(), "unknown key (expected one of " + list + ")");
        }
    }
}

// A number, or "inf" where allowed.
double number(const json& j, const std::string& key, bool allow_inf = false) {
    if (j.is_number()) return j.get<double>();
    if (allow_inf && j.is_string() && (j.get<std::string>() == "inf" || j.get<std::string>() == "infinity")) return kInf;
    fail(key, std::string("must be a number") + (allow_inf ? " or \"inf\"" : "") + ", got " + kind(j));
}

double positive(const json& j, const std::string& key) {
    const double v = number(j, key);
    if (!(v > 0) || !std::isfinite(v)) fail(key, "must be a positive number, got " + j.dump());
    return v;
}

int integer(const json& j, const std::string& key) {
    if (!j.is_number_integer()) fail(key, "must be an integer, got " + kind(j));
    return j.get<int>();
}

json parse_text(const std::string& text, const std::string& where) {
    try {
        return json::parse(text, nullptr, true, /*ignore_comments=*/true);
    } catch (const json::parse_error& e) {
        throw Fail{"malformed JSON (byte " + std::to_string(e.byte) + "): " + e.what()};
    }
}

Result<std::string> read_text(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return Status::error("cannot open '" + path + "'");
    std::ostringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

}  // namespace

Result<LightFieldConfig> parse_lightfield_config(const std::string& text, const std::string& where) {
    try {
        const json j = parse_text(text, where);
        allow_only(j, "", {"gdof_lightfield", "disparity_at_infinity", "focal_baseline", "baseline", "focal_length_mm",
                           "sensor_width_mm", "scene_unit_mm", "center", "crop", "comment"});
        LightFieldConfig c;
        if (j.contains("gdof_lightfield") && integer(j["gdof_lightfield"], "gdof_lightfield") != 1)
            fail("gdof_lightfield", "unsupported version " + j["gdof_lightfield"].dump() + " (expected 1)");
        if (j.contains("disparity_at_infinity")) {
            c.disparity_at_infinity = number(j["disparity_at_infinity"], "disparity_at_infinity");
            if (!std::isfinite(c.disparity_at_infinity)) fail("disparity_at_infinity", "must be finite");
        }
        if (j.contains("focal_baseline")) {
            c.focal_baseline = number(j["focal_baseline"], "focal_baseline");
            if (!std::isfinite(c.focal_baseline) || c.focal_baseline == 0)
                fail("focal_baseline", "must be a finite non-zero number, got " + j["focal_baseline"].dump());
        }
        if (j.contains("baseline")) {
            if (j.contains("focal_baseline")) fail("baseline", "give either focal_baseline or baseline, not both");
            c.baseline = number(j["baseline"], "baseline");
            if (!std::isfinite(c.baseline) || c.baseline == 0)
                fail("baseline", "must be a finite non-zero number (scene units per view step), got " +
                                     j["baseline"].dump());
            for (const char* k : {"focal_length_mm", "sensor_width_mm"})
                if (!j.contains(k)) fail(k, "required with baseline (focal length in pixels = focal_length_mm / sensor_width_mm * width)");
        }
        if (j.contains("focal_length_mm")) c.focal_length_mm = positive(j["focal_length_mm"], "focal_length_mm");
        if (j.contains("sensor_width_mm")) c.sensor_width_mm = positive(j["sensor_width_mm"], "sensor_width_mm");
        if (j.contains("scene_unit_mm")) c.scene_unit_mm = positive(j["scene_unit_mm"], "scene_unit_mm");
        if (j.contains("center")) {
            const json& a = j["center"];
            if (!a.is_array() || a.size() != 2)
                fail("center", "must be [row, column] (file indices of the central view), got " + a.dump());
            c.center = std::array<int, 2>{integer(a[0], "center[0]"), integer(a[1], "center[1]")};
        }
        if (j.contains("crop")) {
            const json& o = j["crop"];
            allow_only(o, "crop", {"x", "y", "width", "height"});
            for (const char* k : {"x", "y", "width", "height"})
                if (!o.contains(k)) fail(std::string("crop.") + k, "missing");
            const int x = integer(o["x"], "crop.x"), y = integer(o["y"], "crop.y");
            const int w = integer(o["width"], "crop.width"), h = integer(o["height"], "crop.height");
            if (w <= 0) fail("crop.width", "must be > 0, got " + std::to_string(w));
            if (h <= 0) fail("crop.height", "must be > 0, got " + std::to_string(h));
            c.crop = Roi{x, y, x + w, y + h};
        }
        return c;
    } catch (const Fail& f) {
        return Status::error(where + ": " + f.message);
    } catch (const json::exception& e) {
        return Status::error(where + ": " + e.what());
    }
}

Result<LightFieldConfig> read_lightfield_config(const std::string& path) {
    auto t = read_text(path);
    if (!t) return t.status();
    return parse_lightfield_config(t.value(), "'" + path + "'");
}

Result<ExtractStackOptions> parse_extract_stack_options(const std::string& text, const std::string& where) {
    try {
        const json j = parse_text(text, where);
        allow_only(j, "", {"gdof_lightfield_stack", "coc_px", "filter", "references", "disparities", "depths",
                           "apertures", "comment"});
        ExtractStackOptions s;
        if (j.contains("gdof_lightfield_stack") && integer(j["gdof_lightfield_stack"], "gdof_lightfield_stack") != 1)
            fail("gdof_lightfield_stack", "unsupported version " + j["gdof_lightfield_stack"].dump() + " (expected 1)");
        if (j.contains("coc_px")) s.coc_px = positive(j["coc_px"], "coc_px");
        if (j.contains("filter")) {
            if (!j["filter"].is_string()) fail("filter", "must be \"bicubic\" or \"bilinear\", got " + kind(j["filter"]));
            auto f = parse_lightfield_filter(j["filter"].get<std::string>());
            if (!f) fail("filter", f.message());
            s.filter = f.value();
        }
        auto aperture = [](const json& v, const std::string& key) {
            const double r = number(v, key);
            if (!(r >= 0) || !std::isfinite(r)) fail(key, "must be >= 0 (radius in view steps), got " + v.dump());
            return r;
        };
        // The grid form: every focus (disparities, then depths) with every aperture.
        const bool grid = j.contains("disparities") || j.contains("depths");
        if (grid && !j.contains("apertures")) fail("apertures", "required with disparities / depths");
        if (j.contains("apertures") && !grid) fail("apertures", "needs disparities or depths to pair with");
        if (grid) {
            const json& ap = j["apertures"];
            if (!ap.is_array() || ap.empty()) fail("apertures", "must be a non-empty array of radii (view steps)");
            for (const char* list : {"disparities", "depths"}) {
                if (!j.contains(list)) continue;
                const json& a = j[list];
                if (!a.is_array() || a.empty()) fail(list, "must be a non-empty array");
                for (std::size_t i = 0; i < a.size(); ++i) {
                    const std::string key = std::string(list) + "[" + std::to_string(i) + "]";
                    StackRequest q;
                    if (std::string(list) == "disparities") {
                        q.focus_disparity = number(a[i], key);
                        if (!std::isfinite(q.focus_disparity)) fail(key, "must be finite");
                    } else {
                        q.focus_depth = number(a[i], key, true);
                        if (!(q.focus_depth > 0)) fail(key, "must be > 0 or \"inf\", got " + a[i].dump());
                    }
                    for (std::size_t k = 0; k < ap.size(); ++k) {
                        q.aperture_radius = aperture(ap[k], "apertures[" + std::to_string(k) + "]");
                        s.references.push_back(q);
                    }
                }
            }
        }
        if (j.contains("references")) {
            const json& a = j["references"];
            if (!a.is_array()) fail("references", "must be an array, got " + kind(a));
            for (std::size_t i = 0; i < a.size(); ++i) {
                const std::string key = "references[" + std::to_string(i) + "]";
                allow_only(a[i], key, {"disparity", "depth", "aperture"});
                StackRequest q;
                const bool has_d = a[i].contains("disparity"), has_z = a[i].contains("depth");
                if (has_d == has_z) fail(key, "give exactly one of disparity (px per view step) or depth");
                if (has_d) {
                    q.focus_disparity = number(a[i]["disparity"], key + ".disparity");
                    if (!std::isfinite(q.focus_disparity)) fail(key + ".disparity", "must be finite");
                } else {
                    q.focus_depth = number(a[i]["depth"], key + ".depth", true);
                    if (!(q.focus_depth > 0)) fail(key + ".depth", "must be > 0 or \"inf\", got " + a[i]["depth"].dump());
                }
                if (!a[i].contains("aperture")) fail(key + ".aperture", "missing (radius in view steps)");
                q.aperture_radius = aperture(a[i]["aperture"], key + ".aperture");
                s.references.push_back(q);
            }
        }
        if (s.references.empty()) fail("references", "no references (give references, or disparities/depths with apertures)");
        return s;
    } catch (const Fail& f) {
        return Status::error(where + ": " + f.message);
    } catch (const json::exception& e) {
        return Status::error(where + ": " + e.what());
    }
}

Result<ExtractStackOptions> read_extract_stack_options(const std::string& path) {
    auto t = read_text(path);
    if (!t) return t.status();
    return parse_extract_stack_options(t.value(), "'" + path + "'");
}

}  // namespace gdof::io
