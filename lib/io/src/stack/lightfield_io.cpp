// Light-field views on disk: discovery (row/column pattern or a Stanford
// archive folder), parallel loading through read_image, and the config
// (geometry, central view, crop) applied to the loaded grid.
#include <algorithm>
#include <atomic>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <mutex>
#include <regex>
#include <string>
#include <vector>

#include "gdof/io/lightfield_io.h"

namespace gdof::io {

namespace {

namespace fs = std::filesystem;

std::string escape_regex(const std::string& s) {
    std::string o;
    for (char c : s) {
        if (std::string(".^$|()[]{}*+?\\").find(c) != std::string::npos) o.push_back('\\');
        o.push_back(c);
    }
    return o;
}

// A file-name pattern split into literal text and printf integer fields.
struct NamePattern {
    std::vector<std::string> literals;  // fields.size() + 1 pieces, "%%" already unescaped
    std::vector<std::string> fields;    // "%02d" ...
};

Result<NamePattern> split_pattern(const std::string& name, const std::string& pattern) {
    NamePattern p;
    std::string lit;
    for (std::size_t i = 0; i < name.size(); ++i) {
        if (name[i] != '%') {
            lit.push_back(name[i]);
            continue;
        }
        if (i + 1 < name.size() && name[i + 1] == '%') {
            lit.push_back('%');
            ++i;
            continue;
        }
        std::size_t j = i + 1;
        while (j < name.size() && std::isdigit(static_cast<unsigned char>(name[j]))) ++j;
        if (j >= name.size() || name[j] != 'd' || j - i - 1 > 2)
            return Status::error("light-field pattern '" + pattern + "': only %d, %Nd and %0Nd fields are supported");
        p.literals.push_back(lit);
        lit.clear();
        p.fields.push_back(name.substr(i, j + 1 - i));
        i = j;
    }
    p.literals.push_back(lit);
    if (p.fields.size() != 2)
        return Status::error("light-field pattern '" + pattern + "': the file name needs two integer fields (row, column), e.g. 'view_%02d_%02d.png'; found " +
                             std::to_string(p.fields.size()));
    return p;
}

std::string format_name(const NamePattern& p, int row, int col) {
    char a[32], b[32];
    std::snprintf(a, sizeof a, p.fields[0].c_str(), row);
    std::snprintf(b, sizeof b, p.fields[1].c_str(), col);
    return p.literals[0] + a + p.literals[1] + b + p.literals[2];
}

// Lays out found (row, col) -> file as a full grid; missing views are errors.
Result<LightFieldFiles> make_grid(const std::map<std::pair<int, int>, std::string>& found,
                                  const std::function<std::string(int, int)>& expected, const std::string& source) {
    if (found.empty()) return Status::error("light field '" + source + "': no views found");
    int r0 = found.begin()->first.first, r1 = r0, c0 = found.begin()->first.second, c1 = c0;
    for (const auto& [rc, f] : found) {
        r0 = std::min(r0, rc.first), r1 = std::max(r1, rc.first);
        c0 = std::min(c0, rc.second), c1 = std::max(c1, rc.second);
    }
    LightFieldFiles g;
    g.first_row = r0, g.first_col = c0;
    g.rows = r1 - r0 + 1, g.cols = c1 - c0 + 1;
    if (std::size_t(g.rows) * std::size_t(g.cols) > 100000)
        return Status::error("light field '" + source + "': indices span " + std::to_string(g.rows) + " x " +
                             std::to_string(g.cols) + " views, too many");
    int missing = 0;
    std::string first_missing;
    for (int r = r0; r <= r1; ++r)
        for (int c = c0; c <= c1; ++c) {
            auto it = found.find({r, c});
            if (it == found.end()) {
                if (missing++ == 0) first_missing = expected(r, c) + " (row " + std::to_string(r) + ", column " + std::to_string(c) + ")";
                continue;
            }
            g.files.push_back(it->second);
        }
    if (missing > 0)
        return Status::error("light field '" + source + "': missing view '" + first_missing + "'" +
                             (missing > 1 ? " and " + std::to_string(missing - 1) + " more" : std::string()) +
                             "; the views must form a full grid, rows " + std::to_string(r0) + ".." +
                             std::to_string(r1) + " x columns " + std::to_string(c0) + ".." + std::to_string(c1));
    return g;
}

Result<LightFieldFiles> find_pattern_views(const std::string& pattern) {
    const fs::path p(pattern);
    const std::string name = p.filename().string();
    const fs::path dir = p.parent_path().empty() ? fs::path(".") : p.parent_path();
    auto np = split_pattern(name, pattern);
    if (!np) return np.status();
    if (p.parent_path().string().find('%') != std::string::npos)
        return Status::error("light-field pattern '" + pattern + "': fields in folder names are not supported");
    std::error_code ec;
    if (!fs::is_directory(dir, ec))
        return Status::error("light-field pattern '" + pattern + "': folder '" + dir.string() + "' does not exist");
    const NamePattern& n = np.value();
    const std::regex rx(escape_regex(n.literals[0]) + "(-?[0-9]+)" + escape_regex(n.literals[1]) + "(-?[0-9]+)" +
                        escape_regex(n.literals[2]));
    std::map<std::pair<int, int>, std::string> found;
    for (const auto& e : fs::directory_iterator(dir, ec)) {
        const std::string f = e.path().filename().string();
        std::smatch m;
        if (!std::regex_match(f, m, rx)) continue;
        if (m[1].length() > 9 || m[2].length() > 9) continue;
        const int r = std::stoi(m[1].str()), c = std::stoi(m[2].str());
        if (format_name(n, r, c) != f) continue;  // "3" where "%02d" wants "03"
        found[{r, c}] = (p.parent_path() / f).string();
    }
    if (ec) return Status::error("light-field pattern '" + pattern + "': cannot list '" + dir.string() + "': " + ec.message());
    if (found.empty())
        return Status::error("light-field pattern '" + pattern + "': no files in '" + dir.string() + "' match it");
    return make_grid(found, [&](int r, int c) { return (p.parent_path() / format_name(n, r, c)).string(); }, pattern);
}

// Stanford Light Field Archive: out_RR_CC_<y>_<x>[_].<ext>.
Result<LightFieldFiles> find_stanford_views(const std::string& folder) {
    static const std::regex rx(R"(out_([0-9]+)_([0-9]+)(_[^/]*)?\.(png|PNG|jpg|JPG|jpeg|tif|tiff|exr))");
    std::map<std::pair<int, int>, std::string> found;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(folder, ec)) {
        const std::string f = e.path().filename().string();
        std::smatch m;
        if (!std::regex_match(f, m, rx) || m[1].length() > 6 || m[2].length() > 6) continue;
        const std::pair<int, int> rc{std::stoi(m[1].str()), std::stoi(m[2].str())};
        const std::string path = (fs::path(folder) / f).string();
        if (auto it = found.find(rc); it != found.end())
            return Status::error("light field '" + folder + "': two files for view (row " + std::to_string(rc.first) +
                                 ", column " + std::to_string(rc.second) + "): '" + it->second + "' and '" + path + "'");
        found[rc] = path;
    }
    if (ec) return Status::error("light field '" + folder + "': cannot list the folder: " + ec.message());
    if (found.empty())
        return Status::error("light field '" + folder +
                             "': no views named like the Stanford archive (out_RR_CC_<y>_<x>.png) in the folder; "
                             "give a pattern with row and column fields instead, e.g. 'views/view_%02d_%02d.png'");
    return make_grid(found,
                     [&](int r, int c) {
                         char b[64];
                         std::snprintf(b, sizeof b, "out_%02d_%02d_*", r, c);
                         return (fs::path(folder) / b).string();
                     },
                     folder);
}

Image crop_image(const Image& v, const Roi& crop) {
    const Roi out_win{0, 0, crop.width(), crop.height()};
    Image out(v.channels(), out_win, out_win);
    out.metadata = v.metadata;
    for (int c = 0; c < v.nchannels(); ++c)
        for (int y = 0; y < crop.height(); ++y)
            for (int x = 0; x < crop.width(); ++x) out.at(c, x, y) = v.at(c, crop.x0 + x, crop.y0 + y);
    return out;
}

}  // namespace

Result<LightFieldFiles> find_lightfield_views(const std::string& source) {
    std::error_code ec;
    if (source.find('%') == std::string::npos && fs::is_directory(source, ec)) return find_stanford_views(source);
    if (source.find('%') == std::string::npos)
        return Status::error("light field '" + source +
                             "': not a folder and not a pattern with row and column fields (e.g. 'views/2067_%02d_%02d.png')");
    return find_pattern_views(source);
}

Result<LightFieldGeometry> lightfield_geometry(const LightFieldConfig& c, int width_px) {
    LightFieldGeometry g;
    g.disparity_at_infinity = c.disparity_at_infinity;
    if (!std::isnan(c.focal_baseline)) {
        g.focal_baseline = c.focal_baseline;
        g.depth_known = true;
    } else if (!std::isnan(c.baseline)) {
        if (!(c.focal_length_mm > 0) || !(c.sensor_width_mm > 0))
            return Status::error("baseline needs focal_length_mm and sensor_width_mm");
        const double f_px = c.focal_length_mm / c.sensor_width_mm * double(width_px);
        g.focal_baseline = f_px * c.baseline;
        g.depth_known = true;
    }
    return g;
}

Result<LightField> load_lightfield(const std::string& source, const LightFieldConfig& config, const ReadOptions& read,
                                   const Exec& exec) {
    auto found = find_lightfield_views(source);
    if (!found) return found.status();
    const LightFieldFiles& files = found.value();
    LightField lf;
    lf.rows = files.rows;
    lf.cols = files.cols;
    lf.sources = files.files;
    lf.views.resize(files.files.size());

    const long n = long(files.files.size());
    std::vector<Status> errors(files.files.size());
    std::atomic<long> done{0};
    const bool finished = parallel_for(
        exec, n,
        [&](long b, long e) {
            for (long i = b; i < e; ++i) {
                const std::string& path = files.files[std::size_t(i)];
                auto r = read_image(path, read);
                if (!r) {
                    const std::string& m = r.message();
                    errors[std::size_t(i)] =
                        Status::error(m.find(path) != std::string::npos ? m : "reading '" + path + "': " + m);
                } else if (r.value().empty() || r.value().is_deep(0)) {
                    errors[std::size_t(i)] = Status::error("light-field view '" + path + "' is not a flat image");
                } else {
                    lf.views[std::size_t(i)] = std::move(r.value().flat(0));
                }
                exec.report(double(++done) / double(n));
            }
        },
        1);
    for (const Status& s : errors)
        if (!s) return s;
    if (!finished) return Status::error("loading light field '" + source + "': cancelled", StatusCode::Cancelled);

    // Sizes and channels before anything else, so errors name the file.
    for (std::size_t i = 1; i < lf.views.size(); ++i) {
        const Image& a = lf.views.front();
        const Image& v = lf.views[i];
        if (v.width() != a.width() || v.height() != a.height())
            return Status::error("light-field view '" + lf.sources[i] + "' is " + std::to_string(v.width()) + "x" +
                                 std::to_string(v.height()) + ", but '" + lf.sources[0] + "' is " +
                                 std::to_string(a.width()) + "x" + std::to_string(a.height()));
    }
    const int full_width = lf.views.front().width();

    // Central view: file indices in the config, else the middle (rounded down).
    int cr = files.first_row + (files.rows - 1) / 2, cc = files.first_col + (files.cols - 1) / 2;
    if (config.center) {
        cr = (*config.center)[0];
        cc = (*config.center)[1];
        if (cr < files.first_row || cr >= files.first_row + files.rows || cc < files.first_col ||
            cc >= files.first_col + files.cols)
            return Status::error("center: view (" + std::to_string(cr) + ", " + std::to_string(cc) +
                                 ") is not in the grid (rows " + std::to_string(files.first_row) + ".." +
                                 std::to_string(files.first_row + files.rows - 1) + ", columns " +
                                 std::to_string(files.first_col) + ".." +
                                 std::to_string(files.first_col + files.cols - 1) + ")");
    }
    lf.center_row = cr - files.first_row;
    lf.center_col = cc - files.first_col;

    if (config.crop) {
        const Roi& crop = *config.crop;
        const Roi dw = lf.views.front().data_window();
        if (!(intersect(crop, dw) == crop))
            return Status::error("crop: " + to_string(crop) + " is not inside the views' data window " + to_string(dw));
        for (Image& v : lf.views) v = crop_image(v, crop);
    }
    auto g = lightfield_geometry(config, full_width);
    if (!g) return g.status();
    lf.geometry = g.value();
    if (auto st = lf.validate(); !st) return st;
    return lf;
}

}  // namespace gdof::io
