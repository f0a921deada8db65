// core/progress.h: progress of a long loop: a \r bar on a terminal, nothing extra otherwise.
#pragma once

#include <atomic>
#include <cstdint>
#include <string>

namespace inlight {

/// Thread-safe counter of finished work items. On a TTY (and unless -q) it redraws
/// "label [#####     ] 52%" on stderr at most every 1%; when stderr is not a terminal it prints
/// nothing, since ScopedStage already writes one line per stage.
class Progress {
  public:
    Progress(std::string label, int64_t total);
    ~Progress();
    /// Adds `n` finished items (callable from worker threads).
    void add(int64_t n = 1);

  private:
    std::string m_label;
    int64_t m_total;
    std::atomic<int64_t> m_done{0};
    std::atomic<int> m_shown_percent{-1};
    bool m_enabled;
};

}  // namespace inlight
