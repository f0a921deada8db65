#include "core/number.h"

#include <charconv>
#include <cmath>

#include "core/error.h"

namespace inlight {
namespace {

std::string_view trimmed(std::string_view s) {
    const size_t b = s.find_first_not_of(" \t");
    if (b == std::string_view::npos) return {};
    const size_t e = s.find_last_not_of(" \t");
    return s.substr(b, e - b + 1);
}

}  // namespace

double parse_finite(std::string_view text, const std::string& context) {
    std::string_view s = trimmed(text);
    if (!s.empty() && s.front() == '+') s.remove_prefix(1);
    double value = 0;
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), value);
    if (s.empty() || ec != std::errc() || end != s.data() + s.size() || !std::isfinite(value)) {
        throw UsageError(str(context, ": '", text, "' is not a finite number"));
    }
    return value;
}

double parse_finite_field(std::string_view text, const std::string& context) {
    try {
        return parse_finite(text, context);
    } catch (const UsageError& e) {
        throw Error(e.what());
    }
}

long long parse_integer(std::string_view text, const std::string& context, long long lo,
                        long long hi) {
    std::string_view s = trimmed(text);
    if (!s.empty() && s.front() == '+') s.remove_prefix(1);
    long long value = 0;
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), value);
    if (s.empty() || ec != std::errc() || end != s.data() + s.size()) {
        throw UsageError(str(context, ": '", text, "' is not an integer"));
    }
    if (value < lo || value > hi) {
        throw UsageError(str(context, ": ", value, " is outside [", lo, ", ", hi, "]"));
    }
    return value;
}

std::vector<std::string> split(std::string_view text, char sep) {
    std::vector<std::string> out;
    size_t start = 0;
    while (true) {
        const size_t pos = text.find(sep, start);
        out.emplace_back(text.substr(start, pos == std::string_view::npos ? pos : pos - start));
        if (pos == std::string_view::npos) break;
        start = pos + 1;
    }
    return out;
}

}  // namespace inlight
