// Harness: the bundle reader (bundle::read_bundle). The input is manifest.json of a bundle folder
// that holds the files of the seed bundle (fuzz/samples.h), so manifests listing them reach the
// size and hash checks, and traversal or symlink paths reach the containment checks.
#include <filesystem>

#include "bundle/bundle.h"
#include "fuzz.h"
#include "samples.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    static const std::string dir = [] {
        const std::string d = inlight::fuzz::temp_path("bundles/weave");
        inlight::fuzz::make_fabric_bundle(inlight::fuzz::temp_path("bundle_src"), d);
        return d;
    }();
    inlight::fuzz::write_temp("bundles/weave/manifest.json", data, size);
    inlight::fuzz::expect_error_or_success([&] { inlight::bundle::read_bundle(dir); });
    return 0;
}
