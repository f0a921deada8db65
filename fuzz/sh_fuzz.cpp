// Harness: the SH coefficient readers (sh::read_coefficients: the JSON document and the binary
// file). The first byte picks the format (by extension, as the tools do); the rest is the file.
#include "fuzz.h"
#include "sh/sh_io.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size < 1) return 0;
    const std::string path = inlight::fuzz::write_temp(
        (data[0] % 2) ? "coefficients.bin" : "coefficients.json", data + 1, size - 1);
    inlight::fuzz::expect_error_or_success([&] { inlight::sh::read_coefficients(path); });
    return 0;
}
