// core/log.h: messages to stderr; warnings are also collected for the run report.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace inlight::log {

enum class Level { kQuiet = 0, kNormal = 1, kVerbose = 2 };

/// Process-wide verbosity (set once by app::run from -q / -v). Thread-safe.
void set_level(Level level);
Level level();

/// Informational line to stderr, suppressed by -q.
void info(const std::string& message);
/// Extra detail, shown only with -v.
void verbose(const std::string& message);
/// Printed as "warning: ..." (unless -q) and recorded; see take_warnings().
void warn(const std::string& message);
/// Always printed.
void error(const std::string& message);

/// A tool's result for the user, printed as "<tool>: <what>: <text>" on stderr at the default
/// verbosity (suppressed by -q), like OpenCV's calibration printing its RMS: the figures a run
/// is for, with words and units, so a user need not open the JSON report. Tools print their
/// summaries through this one function (docs/report.md, "Console summary", says which do yet).
void summary(const std::string& tool, const std::string& what, const std::string& text);

/// "1 light", "2 lights", "0 lights": `n` and the noun, plural unless n == 1 (`plural_form`
/// when the plural is not noun + "s").
std::string count(int64_t n, const std::string& noun, const std::string& plural_form = "");

/// `value` with `digits` significant digits (printf %g) for summaries: 0.21347 -> "0.2135" at 4.
std::string num(double value, int digits = 4);

/// Set by Progress while its bar is on the terminal's last line: the next message clears that
/// line first (the bar comes back at its next redraw), so no line runs on from the bar.
void set_bar_on_screen(bool on);

/// Returns and clears the warnings recorded since the last call (in order of arrival).
std::vector<std::string> take_warnings();

}  // namespace inlight::log
