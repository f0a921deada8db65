// core/json_in.h: the one bounded reader for JSON that comes from outside (files a user, another
// tool or a download wrote). Every reader of such JSON goes through it, so a hostile document
// cannot exhaust the stack (deep nesting) or memory (size) of any tool or of the app.
#pragma once

#include <cstddef>
#include <string>

#include <nlohmann/json.hpp>

namespace inlight::json_in {

/// Deepest nesting of arrays and objects accepted. Every format we read nests at most ~6 levels;
/// 64 leaves room for free-form metadata while keeping recursive walkers far from the stack limit.
constexpr size_t kMaxDepth = 64;
/// Largest JSON text accepted, bytes (256 MiB): our largest JSON files (inner manifests) are a few
/// MiB; this only stops a runaway file from being read whole into memory.
constexpr size_t kMaxBytes = size_t(256) << 20;

/// Nesting depth of `text` (0 for a scalar), counting brackets outside strings. Stops counting
/// and returns as soon as the depth exceeds `stop_above`. Does not validate the syntax.
size_t nesting_depth(const std::string& text, size_t stop_above = kMaxDepth);

/// Parses `text`, read from `source` (a file name shown in messages). Throws Error naming
/// `source` when the text is larger than `max_bytes`, nests deeper than `max_depth`, or is not
/// valid JSON (numbers out of double range included).
nlohmann::json parse(const std::string& text, const std::string& source,
                     size_t max_depth = kMaxDepth, size_t max_bytes = kMaxBytes);

/// Reads and parses the file `path` under the same bounds; the size is checked before the file
/// is read. Throws Error naming `path`.
nlohmann::json read_file(const std::string& path, size_t max_depth = kMaxDepth,
                         size_t max_bytes = kMaxBytes);

}  // namespace inlight::json_in
