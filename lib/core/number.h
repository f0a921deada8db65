// core/number.h: numbers read from text (option values such as "z=90" or "8x6", file fields):
// the whole text must be one finite number. NaN and Inf are bad input wherever a number is read.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace inlight {

/// Parses all of `text` (spaces around it allowed, a leading '+' allowed) as a finite decimal
/// number, e.g. "1.5", "-2e-3". Throws UsageError "<context>: '<text>' is not a finite number"
/// for "nan", "inf", "1e999" (overflow), "", "1.5x", ... `context` names the option or file.
double parse_finite(std::string_view text, const std::string& context);

/// The same check for a number read from a file: throws Error (a data error, exit 1) instead of
/// UsageError. `context` names the file and line, e.g. "mesh.obj:12".
double parse_finite_field(std::string_view text, const std::string& context);

/// Parses all of `text` as a decimal integer in [lo, hi]. Throws UsageError "<context>: '<text>'
/// is not an integer" or "<context>: <n> is outside [lo, hi]".
long long parse_integer(std::string_view text, const std::string& context, long long lo,
                        long long hi);

/// Splits `text` at every `sep`; empty items are kept ("a,,b" -> {"a", "", "b"}; "" -> {""}).
std::vector<std::string> split(std::string_view text, char sep);

}  // namespace inlight
