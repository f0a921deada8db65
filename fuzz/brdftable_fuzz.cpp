// Harness: the binary BRDF SH table reader (brdf::read_binary, the .bin brdf-sh-bake writes and
// envmap-project's budget --brdf-table reads).
#include "brdf/table.h"
#include "fuzz.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string path = inlight::fuzz::write_temp("table.bin", data, size);
    inlight::fuzz::expect_error_or_success([&] { inlight::brdf::read_binary(path); });
    return 0;
}
