// core/enum_names.h: one table of names per enum, used both ways. A module writes its names once,
//
//     constexpr EnumName<Detector> kDetectorNames[] = {
//         {Detector::kAuto, "auto"}, {Detector::kClassic, "classic"}, ...};
//
// and defines to_string() and *_from_string() as one-liners over it, so every tool rejects an
// unknown name with the same wording: "unknown detector 'x' (expected auto, classic, sb or ros)".
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

#include "core/check.h"
#include "core/error.h"

namespace inlight {

template <typename E>
struct EnumName {
    E value;
    const char* name;
};

/// "a", "a or b", "a, b or c": the accepted names in table order.
template <typename E, std::size_t N>
std::string enum_name_list(const EnumName<E> (&names)[N]) {
    std::string list;
    for (std::size_t i = 0; i < N; ++i) {
        if (i > 0) list += (i + 1 == N) ? " or " : ", ";
        list += names[i].name;
    }
    return list;
}

/// The name of `value`. Every enumerator must be in the table: a missing one is a bug.
template <typename E, std::size_t N>
std::string enum_to_string(const EnumName<E> (&names)[N], E value) {
    for (const auto& e : names)
        if (e.value == value) return e.name;
    INLIGHT_CHECK(false) << "enumerator " << static_cast<long long>(value) << " has no name";
    return {};
}

/// The enumerator called `name`, or throws `Exception` (UsageError for option values, Error for
/// names read from a data file) with "unknown <what> '<name>' (expected ...)".
template <typename Exception = UsageError, typename E, std::size_t N>
E enum_from_string(const EnumName<E> (&names)[N], std::string_view name, std::string_view what) {
    for (const auto& e : names)
        if (name == e.name) return e.value;
    throw Exception(str("unknown ", what, " '", name, "' (expected ", enum_name_list(names), ")"));
}

}  // namespace inlight
