// Progress bar, frame counter and --stats stage timers on stderr (progress.cpp).
#pragma once

#include <chrono>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

namespace gdof::cli {

class Progress {
public:
    void enable(bool on) { enabled_ = on; }
    bool enabled() const { return enabled_; }
    // Starts a bar with a label ("eval-blur"); update() is thread-safe.
    void begin(const std::string& label);
    void update(double fraction);
    void end();
    void message(const std::string& line);  // a full line on stderr (clears the bar)

private:
    bool enabled_ = false;
    bool active_ = false;
    int last_percent_ = -1;
    std::chrono::steady_clock::time_point last_draw_{};
    std::string label_;
    std::mutex mu_;
};

class Stats {
public:
    void add(const std::string& stage, double seconds);
    void add_frame() { ++frames_; }
    std::string report(double total_seconds) const;

private:
    std::vector<std::pair<std::string, double>> stages_;  // in order of first use
    int frames_ = 0;
    mutable std::mutex mu_;
};

// Times a scope into Stats under a stage name.
class StageTimer {
public:
    StageTimer(Stats& stats, std::string stage)
        : stats_(stats), stage_(std::move(stage)), t0_(std::chrono::steady_clock::now()) {}
    ~StageTimer() {
        stats_.add(stage_, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count());
    }
    StageTimer(const StageTimer&) = delete;
    StageTimer& operator=(const StageTimer&) = delete;

private:
    Stats& stats_;
    std::string stage_;
    std::chrono::steady_clock::time_point t0_;
};

}  // namespace gdof::cli
