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

/// j.dump(indent) + "\n", after checking that every number in it is finite. Throws Error
/// "<path>: result holds a non-finite number at <pointer> (...)" otherwise; `path` names the
/// output for the message.
std::string dump_finite(const nlohmann::json& j, int indent, const std::string& path);

}  // namespace inlight
