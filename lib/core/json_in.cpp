// core/json_in.cpp: bounded JSON reading (see json_in.h).
#include "core/json_in.h"

#include <filesystem>
#include <system_error>

#include "core/error.h"
#include "core/fs.h"

namespace inlight::json_in {

size_t nesting_depth(const std::string& text, size_t stop_above) {
    size_t depth = 0, deepest = 0;
    bool in_string = false, escaped = false;
    for (const char c : text) {
        if (in_string) {
            if (escaped) escaped = false;
            else if (c == '\\') escaped = true;
            else if (c == '"') in_string = false;
            continue;
        }
        if (c == '"') {
            in_string = true;
        } else if (c == '[' || c == '{') {
            if (++depth > deepest) deepest = depth;
            if (deepest > stop_above) return deepest;
        } else if ((c == ']' || c == '}') && depth > 0) {
            --depth;
        }
    }
    return deepest;
}

nlohmann::json parse(const std::string& text, const std::string& source, size_t max_depth,
                     size_t max_bytes) {
    if (text.size() > max_bytes) {
        throw Error(str(source, ": ", text.size(), " bytes, more than the ", max_bytes,
                        " a JSON file may have"));
    }
    if (nesting_depth(text, max_depth) > max_depth) {
        throw Error(str(source, ": arrays/objects nested deeper than ", max_depth,
                        " levels (refused: no format we read nests so deep)"));
    }
    try {
        return nlohmann::json::parse(text);
    } catch (const nlohmann::json::exception& e) {  // parse_error, and out_of_range (overflow)
        throw Error(str(source, ": not valid JSON: ", e.what()));
    }
}

nlohmann::json read_file(const std::string& path, size_t max_depth, size_t max_bytes) {
    std::error_code ec;
    const auto size = std::filesystem::file_size(path, ec);
    if (!ec && size > max_bytes) {
        throw Error(str(path, ": ", size, " bytes, more than the ", max_bytes,
                        " a JSON file may have"));
    }
    return parse(fs::read_file(path), path, max_depth, max_bytes);
}

}  // namespace inlight::json_in
