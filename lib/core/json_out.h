// core/json_out.h: JSON written as an output file. nlohmann::json writes a NaN or an Inf as
// `null` without a word, so an overflow upstream (an --intensity of 1e308, a radiance near
// FLT_MAX) became a file of nulls with exit 0. Every JSON output goes through dump_finite.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

namespace inlight {

/// The JSON pointer (RFC 6901: "~" and "/" in keys escaped as "~0" and "~1") of the first NaN or
/// Inf number in `j` ("/coefficients/0/2"), "/" for `j` itself, or "" if every number is finite.
std::string first_non_finite(const nlohmann::json& j);

/// A float as a JSON number in its shortest decimal form: the double of the fewest significant
/// digits (at most 9) that reads back as exactly `f` (get<float>() of it is `f`). nlohmann
/// writes a float widened to double with 17 digits ("0.00047978584188967943"); this writes
/// "0.00047978584" (nlohmann's Grisu2 may still add digits to a rare double). Non-finite values
/// pass through (dump_finite refuses them).
double json_float(float f);

/// j.dump(indent) + "\n", after checking that every number in it is finite. Throws Error
/// "<path>: result holds a non-finite number at <pointer> (...)" otherwise; `path` names the
/// output for the message.
std::string dump_finite(const nlohmann::json& j, int indent, const std::string& path);

}  // namespace inlight
