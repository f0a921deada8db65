// core/validators.h: CLI11 checks for numeric options that reject NaN and Inf. CLI11's own
// Range, PositiveNumber and NonNegativeNumber compare with < and >, which NaN passes, so every
// floating-point option of every tool uses these instead (and app::parse adds finite() to any
// FLOAT option as a safety net). Messages read "--intensity: 'nan' is not a finite number".
#pragma once

#include <CLI/CLI.hpp>

namespace inlight::app {

/// Any finite number.
CLI::Validator finite();
/// A finite number in [lo, hi].
CLI::Validator finite_range(double lo, double hi);
/// A finite number in [lo, hi], or exactly `special` (an "auto" or "off" value outside the
/// range, e.g. -1).
CLI::Validator finite_range_or(double lo, double hi, double special);
/// A finite number > 0.
CLI::Validator finite_positive();
/// A finite number >= 0 (quality gates and stop rules: 0 = off, negative values rejected).
CLI::Validator finite_non_negative();

/// A check that runs `parse` on the value (e.g. brdf::parse_grid, calib::parse_board) and fails
/// with its inlight::Error message, so option strings holding numbers ("z=90", "8x6",
/// "thetaphi:9x32") are checked during parsing, before any work. `type` is shown in --help.
CLI::Validator parses_with(std::function<void(const std::string&)> parse, const std::string& type);

/// An existing path that is not a FIFO, device or socket (app::parse adds it to every option
/// checked with CLI::ExistingFile or CLI::ExistingPath: reading /dev/zero or a FIFO never ends).
CLI::Validator not_special_file();

/// A rotation in core/conventions.h parse_rotation syntax ("none", "y-up", "z=90,x=-30");
/// rejects NaN, Inf and angles outside [-360, 360].
CLI::Validator rotation();

}  // namespace inlight::app
