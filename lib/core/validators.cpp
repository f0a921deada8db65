#include "core/validators.h"

#include <limits>

#include "core/conventions.h"
#include "core/error.h"
#include "core/fs.h"
#include "core/number.h"

namespace inlight::app {
namespace {

/// A validator that parses the value with parse_finite and then applies `accept`; `rule` names
/// the accepted set in the message and the help text.
CLI::Validator number_check(const std::string& rule, std::function<bool(double)> accept) {
    return CLI::Validator(
        [rule, accept](std::string& input) -> std::string {
            double v = 0;
            try {
                v = parse_finite(input, "value");
            } catch (const Error&) {
                return str("'", input, "' is not a finite number");
            }
            if (!accept(v)) return str(input, " is not ", rule);
            return std::string();
        },
        rule);
}

/// A parser's message without the option name it starts with ("--seed: '-1' is outside ...",
/// "--board '0': expected ..."): CLI11 puts the option's name in front of a validator's message,
/// which read "--seed: --seed: ...".
std::string without_option_name(const std::string& message) {
    if (message.rfind("--", 0) != 0) return message;
    const size_t end = message.find_first_of(": ");
    if (end == std::string::npos) return message;
    size_t rest = end;
    if (message.compare(rest, 2, ": ") == 0) rest += 2;
    else if (message[rest] == ' ') rest += 1;
    return rest < message.size() ? message.substr(rest) : message;
}

}  // namespace

CLI::Validator finite() {
    CLI::Validator v = number_check("finite", [](double) { return true; });
    v.description("");  // implied by every numeric option: keep the help text short
    return v;
}

CLI::Validator finite_range(double lo, double hi) {
    return number_check(str("in [", lo, ", ", hi, "]"),
                        [lo, hi](double v) { return v >= lo && v <= hi; });
}

CLI::Validator finite_range_or(double lo, double hi, double special) {
    return number_check(str("in [", lo, ", ", hi, "] or ", special),
                        [lo, hi, special](double v) { return v == special || (v >= lo && v <= hi); });
}

CLI::Validator finite_positive() {
    return number_check("> 0", [](double v) { return v > 0; });
}

CLI::Validator finite_non_negative() {
    return number_check(">= 0", [](double v) { return v >= 0; });
}

CLI::Validator parses_with(std::function<void(const std::string&)> parse, const std::string& type) {
    return CLI::Validator(
        [parse](std::string& input) -> std::string {
            try {
                parse(input);
            } catch (const Error& e) {
                return without_option_name(e.what());
            }
            return std::string();
        },
        type);
}

CLI::Validator not_special_file() {
    CLI::Validator v(
        [](std::string& input) -> std::string {
            const std::string kind = fs::special_file_kind(input);
            if (kind.empty()) return std::string();
            return str("'", input, "' is ", kind, ", not a regular file");
        },
        "");
    return v;
}

CLI::Validator rotation() {
    return parses_with([](const std::string& s) { parse_rotation(s); }, "ROTATION");
}

}  // namespace inlight::app
