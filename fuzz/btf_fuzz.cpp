// Harness: the BTF reader (btf::FolderBtf) on a zip archive held in memory, with a small light
// and view set (4 x 3 directions, written once), decoding every image it indexes.
#include "btf/dataset.h"
#include "fuzz.h"

namespace {

const inlight::btf::OpenOptions& options() {
    static const inlight::btf::OpenOptions o = [] {
        inlight::btf::OpenOptions out;
        const std::string lights = "0 0\n15 0\n30 90\n60 200\n";
        const std::string views = "0 0\n30 0\n45 120\n";
        out.light_directions = inlight::fuzz::write_temp(
            "lights.txt", reinterpret_cast<const uint8_t*>(lights.data()), lights.size());
        out.view_directions = inlight::fuzz::write_temp(
            "views.txt", reinterpret_cast<const uint8_t*>(views.data()), views.size());
        return out;
    }();
    return o;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    inlight::fuzz::expect_error_or_success(
        [&] { inlight::btf::fuzz_read_btf_zip(data, size, options()); });
    return 0;
}
