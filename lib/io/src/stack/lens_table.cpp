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

}  // namespace gdof::io
