// Harness: the OBJ and PLY readers (render::load_mesh). The first byte picks the format (by the
// file name's extension, as the renderer does); the rest is the file.
#include "fuzz.h"
#include "render/mesh.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size < 1) return 0;
    const std::string path = inlight::fuzz::write_temp(
        (data[0] % 2) ? "mesh.ply" : "mesh.obj", data + 1, size - 1);
    inlight::fuzz::expect_error_or_success([&] { inlight::render::load_mesh(path); });
    return 0;
}
