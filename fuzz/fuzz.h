// fuzz/fuzz.h: what every harness shares. Each harness defines LLVMFuzzerTestOneInput; built with
// -DINLIGHT_FUZZ=ON and clang it links libFuzzer (make fuzz), otherwise replay_main.cpp, which
// runs it over the seed corpus and the regression inputs under ctest.
//
// The contract a harness checks: a loader given any bytes returns or throws inlight::Error. Any
// other exception (std::bad_alloc, a library's own exception type, ...) escapes the harness and
// is a finding, as is every sanitizer report and abort (a CHECK is for the program's own
// invariants, never for input).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>

namespace inlight::fuzz {

/// A path `name` inside a folder private to this process (made on first use, removed at exit).
std::string temp_path(const std::string& name);
/// Writes `size` bytes to temp_path(name) and returns that path.
std::string write_temp(const std::string& name, const uint8_t* data, size_t size);
/// Splits an input holding two files at its first NUL byte (the seed generator writes pairs so);
/// without a NUL the second part is empty.
std::pair<std::string, std::string> split_pair(const uint8_t* data, size_t size);
/// Runs `f`, swallowing inlight::Error (the loader's documented failure).
template <class F>
void expect_error_or_success(F&& f);

}  // namespace inlight::fuzz

#include "core/error.h"

template <class F>
void inlight::fuzz::expect_error_or_success(F&& f) {
    try {
        f();
    } catch (const inlight::Error&) {
    }
}
