// core/log.h: messages to stderr; warnings are also collected for the run report.
#pragma once

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

/// Returns and clears the warnings recorded since the last call (in order of arrival).
std::vector<std::string> take_warnings();

}  // namespace inlight::log
