// Progress on stderr, and the --stats stage timers (progress.cpp).
//
// Each frame is one scale from 0 to 100%: its progress stages (--eval-blur,
// --diffuse, --render ...; Command::progress_stage) share it in equal slots,
// in the order they run, and a stage's library progress (0..1, from any
// thread, in any order) fills its slot. The percent shown never goes back
// within a frame. On a terminal it is a bar redrawn in place; otherwise whole
// lines a farm's log parser reads, at most one a second plus one when each
// frame is done:
//   gdof: progress frame 1001 (1/3) diffuse 45%
//   gdof: progress frame 1001 (1/3) done 100%
//   gdof: progress eval-blur 40%            (no sequence: no frame field)
#pragma once

#include <chrono>
#include <mutex>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace gdof::cli {

enum class ProgressStyle { Off, Bar, Lines };

class Progress {
public:
    void set_style(ProgressStyle style) { style_ = style; }
    bool enabled() const { return style_ != ProgressStyle::Off; }

    // A frame starts: its number (none without a sequence), its place in the
    // run (index of count) and how many progress stages its steps have.
    void begin_frame(std::optional<int> frame, int index, int count, int stages);
    // The frame is done: 100% (a line, or the bar completed and ended).
    void end_frame();
    // The next stage of the frame ("diffuse", one word): its progress fills the next slot.
    void begin(const std::string& stage);
    // Part k of n of the current stage (a part of an image, a view): the
    // library's 0..1 fills that share of the stage's slot.
    void part(int k, int n);
    void update(double fraction);  // thread-safe
    // Ends a bar drawn on the terminal (before an error message).
    void finish();
    void message(const std::string& line);  // a full line on stderr

private:
    int percent_of(double fraction) const;  // the frame's percent for a stage fraction
    void draw(int percent, bool force);     // under mu_

    ProgressStyle style_ = ProgressStyle::Off;
    std::string frame_label_;  // "frame 1001 (1/3)" or ""
    int stages_ = 1;
    int slot_ = -1;                  // current stage's slot
    double part_lo_ = 0, part_hi_ = 1;  // share of the slot the library's 0..1 maps to
    std::string stage_;
    int percent_ = -1;  // last percent shown (never decreases within a frame)
    bool bar_drawn_ = false;
    std::chrono::steady_clock::time_point last_draw_{};
    bool drawn_once_ = false;  // any line or bar yet
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
