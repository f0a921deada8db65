// btf-pca export-gles: OpenGL ES shaders, atlases and lighting matrices that draw a btf-pca
// folder (gles/btf_export.h, docs/btf-gles.md).
#include <string>

#include "core/app.h"
#include "core/error.h"
#include "core/fs.h"
#include "core/validators.h"
#include "gles/btf_export.h"
#include "modes.h"

namespace inlight::btf_pca_cli {

int export_gles(int argc, char** argv) {
    CLI::App app{kExportGlesPurpose, "btf-pca export-gles"};
    app::CommonArgs common;
    std::string input, output, versions = "100,300", precision = "highp", atlases = "write";
    gles::BtfGlesOptions o;
    app.add_option("input", input, "btf-pca output folder (it holds btf-pca.json; linear fit space, 8-bit PNG "
                   "components)")->required()->check(CLI::ExistingDirectory);
    app.add_option("-o,--output", output, "Output folder: btf-gles.json, the shaders, one atlas per view group "
                   "and lighting-matrices.bin")->required();
    app.add_option("--bands", o.sh_bands, "SH bands of the lighting the matrices take (1..9)")
        ->check(CLI::Range(1, 9))->capture_default_str();
    app.add_option("--gles-versions", versions, "GLSL ES versions: 100, 300 or both (comma list)")
        ->check(app::parses_with([](const std::string& s) { gles::glsl_versions_from_string(s); }, "LIST"))
        ->capture_default_str();
    app.add_option("--precision", precision, "Fragment float precision: highp only (mediump is refused: docs/btf-gles.md)")
        ->capture_default_str();
    app.add_option("--irradiance-w-m2", o.irradiance_w_m2, "The capture's irradiance E (image = btf x E) the "
                   "matrices divide by (default: the folder's btf-pca.json irradiance_w_m2, which btf-pca records "
                   "from a capture's capture.json, else 1)")
        ->check(app::finite_positive());
    app.add_option("--atlases", atlases, "write: one atlas PNG per view group; none: no atlas files, the app "
                   "assembles them from the folder's PNGs by btf-gles.json's channel files (a fabric bundle, which "
                   "ships those PNGs already: docs/btf-gles.md \"In the bundle\")")
        ->check(CLI::IsMember({"write", "none"}))->capture_default_str();
    app::setup(app, common, kExportGlesExample);
    if (auto code = app::parse(app, argc, argv, 1)) return *code;
    if (precision != "highp") {
        std::cerr << "btf-pca export-gles: --precision " << precision
                  << ": refused: mediump guarantees a 10-bit mantissa, and the shader sums 3 x (1 + C) decoded "
                     "8-bit terms of either sign, often 10 times the pixel's value: the rounding bound, 3 (1 + C) "
                     "x 2^-11 x the terms' size, exceeds one 8-bit code (docs/btf-gles.md, \"Precision\"); use highp\n";
        return app::kExitUsage;
    }
    o.versions = gles::glsl_versions_from_string(versions);
    o.write_atlases = atlases == "write";
    return app::run("btf-pca", app, common, argc, argv, [&](Report& report) {
        report.add_input(input + "/btf-pca.json");
        const gles::BtfGlesExport e = gles::export_btf_gles(input, o);
        for (const auto& [name, bytes] : e.files()) {
            const std::string path = output + "/" + name;
            fs::write_text_atomic(path, bytes);
            report.add_output(path, "btf_gles_export");
        }
        report.metrics()["btf_gles_export"] = {{"dir", output},
                                               {"variants", e.variants.size()},
                                               {"texture_bytes", e.manifest["textures"]["bytes_total"]},
                                               {"matrices_bytes", e.manifest["matrices"]["bytes"]}};
    });
}

}  // namespace inlight::btf_pca_cli
