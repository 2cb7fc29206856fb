#include "gdof/io/stack_sources.h"

#include <cmath>
#include <filesystem>
#include <optional>
#include <vector>

#include "gdof/io/sequence.h"
#include "gdof/text_file.h"
#include "common/json_read.h"
#include "files/files.h"
#include "oiio/oiio_io.h"

namespace gdof::io {

namespace {

namespace fs = std::filesystem;
using json = json_read::json;
using json_read::Object;
using json_read::Value;

struct Header {
    int width = 0, height = 0;
    std::optional<double> focus_distance, f_number, focal_length_mm, sensor_width_mm;
};

Result<Header> read_header(const std::string& path) {
    const Result<detail::OiioHeader> spec = detail::read_oiio_header(path);
    if (!spec) return Status::error("'" + path + "': cannot read the header (" + spec.status().message() + ")");
    Header h;
    h.width = spec->display.width() > 0 ? spec->display.width() : spec->data.width();
    h.height = spec->display.height() > 0 ? spec->display.height() : spec->data.height();
    // The first attribute of that name in any case (as OIIO's find_attribute
    // looks), when it is one float, int or double.
    auto get = [&](const char* name) -> std::optional<double> {
        const std::string want = detail::lower(name);
        for (const Attribute& a : spec->attributes.attributes()) {
            if (detail::lower(a.name) != want) continue;
            if (a.numbers.size() != 1 || (a.type != "float" && a.type != "int" && a.type != "double"))
                return std::nullopt;
            return a.numbers[0];
        }
        return std::nullopt;
    };
    h.focus_distance = get("focusDistance");
    if (!h.focus_distance) h.focus_distance = get("focus");  // OpenEXR standard attribute
    h.f_number = get("fNumber");
    if (!h.f_number) h.f_number = get("aperture");
    if (!h.f_number) h.f_number = get("FNumber");  // OIIO's name for EXR "aperture"
    h.focal_length_mm = get("focalLength");
    h.sensor_width_mm = get("sensorWidth");
    return h;
}

std::string resolve(const std::string& base, const std::string& p) {
    return fs::path(p).is_absolute() || base.empty() ? p : (fs::path(base) / p).string();
}

Status expand_from_attributes(json& j, const std::string& base, const std::string& pattern) {
    const std::string full = resolve(base, pattern);
    auto frames = frames_on_disk(full);
    if (!frames) return frames.status();
    if (frames->empty()) return Status::error("pattern '" + pattern + "': no files on disk");
    json refs = json::array();
    for (int frame : *frames) {
        auto file = expand_frame_pattern(pattern, frame);
        if (!file) return file.status();
        auto h = read_header(resolve(base, *file));
        if (!h) return h.status();
        if (!j.contains("width")) j["width"] = h->width;
        if (!j.contains("height")) j["height"] = h->height;
        json r;
        r["file"] = *file;
        if (!h->focus_distance) return Status::error("'" + *file + "': no focusDistance or focus attribute");
        if (!h->f_number) return Status::error("'" + *file + "': no fNumber or aperture attribute");
        r["focus_distance"] = *h->focus_distance;
        r["f_number"] = *h->f_number;
        if (h->focal_length_mm) r["focal_length_mm"] = *h->focal_length_mm;
        if (h->sensor_width_mm) r["sensor_width_mm"] = *h->sensor_width_mm;
        refs.push_back(r);
    }
    j["references"] = refs;
    return Status::ok();
}

Status expand_from_table(json& j, const std::string& base, const std::string& pattern, const std::string& table) {
    const std::string tpath = resolve(base, table);
    const Result<std::string> text = read_text(tpath, "table");
    if (!text) return text.status();
    const std::string source = "table '" + tpath + "'";
    const auto rows = read_lens_table(*text, source);
    if (!rows) return rows.status();
    json refs = json::array();
    for (const LensTableRow& row : *rows) {
        json r;
        if (row.file) r["file"] = *row.file;
        if (row.frame) {
            const std::string where = source + " line " + std::to_string(row.line) + " column 'frame'";
            if (pattern.empty()) return Status::error(where + ": a 'frame' column needs \"pattern\" in the manifest");
            auto file = expand_frame_pattern(pattern, int(*row.frame));
            if (!file) return file.status();
            r["file"] = *file;
        }
        for (const auto& [column, v] : row.values) {
            if (std::isinf(v)) r[column] = "inf";
            else r[column] = v;
        }
        refs.push_back(r);
    }
    if (refs.empty()) return Status::error(source + ": no rows");
    if (!j.contains("width") || !j.contains("height")) {
        auto h = read_header(resolve(base, refs[0]["file"].get<std::string>()));
        if (!h) return h.status();
        if (!j.contains("width")) j["width"] = h->width;
        if (!j.contains("height")) j["height"] = h->height;
    }
    j["references"] = refs;
    return Status::ok();
}

// A manifest with "pattern" / "table" / "lens_from" -> the same manifest
// listing its references; any other manifest as it is.
json expand(json j, const std::string& base) {
    if (!j.is_object() || (!j.contains("pattern") && !j.contains("table") && !j.contains("lens_from"))) return j;
    const Object o = Value(j, "").object();
    if (o.has("references")) o.fail("give \"references\" or \"pattern\"/\"table\", not both");
    const std::string pattern = o.has("pattern") ? o.get("pattern").string() : std::string();
    const std::string lens_from =
        o.has("lens_from") ? o.get("lens_from").string() : std::string(o.has("table") ? "table" : "attributes");
    Status st;
    if (lens_from == "attributes" && !o.has("table")) {
        if (pattern.empty()) json_read::fail("lens_from", "\"attributes\" needs \"pattern\"", StatusCode::NotFound);
        st = expand_from_attributes(j, base, pattern);
    } else if (o.has("table")) {
        st = expand_from_table(j, base, pattern, o.get("table").string());
    } else {
        json_read::fail("lens_from", "must be \"attributes\", or give a \"table\" (CSV file)");
    }
    if (!st) json_read::fail("", st);
    for (const char* k : {"pattern", "table", "lens_from"}) j.erase(k);
    return j;
}

}  // namespace

Result<FocalStack> load_stack(const std::string& manifest_path) {
    const std::string where = "stack manifest '" + manifest_path + "'";
    const Result<std::string> text = read_text(manifest_path, "stack manifest");
    if (!text) return text.status();
    std::error_code ec;
    const std::string base = fs::absolute(fs::path(manifest_path), ec).parent_path().string();
    Result<json> doc = json_read::parse(text.value());
    if (!doc) return json_read::with_source(doc.status(), where);
    const Result<json> manifest = json_read::catch_errors(where, [&] { return expand(std::move(doc).value(), base); });
    if (!manifest) return manifest.status();
    auto stack = parse_stack_manifest(manifest->dump(), base);
    if (!stack) return stack.status().prefix("'" + manifest_path + "'");
    return stack;
}

}  // namespace gdof::io
