// Harness: envmap-project's image path (EXR, HDR, PNG file -> image::read_image ->
// envmap::load_environment as a lat-long map). The first byte picks the format (by the file
// name's extension, as the tool does); the rest is the file.
#include "envmap/environment.h"
#include "fuzz.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size < 1) return 0;
    static const char* const kExt[] = {"exr", "hdr", "png"};
    const std::string path =
        inlight::fuzz::write_temp(std::string("env.") + kExt[data[0] % 3], data + 1, size - 1);
    inlight::fuzz::expect_error_or_success([&] {
        inlight::envmap::LoadOptions options;
        inlight::envmap::load_environment(path, options);
    });
    return 0;
}
