// btf-pca: the codec of a bidirectional texture function (docs/btf.md).
//   btf-pca compress:     a BTF (UBO2003 folder or Bonn zip file) -> PCA per group of k
//                         neighbouring views, components stored for streaming, Table 7.1-style
//                         errors in the report
//   btf-pca interpolate:  a BTF or a btf-pca folder evaluated at arbitrary (light, view) pairs by
//                         angular interpolation (docs/btf-interpolation.md)
#include <filesystem>
#include <iostream>
#include <string>

#include "core/app.h"
#include "core/modes.h"
#include "modes.h"

using namespace inlight;
using namespace inlight::btf_pca_cli;

namespace {

/// The subcommand an older command line (an input and flags, no subcommand) meant, or null.
const char* old_mode(int argc, char** argv) {
    bool old = false, interp = false;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "-h" || a == "--help" || a == "--version") break;
        if (a.rfind("--interpolate", 0) == 0) interp = true;
        const bool input = !a.empty() && a[0] != '-' &&
                           (std::filesystem::exists(a) || std::filesystem::path(a).extension() == ".zip");
        if (input || interp || a == "-o" || a.rfind("--output", 0) == 0) old = true;
    }
    if (!old) return nullptr;
    return interp ? "interpolate INPUT --pairs PAIRS -o OUT" : "compress INPUT -o OUT";
}

}  // namespace

int main(int argc, char** argv) {
    const std::string mode = argc > 1 ? argv[1] : "";
    if (mode == "compress") return compress(argc, argv);
    if (mode == "interpolate") return interpolate(argc, argv);
#ifdef INLIGHT_BTF_PCA_GLES
    if (mode == "export-gles") return export_gles(argc, argv);
#endif
    if (const char* meant = old_mode(argc, argv)) {
        std::cerr << "btf-pca: modes are subcommands now: use 'btf-pca " << meant
                  << "' (see btf-pca --help)\n";
        return app::kExitUsage;
    }
    return app::list_modes("btf-pca", "btf-pca: the codec of a bidirectional texture function: "
                           "PCA compression, and decompression at arbitrary directions",
                           {{"compress", kCompressPurpose, kCompressExample},
                            {"interpolate", kInterpolatePurpose, kInterpolateExample},
#ifdef INLIGHT_BTF_PCA_GLES
                            {"export-gles", kExportGlesPurpose, kExportGlesExample},
#endif
                           },
                           "0 ok, 1 runtime error, 2 usage error, 3 quality gate failed.", argc, argv);
}
