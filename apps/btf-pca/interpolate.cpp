// btf-pca interpolate: a BTF or a btf-pca folder evaluated at (light, view) pairs.
#include <string>

#include "btf/interp_run.h"
#include "btf/pca_run.h"
#include "core/app.h"
#include "core/validators.h"
#include "modes.h"

namespace inlight::btf_pca_cli {

void add_open_options(CLI::App& app, btf::OpenOptions& open, bool& linear) {
    app.add_option("--light-directions", open.light_directions, "Light direction file "
                   "(default: the UBO2003 dome)")->check(CLI::ExistingFile);
    app.add_option("--view-directions", open.view_directions, "View direction file "
                   "(default: the UBO2003 dome)")->check(CLI::ExistingFile);
    app.add_flag("--linear-input", linear, "8/16-bit images hold linear values (default: sRGB-encoded)");
}

int interpolate(int argc, char** argv) {
    CLI::App app{kInterpolatePurpose, "btf-pca interpolate"};
    app::CommonArgs common;
    btf::InterpRunOptions o;
    app.add_option("input", o.input, "BTF folder, Bonn .zip file or btf-pca output folder (it "
                   "holds btf-pca.json)")->required()->check(CLI::ExistingPath);
    app.add_option("--pairs", o.pairs, "The (light, view) pairs to evaluate, one per line as "
                   "render capture-btf --btf-pairs reads them (docs/btf-interpolation.md)")
        ->required()->check(CLI::ExistingFile);
    app.add_option("-o,--output", o.output, "Output folder: one EXR per pair")->required();
    std::string scheme = "delaunay";
    app.add_option("--scheme", scheme, "thesis (three closest directions per ring), delaunay "
                   "(spherical Delaunay triangles) or nearest (no interpolation, the baseline)")
        ->check(CLI::IsMember({"thesis", "delaunay", "nearest"}))->capture_default_str();
    app.add_option("--truth", o.truth, "A capture of the same pairs to compare with")
        ->check(CLI::ExistingDirectory);
    bool linear = false;
    add_open_options(app, o.open, linear);
    app::setup(app, common, kInterpolateExample);
    if (auto code = app::parse(app, argc, argv, 1)) return *code;
    o.open.decode_srgb = !linear;
    o.scheme = btf::interp_scheme_from_string(scheme);
    return app::run("btf-pca", app, common, argc, argv,
                    [&](Report& report) { btf::run_interpolation(o, report); });
}

}  // namespace inlight::btf_pca_cli
