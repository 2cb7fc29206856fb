// Progress on stderr (a bar on a terminal, lines otherwise; progress.h) and
// the --stats stage timers.
#include <sys/resource.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iomanip>
#include <sstream>

#include "cli.h"

namespace gdof::cli {

namespace {
constexpr int kBarWidth = 30;
}

void Progress::begin_frame(std::optional<int> frame, int index, int count, int stages) {
    std::lock_guard<std::mutex> lock(mu_);
    frame_label_ = frame ? "frame " + std::to_string(*frame) + " (" + std::to_string(index + 1) + "/" +
                               std::to_string(count) + ")"
                         : std::string();
    stages_ = std::max(stages, 1);
    slot_ = -1;
    part_lo_ = 0, part_hi_ = 1;
    stage_ = "start";
    percent_ = -1;
}

void Progress::begin(const std::string& stage) {
    std::lock_guard<std::mutex> lock(mu_);
    slot_ = std::min(slot_ + 1, stages_ - 1);  // more stages than counted share the last slot
    part_lo_ = 0, part_hi_ = 1;
    stage_ = stage;
}

void Progress::part(int k, int n) {
    std::lock_guard<std::mutex> lock(mu_);
    if (n < 1) n = 1;
    part_lo_ = double(k) / double(n);
    part_hi_ = double(k + 1) / double(n);
}

int Progress::percent_of(double fraction) const {
    if (!(fraction >= 0)) fraction = 0;
    if (fraction > 1) fraction = 1;
    const double in_slot = part_lo_ + (part_hi_ - part_lo_) * fraction;
    const double f = (double(std::max(slot_, 0)) + in_slot) / double(stages_);
    return std::clamp(int(std::floor(f * 100.0)), 0, 100);
}

void Progress::draw(int percent, bool force) {
    percent = std::max(percent, percent_);  // never back within a frame
    const auto now = std::chrono::steady_clock::now();
    if (style_ == ProgressStyle::Lines) {
        if (!force && (percent == percent_ || (drawn_once_ && now - last_draw_ < std::chrono::seconds(1)))) return;
        std::fprintf(stderr, "gdof: progress %s%s%s %d%%\n", frame_label_.c_str(), frame_label_.empty() ? "" : " ",
                     stage_.c_str(), percent);
    } else {
        if (!force && (percent == percent_ || (bar_drawn_ && now - last_draw_ < std::chrono::milliseconds(100))))
            return;
        const int filled = int(std::lround(percent * kBarWidth / 100.0));
        std::string bar(std::size_t(filled), '#');
        bar.resize(kBarWidth, ' ');
        std::string label = frame_label_.empty() ? stage_ : frame_label_ + " " + stage_;
        if (label.size() < 28) label.resize(28, ' ');
        std::fprintf(stderr, "\r%s [%s] %3d%%", label.c_str(), bar.c_str(), percent);
        bar_drawn_ = true;
    }
    std::fflush(stderr);
    percent_ = percent;
    last_draw_ = now;
    drawn_once_ = true;
}

void Progress::update(double fraction) {
    if (!enabled()) return;
    std::lock_guard<std::mutex> lock(mu_);
    if (slot_ < 0) return;  // progress outside a stage (none is expected)
    draw(percent_of(fraction), false);
}

void Progress::end_frame() {
    if (!enabled()) return;
    std::lock_guard<std::mutex> lock(mu_);
    stage_ = "done";
    draw(100, true);
    if (bar_drawn_) std::fputc('\n', stderr), std::fflush(stderr);
    bar_drawn_ = false;
}

void Progress::finish() {
    std::lock_guard<std::mutex> lock(mu_);
    if (bar_drawn_) std::fputc('\n', stderr), std::fflush(stderr);
    bar_drawn_ = false;
}

void Progress::message(const std::string& line) {
    std::lock_guard<std::mutex> lock(mu_);
    if (bar_drawn_) std::fputc('\n', stderr);
    bar_drawn_ = false;  // the next update draws the bar again below the message
    std::fprintf(stderr, "%s\n", line.c_str());
    std::fflush(stderr);
}

void Stats::add(const std::string& stage, double seconds) {
    std::lock_guard<std::mutex> lock(mu_);
    for (auto& [name, t] : stages_)
        if (name == stage) {
            t += seconds;
            return;
        }
    stages_.emplace_back(stage, seconds);
}

std::string Stats::report(double total_seconds) const {
    std::lock_guard<std::mutex> lock(mu_);
    std::ostringstream o;
    o << std::fixed << std::setprecision(3);
    o << "gdof: stats";
    if (frames_ > 0) o << " (" << frames_ << (frames_ == 1 ? " frame" : " frames") << ")";
    o << ":\n";
    for (const auto& [name, t] : stages_) o << "  " << std::left << std::setw(16) << name << std::right << std::setw(10) << t << " s\n";
    o << "  " << std::left << std::setw(16) << "total" << std::right << std::setw(10) << total_seconds << " s\n";
    rusage ru{};
    if (getrusage(RUSAGE_SELF, &ru) == 0)
        o << "  " << std::left << std::setw(16) << "peak memory" << std::right << std::setw(10)
          << std::setprecision(1) << double(ru.ru_maxrss) / 1024.0 << " MB\n";
    return o.str();
}

}  // namespace gdof::cli
