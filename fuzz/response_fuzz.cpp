// Harness: the camera response reader (calib::read_response, the JSON file calibrate response
// writes and envmap-project --response reads).
#include "calib/response.h"
#include "fuzz.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string path = inlight::fuzz::write_temp("response.json", data, size);
    inlight::fuzz::expect_error_or_success([&] { inlight::calib::read_response(path); });
    return 0;
}
