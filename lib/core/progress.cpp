#include "core/progress.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/log.h"

namespace inlight {

std::string format_duration(double seconds) {
    if (!std::isfinite(seconds) || seconds < 0) return "--:--";
    const auto total = static_cast<int64_t>(std::floor(seconds));
    const int64_t h = total / 3600, m = (total / 60) % 60, s = total % 60;
    char buf[48];
    if (h > 0)
        std::snprintf(buf, sizeof buf, "%lld:%02lld:%02lld", static_cast<long long>(h),
                      static_cast<long long>(m), static_cast<long long>(s));
    else
        std::snprintf(buf, sizeof buf, "%lld:%02lld", static_cast<long long>(m),
                      static_cast<long long>(s));
    return buf;
}

std::string format_progress(const std::string& label, int64_t done, int64_t total,
                            double elapsed_s) {
    total = std::max<int64_t>(total, 1);
    done = std::clamp<int64_t>(done, 0, total);
    const int percent = static_cast<int>(100 * done / total);
    char bar[41];
    const int filled = percent * 40 / 100;
    for (int i = 0; i < 40; ++i) bar[i] = i < filled ? '#' : ' ';
    bar[40] = 0;
    const double eta = done > 0 ? elapsed_s * static_cast<double>(total - done) / done
                                : std::nan("");
    char buf[96];
    std::snprintf(buf, sizeof buf, " [%s] %3d%%  %s elapsed, ETA %s", bar, percent,
                  format_duration(elapsed_s).c_str(), format_duration(eta).c_str());
    return label + buf;
}

Progress::Progress(std::string label, int64_t total)
    : m_label(std::move(label)),
      m_total(total > 0 ? total : 1),
      m_start(std::chrono::steady_clock::now()),
      m_enabled(::isatty(STDERR_FILENO) && log::level() != log::Level::kQuiet) {}

Progress::~Progress() {
    if (m_enabled && m_shown_percent >= 0) {
        std::fprintf(stderr, "\r\033[K");
        log::set_bar_on_screen(false);
    }
}

void Progress::add(int64_t n) {
    const int64_t done = m_done += n;
    if (!m_enabled) return;
    const double elapsed =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - m_start).count();
    const int percent = static_cast<int>(100 * std::min(done, m_total) / m_total);
    const auto second = static_cast<int64_t>(elapsed);
    int shown = m_shown_percent.load();
    int64_t shown_second = m_shown_second.load();
    // One thread wins the redraw: a new percentage, or the same one a second later.
    if (percent > shown) {
        if (!m_shown_percent.compare_exchange_strong(shown, percent)) return;
        m_shown_second = second;
    } else if (second > shown_second) {
        if (!m_shown_second.compare_exchange_strong(shown_second, second)) return;
    } else {
        return;
    }
    std::fprintf(stderr, "\r%s\033[K", format_progress(m_label, done, m_total, elapsed).c_str());
    std::fflush(stderr);
    log::set_bar_on_screen(true);
}

}  // namespace inlight
