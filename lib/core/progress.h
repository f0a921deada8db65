// core/progress.h: progress of a long loop: a \r bar with elapsed time and ETA on a terminal,
// nothing extra otherwise.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <string>

namespace inlight {

/// "m:ss" (or "h:mm:ss" from one hour on) of a non-negative duration in seconds, rounded down;
/// "--:--" for NaN, Inf or negative values.
std::string format_duration(double seconds);

/// The line Progress draws: "label [####      ] 52%  0:12 elapsed, ETA 0:11".
/// `done` in [0, total], `total` > 0 work items, `elapsed_s` seconds since the start.
/// The ETA assumes the remaining items take as long each as the finished ones did on average;
/// it reads "ETA --:--" until one item is done.
std::string format_progress(const std::string& label, int64_t done, int64_t total,
                            double elapsed_s);

/// Thread-safe counter of finished work items. On a TTY (and unless -q) it redraws
/// format_progress() on stderr when the percentage changes or at most once a second otherwise
/// (so the elapsed time and ETA move on a slow loop); when stderr is not a terminal it prints
/// nothing, since ScopedStage already writes one line per stage.
class Progress {
  public:
    Progress(std::string label, int64_t total);
    ~Progress();
    /// Adds `n` finished items (callable from worker threads).
    void add(int64_t n = 1);
    /// True when the bar is drawn (stderr is a terminal and not -q): callers may then move
    /// per-item lines to -v, the bar standing for them.
    bool drawing() const { return m_enabled; }

  private:
    std::string m_label;
    int64_t m_total;
    std::atomic<int64_t> m_done{0};
    std::atomic<int> m_shown_percent{-1};
    std::atomic<int64_t> m_shown_second{-1};
    std::chrono::steady_clock::time_point m_start;
    bool m_enabled;
};

}  // namespace inlight
