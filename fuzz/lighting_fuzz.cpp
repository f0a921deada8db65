// Harness: the real-time lighting reader (render::read_lighting_file: SH coefficients plus
// dominant lights, the JSON render --rt-lighting and brdf-sh-bake --gles-lighting read).
#include "fuzz.h"
#include "render/realtime_lights.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string path = inlight::fuzz::write_temp("lighting.json", data, size);
    inlight::fuzz::expect_error_or_success([&] { inlight::render::read_lighting_file(path); });
    return 0;
}
