// The lens table (CSV) of a stack: header, rows, number cells. One reader for
// the manifests' "table" files and the OFX plugin's lens_table parameter, so
// both accept the same text and report a bad cell the same way.
#include <algorithm>
#include <cmath>
#include <limits>

#include "gdof/io/stack_sources.h"

namespace gdof::io {

namespace {

const char* const kNumberColumns[] = {"focus_distance", "f_number", "focal_length_mm", "sensor_width_mm", "near", "far"};

std::vector<std::string> split_csv_line(const std::string& line) {
    std::vector<std::string> out;
    std::string cur;
    for (char c : line) {
        if (c == ',') {
            out.push_back(cur);
            cur.clear();
        } else if (c != '\r') {
            cur += c;
        }
    }
    out.push_back(cur);
    for (auto& s : out) {
        const auto b = s.find_first_not_of(" \t"), e = s.find_last_not_of(" \t");
        s = b == std::string::npos ? std::string() : s.substr(b, e - b + 1);
    }
    return out;
}

// A number cell: finite, as JSON numbers are (no "nan", "inf" or overflow).
std::optional<double> number_cell(const std::string& cell) {
    std::size_t used = 0;
    double v = 0;
    try {
        v = std::stod(cell, &used);
    } catch (...) {
        return std::nullopt;
    }
    if (used == 0 || used != cell.size() || !std::isfinite(v)) return std::nullopt;
    return v;
}

Status check_header(const std::vector<std::string>& header, const std::string& source, LensTableKey key) {
    const bool files = key == LensTableKey::FrameOrFile;
    bool has_key = false;
    for (const std::string& h : header) {
        const bool is_key = h == "frame" || (files && h == "file");
        const bool known = is_key || std::any_of(std::begin(kNumberColumns), std::end(kNumberColumns),
                                                 [&](const char* k) { return h == k; });
        if (!known)
            return Status::error(source + ": unknown column '" + h + "' (known: frame, " + (files ? "file, " : "") +
                                 "focus_distance, f_number, focal_length_mm, sensor_width_mm, near, far)");
        has_key = has_key || is_key;
    }
    if (!has_key) return Status::error(source + (files ? ": needs a 'frame' or 'file' column" : ": needs a 'frame' column"));
    return Status::ok();
}

}  // namespace

Result<std::vector<LensTableRow>> read_lens_table(const std::string& text, const std::string& source, LensTableKey key) {
    std::vector<std::string> header;
    std::vector<LensTableRow> rows;
    int lineno = 0;
    for (std::size_t pos = 0; pos < text.size();) {
        std::size_t end = text.find('\n', pos);
        if (end == std::string::npos) end = text.size();
        const std::string line = text.substr(pos, end - pos);
        pos = end + 1;
        ++lineno;
        if (line.find_first_not_of(" \t\r") == std::string::npos || line[line.find_first_not_of(" \t")] == '#') continue;
        const std::vector<std::string> cells = split_csv_line(line);
        if (header.empty()) {
            if (Status st = check_header(cells, source, key); !st) return st;
            header = cells;
            continue;
        }
        if (cells.size() != header.size())
            return Status::error(source + " line " + std::to_string(lineno) + ": " + std::to_string(cells.size()) +
                                 " cells, the header has " + std::to_string(header.size()));
        LensTableRow row;
        row.line = lineno;
        for (std::size_t c = 0; c < header.size(); ++c) {
            const std::string& h = header[c];
            if (h == "file") {
                row.file = cells[c];
                continue;
            }
            if (h == "far" && cells[c] == "inf") {
                row.values.emplace_back(h, std::numeric_limits<double>::infinity());
                continue;
            }
            const std::optional<double> number = number_cell(cells[c]);
            if (!number)
                return Status::error(source + " line " + std::to_string(lineno) + " column '" + h + "': not a number: '" +
                                     cells[c] + "'");
            if (h == "frame") row.frame = *number;
            else row.values.emplace_back(h, *number);
        }
        rows.push_back(std::move(row));
    }
    return rows;
}

Result<LensOverrides> lens_at_frame(const std::vector<LensTableRow>& rows, double frame, const std::string& source) {
    if (rows.empty()) return Status::error(source + ": no rows", StatusCode::InvalidArgument);
    for (const LensTableRow& r : rows) {
        if (!r.frame)
            return Status::error(source + " line " + std::to_string(r.line) + ": no frame", StatusCode::InvalidArgument);
        for (const auto& [name, v] : r.values) {
            if (name == "near" || name == "far")
                return Status::error(source + ": column '" + name + "' is a focal stack's (a lens over frames has "
                                              "focus_distance, f_number, focal_length_mm, sensor_width_mm)",
                                     StatusCode::InvalidArgument);
            if (!(v > 0.0))
                return Status::error(source + " line " + std::to_string(r.line) + " column '" + name +
                                         "': must be positive, got " + std::to_string(v),
                                     StatusCode::InvalidArgument);
        }
    }
    // Rows in frame order (the table's may be any).
    std::vector<const LensTableRow*> by_frame;
    for (const LensTableRow& r : rows) by_frame.push_back(&r);
    std::stable_sort(by_frame.begin(), by_frame.end(), [](const LensTableRow* a, const LensTableRow* b) { return *a->frame < *b->frame; });
    for (std::size_t i = 1; i < by_frame.size(); ++i)
        if (*by_frame[i]->frame == *by_frame[i - 1]->frame)
            return Status::error(source + " lines " + std::to_string(by_frame[i - 1]->line) + " and " +
                                     std::to_string(by_frame[i]->line) + ": two rows of frame " +
                                     std::to_string(*by_frame[i]->frame),
                                 StatusCode::InvalidArgument);
    // The rows at or around the frame: a and b, b's weight t.
    std::size_t hi = 0;
    while (hi < by_frame.size() && *by_frame[hi]->frame < frame) ++hi;
    const LensTableRow& a = *by_frame[hi == 0 ? 0 : hi - 1];
    const LensTableRow& b = *by_frame[hi == by_frame.size() ? hi - 1 : hi];
    const double t = &a == &b ? 0.0 : (frame - *a.frame) / (*b.frame - *a.frame);
    // A row's own values exactly; between rows linear, the focus in 1 / distance.
    auto between = [t](double va, double vb, bool inverse) {
        if (t == 0.0 || t == 1.0) return t == 0.0 ? va : vb;
        return inverse ? 1.0 / (1.0 / va + t * (1.0 / vb - 1.0 / va)) : va + t * (vb - va);
    };
    LensOverrides lens;
    for (std::size_t c = 0; c < a.values.size(); ++c) {
        const auto& [name, va] = a.values[c];
        const double vb = b.values[c].second;  // every row has the header's columns, in its order
        if (name == "focus_distance") lens.focus_distance = between(va, vb, true);
        else if (name == "f_number") lens.f_number = between(va, vb, false);
        else if (name == "focal_length_mm") lens.focal_length_mm = between(va, vb, false);
        else if (name == "sensor_width_mm") lens.sensor_width_mm = between(va, vb, false);
    }
    return lens;
}

}  // namespace gdof::io
