// Frame ranges and frame-number patterns, as in oiiotool.
//
// Ranges: comma-separated items "A", "A-B", "A-BxN" (every Nth frame),
// "A-ByN" (the frames "A-BxN" leaves out); A > B counts down; frames may be
// negative ("-5--1"). Patterns: a run of N '#' pads to N digits (a lone '#'
// to 4), N '@' pad to N digits, printf "%0Nd" / "%Nd" / "%d". Negative frames
// are formatted like printf's %0Nd, as oiiotool does: the sign counts toward
// the width, so "####" with -5 gives "-005".
#include "gdof/io/sequence.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <regex>
#include <set>

namespace gdof::io {

namespace {

constexpr long long kMaxFrames = 10'000'000;

Status range_error(const std::string& spec, const std::string& why) {
    return Status::error("frame range '" + spec + "': " + why);
}

// Parses an optionally signed integer at s[i]; advances i.
bool parse_int(const std::string& s, std::size_t& i, long long& v) {
    std::size_t j = i;
    bool neg = false;
    if (j < s.size() && (s[j] == '-' || s[j] == '+')) neg = s[j++] == '-';
    std::size_t d0 = j;
    long long x = 0;
    while (j < s.size() && std::isdigit(static_cast<unsigned char>(s[j]))) {
        x = x * 10 + (s[j] - '0');
        if (x > std::numeric_limits<int>::max()) return false;
        ++j;
    }
    if (j == d0) return false;
    v = neg ? -x : x;
    i = j;
    return true;
}

std::string trim(const std::string& s) {
    std::size_t a = s.find_first_not_of(" \t"), b = s.find_last_not_of(" \t");
    return a == std::string::npos ? std::string() : s.substr(a, b - a + 1);
}

// One pattern field inside a path.
struct Field {
    std::size_t pos = 0, len = 0;  // in the path
    std::string printf_fmt;         // e.g. "%04d"
};

std::vector<Field> find_fields(const std::string& p) {
    std::vector<Field> out;
    for (std::size_t i = 0; i < p.size();) {
        if (p[i] == '#' || p[i] == '@') {
            char ch = p[i];
            std::size_t j = i;
            while (j < p.size() && p[j] == ch) ++j;
            std::size_t n = j - i;
            if (ch == '#' && n == 1) n = 4;
            out.push_back({i, j - i, "%0" + std::to_string(n) + "d"});
            i = j;
        } else if (p[i] == '%') {
            if (i + 1 < p.size() && p[i + 1] == '%') {
                i += 2;
                continue;
            }
            std::size_t j = i + 1;
            bool zero = j < p.size() && p[j] == '0';
            if (zero) ++j;
            std::size_t d0 = j;
            while (j < p.size() && std::isdigit(static_cast<unsigned char>(p[j]))) ++j;
            if (j < p.size() && p[j] == 'd' && j - d0 <= 2) {
                std::string width = p.substr(d0, j - d0);
                out.push_back({i, j + 1 - i, std::string("%") + (zero ? "0" : "") + width + "d"});
                i = j + 1;
            } else {
                ++i;
            }
        } else {
            ++i;
        }
    }
    return out;
}

std::string format_field(const Field& f, int frame) {
    char buf[64];
    std::snprintf(buf, sizeof buf, f.printf_fmt.c_str(), frame);
    return buf;
}

}  // namespace

Result<std::vector<int>> parse_frame_range(const std::string& spec_in) {
    const std::string spec = trim(spec_in);
    if (spec.empty()) return range_error(spec_in, "empty");
    std::vector<int> frames;
    std::size_t start = 0;
    while (start <= spec.size()) {
        std::size_t comma = spec.find(',', start);
        std::string item = trim(spec.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
        if (item.empty()) return range_error(spec_in, "empty item");
        std::size_t i = 0;
        long long a = 0, b = 0, step = 1;
        bool complement = false;
        if (!parse_int(item, i, a)) return range_error(spec_in, "'" + item + "' is not a frame number or range");
        b = a;
        if (i < item.size() && item[i] == '-') {
            ++i;
            if (!parse_int(item, i, b)) return range_error(spec_in, "'" + item + "' has no end frame");
            if (i < item.size() && (item[i] == 'x' || item[i] == 'y')) {
                complement = item[i] == 'y';
                ++i;
                std::size_t s0 = i;
                if (!parse_int(item, i, step) || item[s0] == '-' || item[s0] == '+' || step <= 0)
                    return range_error(spec_in, "'" + item + "': the step must be a positive integer");
            }
        }
        if (i != item.size()) return range_error(spec_in, "unexpected '" + item.substr(i) + "' in '" + item + "'");
        const long long dir = b >= a ? 1 : -1;
        const long long count = (b - a) * dir + 1;
        if (count + (long long)frames.size() > kMaxFrames)
            return range_error(spec_in, "more than " + std::to_string(kMaxFrames) + " frames");
        for (long long k = 0; k < count; ++k) {
            const bool on_step = k % step == 0;
            if (on_step != complement) frames.push_back(int(a + dir * k));
        }
        if (comma == std::string::npos) break;
        start = comma + 1;
    }
    return frames;
}

bool has_frame_pattern(const std::string& path) { return !find_fields(path).empty(); }

Result<std::string> expand_frame_pattern(const std::string& pattern, int frame) {
    const auto fields = find_fields(pattern);
    if (fields.empty()) return Status::error("'" + pattern + "': no frame number pattern (#, @ or %0Nd)");
    std::string out;
    std::size_t last = 0;
    for (const auto& f : fields) {
        out += pattern.substr(last, f.pos - last);
        out += format_field(f, frame);
        last = f.pos + f.len;
    }
    out += pattern.substr(last);
    // "%%" stands for a literal '%' in printf-style patterns.
    const bool printf_style = std::any_of(fields.begin(), fields.end(), [&](const Field& f) { return pattern[f.pos] == '%'; });
    if (!printf_style) return out;
    std::string res;
    for (std::size_t i = 0; i < out.size(); ++i) {
        res.push_back(out[i]);
        if (out[i] == '%' && i + 1 < out.size() && out[i + 1] == '%') ++i;
    }
    return res;
}

Result<std::vector<int>> frames_on_disk(const std::string& pattern) {
    namespace fs = std::filesystem;
    const fs::path p(pattern);
    const std::string name = p.filename().string();
    const fs::path dir = p.parent_path().empty() ? fs::path(".") : p.parent_path();
    const auto fields = find_fields(name);
    if (fields.empty()) return Status::error("'" + pattern + "': no frame number pattern (#, @ or %0Nd) in the file name");
    if (has_frame_pattern(p.parent_path().string()))
        return Status::error("'" + pattern + "': frame patterns in folder names are not supported");
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) return Status::error("'" + pattern + "': folder '" + dir.string() + "' does not exist");

    // Candidate names: each field matches a signed number; the exact padding
    // is then checked by expanding the pattern with the number found.
    std::string re;
    std::size_t last = 0;
    auto escape = [](const std::string& s) {
        std::string o;
        for (char c : s) {
            if (std::string(".^$|()[]{}*+?\\").find(c) != std::string::npos) o.push_back('\\');
            o.push_back(c);
        }
        return o;
    };
    for (std::size_t k = 0; k < fields.size(); ++k) {
        re += escape(name.substr(last, fields[k].pos - last));
        re += k == 0 ? "(-?[0-9]+)" : "-?[0-9]+";
        last = fields[k].pos + fields[k].len;
    }
    re += escape(name.substr(last));
    std::regex rx;
    try {
        rx = std::regex(re);
    } catch (const std::regex_error&) {
        return Status::error("'" + pattern + "': cannot use this pattern");
    }
    std::set<int> found;
    for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
        const std::string entry = it->path().filename().string();
        std::smatch m;
        if (!std::regex_match(entry, m, rx)) continue;
        long long v = 0;
        std::size_t i = 0;
        const std::string digits = m[1].str();
        if (!parse_int(digits, i, v) || i != digits.size()) continue;
        auto expanded = expand_frame_pattern(name, int(v));
        if (expanded && expanded.value() == entry) found.insert(int(v));
    }
    if (ec) return Status::error("'" + pattern + "': cannot list folder '" + dir.string() + "' (" + ec.message() + ")");
    return std::vector<int>(found.begin(), found.end());
}

}  // namespace gdof::io
