#include "focal_stack_params.h"

#include <charconv>
#include <cmath>

#include <nlohmann/json.hpp>

#include "gdof/io/stack_sources.h"

namespace gdof::ofx {

namespace {

using json = nlohmann::json;

const std::vector<std::string> kStackSources = {"frames", "files"};
const std::vector<std::string> kFocusSources = {"surfaces", "surfaces_file", "maps"};
const std::vector<std::string> kGrids = {"1x1", "2x2", "3x3", "4x4"};
const std::vector<std::string> kChannels = {"R", "G", "B", "A"};

std::string cp_name(const char* which, int row, int col) {
    return std::string(which) + "_" + std::to_string(row) + std::to_string(col);
}

// The lens table as manifest references ("file" is "frame N"), read as the
// CLI reads a manifest's table.
Result<json> table_references(const std::string& table, std::vector<int>& frames) {
    const std::string source = "parameter 'lens_table'";
    const auto rows = io::read_lens_table(table, source, io::LensTableKey::Frame);
    if (!rows) return rows.status();
    json refs = json::array();
    for (const io::LensTableRow& row : *rows) {
        json r;
        const double frame = *row.frame;  // the Frame key: every row has one
        if (frame != double(int(frame))) {
            char shortest[32];
            const auto printed = std::to_chars(shortest, shortest + sizeof shortest, frame);
            return Status::error(source + " line " + std::to_string(row.line) + " column 'frame': not a whole number: " +
                                 std::string(shortest, printed.ptr));
        }
        frames.push_back(int(frame));
        r["file"] = "frame " + std::to_string(int(frame));
        for (const auto& [column, v] : row.values) {
            if (std::isinf(v)) r[column] = "inf";
            else r[column] = v;
        }
        refs.push_back(r);
    }
    if (refs.empty()) return Status::error(source + ": no rows (a header such as 'frame,focus_distance,f_number' and one row per frame)");
    return refs;
}

}  // namespace

void describe_focal_stack_params(ParamDefiner& d) {
    const FocalStackParams def;
    d.set_group("");
    d.choice("stack_source", "Stack", kStackSources, 0,
             "frames: the frames of the Source clip, one focus/aperture setting each (lens_table or manifest); "
             "files: the files of a stack manifest");
    d.text("manifest", "Manifest", "", kOfxParamStringIsFilePath,
           "Stack manifest (JSON, as for gdof --composite). frames: reference i is Source frame first_frame + i");
    d.text("lens_table", "Lens Table", "frame,focus_distance,f_number\n", kOfxParamStringIsMultiLine,
           "frames without a manifest: CSV with a header row: frame and any of focus_distance, f_number, "
           "focal_length_mm, sensor_width_mm, near, far (far may be inf)");
    d.integer("first_frame", "First Frame", def.first_frame, -1000000, 1000000, "frames + manifest: Source frame of the first reference");
    d.number("coc_px", "Acceptable CoC (px)", def.coc_px, 1e-6, 1000, 0.1, 10,
             "Acceptable circle of confusion radius, for near/far computed from a lens");
    d.number("focal_length_mm", "Focal Length (mm)", def.focal_length_mm, 0.1, 10000, 10, 300, "Lens table default");
    d.number("sensor_width_mm", "Sensor Width (mm)", def.sensor_width_mm, 0.1, 1000, 5, 70, "Lens table default");
    d.number("scene_unit_mm", "Scene Unit (mm)", def.scene_unit_mm, 1e-6, 1e9, 1, 1000, "Millimetres per depth unit");
    d.integer("soft", "Soft", def.soft, 1, 16, "1: the paper's hard pick; K: blend the best K references");

    d.group("grp_focus", "Desired Focus");
    d.set_group("grp_focus");
    d.choice("focus_source", "Focus From", kFocusSources, 0,
             "surfaces: the control points below; surfaces_file: a surfaces JSON; maps: the Near and Far clips");
    d.text("surfaces", "Surfaces File", "", kOfxParamStringIsFilePath, "Near/far focus surfaces (JSON, as for gdof --surfaces)");
    d.choice("grid", "Control Grid", kGrids, 1, "Control points per side of the near and far B-spline surfaces");
    d.boolean("interpolate", "Interpolate", false, "The surfaces pass through the control values (else approximate them)");
    d.boolean("far_infinite", "Far at Infinity", false, "The far surface is at infinity (ignores the far values)");
    d.choice("map_channel", "Map Channel", kChannels, 0, "maps: channel of the Near and Far clips");
    for (const char* which : {"near", "far"}) {
        for (int r = 0; r < kMaxGrid; ++r)
            for (int c = 0; c < kMaxGrid; ++c) {
                const std::string n = cp_name(which, r, c);
                const std::string label = std::string(which) + " [" + std::to_string(r) + "," + std::to_string(c) + "]";
                d.number(n.c_str(), label.c_str(), which[0] == 'n' ? 1.0 : 3.0, 0, 1e9, 0.1, 100,
                         "Control depth (row from the top, column from the left), depth units");
            }
    }
    d.set_group("");
}

FocalStackParams read_focal_stack_params(const ParamReader& r) {
    FocalStackParams p;
    p.stack_source = r.option("stack_source", kStackSources);
    p.manifest = r.text("manifest");
    p.lens_table = r.text("lens_table");
    p.first_frame = r.integer("first_frame");
    p.coc_px = r.number("coc_px");
    p.focal_length_mm = r.number("focal_length_mm");
    p.sensor_width_mm = r.number("sensor_width_mm");
    p.scene_unit_mm = r.number("scene_unit_mm");
    p.soft = r.integer("soft");
    p.focus_source = r.option("focus_source", kFocusSources);
    p.surfaces = r.text("surfaces");
    p.grid = r.choice("grid") + 1;
    if (p.grid < 1 || p.grid > kMaxGrid) fail("parameter 'grid': option out of range");
    p.interpolate = r.boolean("interpolate");
    p.far_infinite = r.boolean("far_infinite");
    p.map_channel = r.option("map_channel", kChannels);
    for (int row = 0; row < p.grid; ++row)
        for (int col = 0; col < p.grid; ++col) {
            p.near.push_back(r.number(cp_name("near", row, col).c_str()));
            p.far.push_back(r.number(cp_name("far", row, col).c_str()));
        }
    return p;
}

std::string surfaces_json(const FocalStackParams& p) {
    auto grid = [&](const std::vector<double>& v) {
        json rows = json::array();
        for (int r = 0; r < p.grid; ++r) {
            json row = json::array();
            for (int c = 0; c < p.grid; ++c) row.push_back(v[std::size_t(r * p.grid + c)]);
            rows.push_back(row);
        }
        return rows;
    };
    json j;
    j["gdof_surfaces"] = 1;
    j["interpolate"] = p.interpolate;
    j["near"] = {{"grid", grid(p.near)}};
    if (p.far_infinite) j["far"] = "inf";
    else j["far"] = {{"grid", grid(p.far)}};
    return j.dump();
}

Result<FrameStack> frame_stack(const FocalStackParams& p, int width, int height) {
    FrameStack fs;
    if (!p.manifest.empty()) {
        auto s = io::load_stack(p.manifest);
        if (!s) return s.status().prefix("parameter 'manifest'");
        fs.stack = std::move(s).value();
        for (std::size_t i = 0; i < fs.stack.references.size(); ++i) fs.frames.push_back(p.first_frame + int(i));
        return fs;
    }
    json m;
    m["gdof_stack"] = 1;
    m["coc_px"] = p.coc_px;
    m["scene_unit_mm"] = p.scene_unit_mm;
    m["focal_length_mm"] = p.focal_length_mm;
    m["sensor_width_mm"] = p.sensor_width_mm;
    if (width > 0 && height > 0) {
        m["width"] = width;
        m["height"] = height;
    }
    auto refs = table_references(p.lens_table, fs.frames);
    if (!refs) return refs.status();
    m["references"] = std::move(refs).value();
    auto s = parse_stack_manifest(m.dump(), "");
    if (!s) return s.status().prefix("parameter 'lens_table'");
    fs.stack = std::move(s).value();
    return fs;
}

}  // namespace gdof::ofx
