// lf.json (light-field geometry) and stack.json (references to extract)
// parsers, read with json_read; formats in docs/lightfield.md. Errors name
// the file and key; both formats allow // and /* */ comments.
#include <cmath>
#include <string>
#include <vector>

#include "gdof/io/lightfield_io.h"
#include "gdof/text_file.h"
#include "common/json_read.h"

namespace gdof::io {

namespace {

using json_read::Comments;
using json_read::Infinity;
using json_read::Object;
using json_read::Value;
using json_read::fail;

// A JSON integer that fits an int.
int integer(const Value& v) { return int(v.integer()); }

// A finite non-zero number (focal_baseline, baseline).
double non_zero(const Value& v, const std::string& what) {
    const double d = v.number();
    if (d == 0) v.fail("must be a finite non-zero number" + what + ", got " + json_read::format_number(d));
    return d;
}

// An optional "gdof_lightfield" / "gdof_lightfield_stack" version: 1.
void check_version(const Object& o, const std::string& key) {
    if (const auto v = o.find(key); v && v->integer() != 1)
        v->fail("unsupported version " + v->raw().dump() + " (expected 1)");
}

LightFieldConfig read_config(const Value& root) {
    const Object o = root.object({"gdof_lightfield", "disparity_at_infinity", "focal_baseline", "baseline",
                                  "focal_length_mm", "sensor_width_mm", "scene_unit_mm", "center", "crop", "comment"});
    LightFieldConfig c;
    check_version(o, "gdof_lightfield");
    if (const auto v = o.find("disparity_at_infinity")) c.disparity_at_infinity = v->number();
    if (const auto v = o.find("focal_baseline")) c.focal_baseline = non_zero(*v, "");
    if (const auto v = o.find("baseline")) {
        if (o.has("focal_baseline")) v->fail("give either focal_baseline or baseline, not both");
        c.baseline = non_zero(*v, " (scene units per view step)");
        for (const char* k : {"focal_length_mm", "sensor_width_mm"})
            o.require(k, "with baseline: focal length in pixels = focal_length_mm / sensor_width_mm * width");
    }
    if (const auto v = o.find("focal_length_mm")) c.focal_length_mm = v->positive();
    if (const auto v = o.find("sensor_width_mm")) c.sensor_width_mm = v->positive();
    if (const auto v = o.find("scene_unit_mm")) c.scene_unit_mm = v->positive();
    if (const auto v = o.find("center")) {
        if (!v->raw().is_array() || v->raw().size() != 2)
            v->fail("must be [row, column] (file indices of the central view), got " + v->raw().dump());
        const std::vector<Value> rc = v->array();
        c.center = std::array<int, 2>{integer(rc[0]), integer(rc[1])};
    }
    if (const auto v = o.find("crop")) {
        const Object crop = v->object({"x", "y", "width", "height"}, {"x", "y", "width", "height"});
        const int x = integer(crop.get("x")), y = integer(crop.get("y"));
        const int w = integer(crop.get("width")), h = integer(crop.get("height"));
        if (w <= 0) fail(crop.path("width"), "must be > 0, got " + std::to_string(w));
        if (h <= 0) fail(crop.path("height"), "must be > 0, got " + std::to_string(h));
        c.crop = Roi{x, y, x + w, y + h};
    }
    return c;
}

// One focus of a request: a disparity (finite), or a depth (> 0, or "inf").
void read_focus(const Value& v, bool disparity, StackRequest& q) {
    if (disparity) q.focus_disparity = v.number();
    else q.focus_depth = v.positive(Infinity::Allowed);
}

ExtractStackOptions read_extract(const Value& root) {
    const Object o = root.object({"gdof_lightfield_stack", "coc_px", "filter", "references", "disparities", "depths",
                                  "apertures", "comment"});
    ExtractStackOptions s;
    check_version(o, "gdof_lightfield_stack");
    if (const auto v = o.find("coc_px")) s.coc_px = v->positive();
    if (const auto v = o.find("filter")) {
        if (!v->raw().is_string()) v->fail("must be \"bicubic\" or \"bilinear\", got " + json_read::type_name(v->raw()));
        auto f = parse_lightfield_filter(v->string());
        if (!f) v->fail(f.message(), f.status().code());
        s.filter = f.value();
    }
    // The grid form: every focus (disparities, then depths) with every aperture.
    const bool grid = o.has("disparities") || o.has("depths");
    if (grid) o.require("apertures", "with disparities / depths");
    if (o.has("apertures") && !grid) fail("apertures", "needs disparities or depths to pair with");
    if (grid) {
        const std::vector<Value> apertures = o.get("apertures").non_empty_array("radii (view steps)");
        for (const char* list : {"disparities", "depths"}) {
            const auto values = o.find(list);
            if (!values) continue;
            for (const Value& f : values->non_empty_array()) {
                StackRequest q;
                read_focus(f, std::string(list) == "disparities", q);
                for (const Value& a : apertures) {
                    q.aperture_radius = a.non_negative();
                    s.references.push_back(q);
                }
            }
        }
    }
    if (const auto refs = o.find("references"))
        for (const Value& r : refs->array()) {
            const Object ro = r.object({"disparity", "depth", "aperture"});
            const bool has_d = ro.has("disparity"), has_z = ro.has("depth");
            if (has_d == has_z) ro.fail("give exactly one of disparity (px per view step) or depth");
            StackRequest q;
            read_focus(ro.get(has_d ? "disparity" : "depth"), has_d, q);
            q.aperture_radius = ro.get("aperture", "radius in view steps").non_negative();
            s.references.push_back(q);
        }
    if (s.references.empty())
        fail("references", "no references (give references, or disparities/depths with apertures)", StatusCode::NotFound);
    return s;
}

// The file's text through `parse`, the file named as the source.
template <class T>
Result<T> read_file(const std::string& path, Result<T> (*parse)(const std::string&, const std::string&)) {
    const Result<std::string> text = read_text(path);
    if (!text) return text.status();
    return parse(text.value(), "'" + path + "'");
}

}  // namespace

Result<LightFieldConfig> parse_lightfield_config(const std::string& text, const std::string& where) {
    return json_read::read_document(text, where, read_config, Comments::Allowed);
}

Result<LightFieldConfig> read_lightfield_config(const std::string& path) { return read_file(path, parse_lightfield_config); }

Result<ExtractStackOptions> parse_extract_stack_options(const std::string& text, const std::string& where) {
    return json_read::read_document(text, where, read_extract, Comments::Allowed);
}

Result<ExtractStackOptions> read_extract_stack_options(const std::string& path) {
    return read_file(path, parse_extract_stack_options);
}

}  // namespace gdof::io
