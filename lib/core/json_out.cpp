#include "core/json_out.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "core/error.h"

namespace inlight {
namespace {

/// One reference token of a JSON pointer (RFC 6901, section 3): "~" is written "~0" and "/" is
/// written "~1", so a key holding either still names one member.
std::string pointer_token(const std::string& key) {
    std::string t;
    for (char c : key) {
        if (c == '~') t += "~0";
        else if (c == '/') t += "~1";
        else t += c;
    }
    return t;
}

bool find_non_finite(const nlohmann::json& j, std::string& pointer) {
    if (j.is_number_float()) return !std::isfinite(j.get<double>());
    if (j.is_array()) {
        for (size_t i = 0; i < j.size(); ++i) {
            if (find_non_finite(j[i], pointer)) {
                pointer = "/" + std::to_string(i) + pointer;
                return true;
            }
        }
    } else if (j.is_object()) {
        for (auto it = j.begin(); it != j.end(); ++it) {
            if (find_non_finite(it.value(), pointer)) {
                pointer = "/" + pointer_token(it.key()) + pointer;
                return true;
            }
        }
    }
    return false;
}

}  // namespace

std::string first_non_finite(const nlohmann::json& j) {
    std::string pointer;
    if (!find_non_finite(j, pointer)) return "";
    return pointer.empty() ? "/" : pointer;
}

double json_float(float f) {
    if (!std::isfinite(f)) return double(f);
    char buf[32];
    for (int digits = 1; digits < 9; ++digits) {
        std::snprintf(buf, sizeof buf, "%.*g", digits, double(f));
        const double d = std::strtod(buf, nullptr);
        if (static_cast<float>(d) == f) return d;
    }
    std::snprintf(buf, sizeof buf, "%.9g", double(f));  // 9 digits always read back as f
    return std::strtod(buf, nullptr);
}

std::string dump_finite(const nlohmann::json& j, int indent, const std::string& path) {
    const std::string at = first_non_finite(j);
    if (!at.empty()) {
        throw Error(str(path, ": the result holds a non-finite number (NaN or Inf) at ", at,
                        ": an overflow or NaN upstream, e.g. a scale option or input values too "
                        "large; no output was written"));
    }
    return j.dump(indent) + "\n";
}

}  // namespace inlight
