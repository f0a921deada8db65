#include "core/progress.h"

#include <unistd.h>

#include <cstdio>

#include "core/log.h"

namespace inlight {

Progress::Progress(std::string label, int64_t total)
    : m_label(std::move(label)),
      m_total(total > 0 ? total : 1),
      m_enabled(::isatty(STDERR_FILENO) && log::level() != log::Level::kQuiet) {}

Progress::~Progress() {
    if (m_enabled && m_shown_percent >= 0) std::fprintf(stderr, "\r\033[K");
}

void Progress::add(int64_t n) {
    const int64_t done = m_done += n;
    if (!m_enabled) return;
    const int percent = static_cast<int>(100 * done / m_total);
    int shown = m_shown_percent.load();
    if (percent <= shown || !m_shown_percent.compare_exchange_strong(shown, percent)) return;
    char bar[41];
    const int filled = percent * 40 / 100;
    for (int i = 0; i < 40; ++i) bar[i] = i < filled ? '#' : ' ';
    bar[40] = 0;
    std::fprintf(stderr, "\r%s [%s] %3d%%", m_label.c_str(), bar, percent);
    std::fflush(stderr);
}

}  // namespace inlight
