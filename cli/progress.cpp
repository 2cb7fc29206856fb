// Progress bar and frame counter on stderr, and the --stats stage timers.
#include <sys/resource.h>

#include <cmath>
#include <cstdio>
#include <iomanip>
#include <sstream>

#include "cli.h"

namespace gdof::cli {

namespace {
constexpr int kBarWidth = 30;
}

void Progress::begin(const std::string& label) {
    if (!enabled_) return;
    std::lock_guard<std::mutex> lock(mu_);
    label_ = label;
    active_ = true;
    last_percent_ = -1;
}

void Progress::update(double fraction) {
    if (!enabled_ || !active_) return;
    if (!(fraction >= 0)) fraction = 0;
    if (fraction > 1) fraction = 1;
    const int percent = int(std::floor(fraction * 100.0));
    std::lock_guard<std::mutex> lock(mu_);
    // Throttle: redraw on a new percentage, at most every 100 ms (and always at 100%).
    if (percent == last_percent_) return;
    const auto now = std::chrono::steady_clock::now();
    if (last_percent_ >= 0 && percent < 100 && now - last_draw_ < std::chrono::milliseconds(100)) return;
    last_draw_ = now;
    last_percent_ = percent;
    const int filled = int(std::lround(fraction * kBarWidth));
    std::string bar(std::size_t(filled), '#');
    bar.resize(kBarWidth, ' ');
    std::fprintf(stderr, "\r%s [%s] %3d%%", label_.c_str(), bar.c_str(), percent);
    std::fflush(stderr);
}

void Progress::end() {
    if (!enabled_) return;
    std::lock_guard<std::mutex> lock(mu_);
    if (active_ && last_percent_ >= 0) {
        std::fputc('\n', stderr);
        std::fflush(stderr);
    }
    active_ = false;
    last_percent_ = -1;
}

void Progress::message(const std::string& line) {
    std::lock_guard<std::mutex> lock(mu_);
    if (active_ && last_percent_ >= 0) std::fputc('\n', stderr);
    last_percent_ = -1;
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
