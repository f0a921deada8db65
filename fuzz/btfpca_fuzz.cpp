// Harness: the compressed-BTF reader (btf::CompressedBtf::open, the folder btf-pca writes and
// render --btf-compressed, btf-pca interpolate and the bundle read). The input is btf-pca.json,
// a NUL, then weights.bin, in a folder holding the component images of the seed BTF
// (fuzz/samples.h), so manifests naming them reach the size, index and offset checks.
#include "btf/compressed.h"
#include "fuzz.h"
#include "samples.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    static const std::string dir = [] {
        const std::string d = inlight::fuzz::temp_path("btfpca");
        inlight::fuzz::make_compressed_btf(d);
        return d;
    }();
    const auto [manifest, weights] = inlight::fuzz::split_pair(data, size);
    inlight::fuzz::write_temp("btfpca/btf-pca.json", reinterpret_cast<const uint8_t*>(manifest.data()),
                              manifest.size());
    inlight::fuzz::write_temp("btfpca/weights.bin", reinterpret_cast<const uint8_t*>(weights.data()),
                              weights.size());
    inlight::fuzz::expect_error_or_success([&] {
        const auto btf = inlight::btf::CompressedBtf::open(dir);
        // Decode one image per view so the indices the reader accepted are used.
        for (int v = 0; v < btf->shape().n_views(); ++v) btf->read_image_streamed(0, v, 1);
    });
    return 0;
}
