// btf-pca: the codec of a bidirectional texture function (docs/btf.md).
//   btf-pca compress:     a BTF (UBO2003 folder or Bonn zip file) -> PCA per group of k
//                         neighbouring views, components stored for streaming, Table 7.1-style
//                         errors in the report
//   btf-pca interpolate:  a BTF or a btf-pca folder evaluated at arbitrary (light, view) pairs by
//                         angular interpolation (docs/btf-interpolation.md)
#include <filesystem>
#include <iostream>
#include <string>

#include "btf/interp_run.h"
#include "btf/pca_run.h"
#include "core/app.h"
#include "core/modes.h"
#include "core/validators.h"

using namespace inlight;

namespace {

constexpr const char* kCompressPurpose =
    "btf-pca compress: PCA compression of a bidirectional texture function per group of k "
    "neighbouring views, components as 8-bit PNG (or EXR) ordered for streaming";
constexpr const char* kCompressExample =
    "btf-pca compress wool_btf.zip -o out/wool -k 3 -c 8 --report wool.json";
constexpr const char* kInterpolatePurpose =
    "btf-pca interpolate: evaluate a BTF or a btf-pca output folder at each (light, view) pair of "
    "a file by angular interpolation, one EXR per pair (docs/btf-interpolation.md)";
constexpr const char* kInterpolateExample =
    "btf-pca interpolate out/wool --pairs pairs.txt -o out/wool_interp --scheme delaunay";

/// The options both modes read a raw BTF with; `linear` is --linear-input.
void add_open_options(CLI::App& app, btf::OpenOptions& open, bool& linear) {
    app.add_option("--light-directions", open.light_directions, "Light direction file "
                   "(default: the UBO2003 dome)")->check(CLI::ExistingFile);
    app.add_option("--view-directions", open.view_directions, "View direction file "
                   "(default: the UBO2003 dome)")->check(CLI::ExistingFile);
    app.add_flag("--linear-input", linear, "8/16-bit images hold linear values (default: sRGB-encoded)");
}

int compress(int argc, char** argv) {
    CLI::App app{kCompressPurpose, "btf-pca compress"};
    app::CommonArgs common;
    btf::PcaRunOptions o;
    std::string method = "auto", format = "png";
    app.add_option("input", o.input, "BTF folder (UBO2003 names at any depth) or Bonn .zip file")
        ->required()->check(CLI::ExistingPath);
    app.add_option("-o,--output", o.output, "Output folder (btf-pca.json, weights.bin, component "
                   "images, streaming.tsv/.gp)")->required();
    app.add_option("-k,--view-group-size", o.pca.view_group_size, "Neighbouring views per PCA "
                   "group (1 = PCA RF; >= the view count = one PCA)")->check(CLI::Range(1, 100000))->capture_default_str();
    app.add_option("-c,--components", o.pca.components, "Components per group (with --max-rmse: "
                   "the most a group may keep)")->check(CLI::Range(1, 4096))->capture_default_str();
    app.add_option("--max-rmse", o.pca.max_rmse, "Error budget: each group keeps the fewest "
                   "components whose RMS error (unquantised, in --fit-space units) is at most this; -1 = off")
        ->check(app::finite_range_or(0, 1e6, -1))->capture_default_str();
    app.add_option("--method", method, "auto: Gram matrix up to --gram-max-side, randomized SVD "
                   "above; full-svd is the slow reference")
        ->check(CLI::IsMember({"auto", "gram", "randomized", "full-svd"}))->capture_default_str();
    app.add_option("--gram-max-side", o.pca.gram_max_side, "Largest short side (pixels or "
                   "columns) solved through its Gram matrix")->check(CLI::Range(1, 65536))->capture_default_str();
    app.add_option("--oversampling", o.pca.oversampling, "Randomized SVD: extra test vectors")
        ->check(CLI::Range(0, 1000))->capture_default_str();
    app.add_option("--power-iterations", o.pca.power_iterations, "Randomized SVD: power iterations")
        ->check(CLI::Range(0, 20))->capture_default_str();
    int64_t max_memory_mib = 0;
    app.add_option("--max-memory-mib", max_memory_mib, "Memory budget per view group (MiB): a group whose "
                   "in-core fit would exceed it is streamed from the images a block of views at a time "
                   "(out of core, same result); 0 = half the physical memory")
        ->check(CLI::Range(int64_t(0), int64_t(1) << 30))->capture_default_str();
    app.add_option("--stream-views", o.pca.stream_views, "Fit groups larger than this many views out of "
                   "core, this many views per block (0 = chosen from --max-memory-mib)")
        ->check(CLI::Range(0, 100000))->capture_default_str();
    app.add_option("--format", format, "Component images: 8-bit PNG with scale/offset each, or "
                   "half/float EXR")->check(CLI::IsMember({"png", "exr-half", "exr-float"}))->capture_default_str();
    std::string fit_space = "linear";
    app.add_option("--quant-noise", o.quant_noise, "png: quantise each group's components with one step "
                   "chosen so that rounding adds about this fraction of the group's residual error energy "
                   "(small components then use few codes and fewer bytes); 0 = each on 256 levels")
        ->check(app::finite_range_or(0, 10, 0))->capture_default_str();
    std::string weights_format = "float32";
    app.add_option("--weights-format", weights_format, "How V (weights.bin) is stored: float32, float16, or "
                   "uint8 with a scale and offset per component")
        ->check(CLI::IsMember({"float32", "float16", "uint8"}))->capture_default_str();
    app.add_option("--fit-space", fit_space, "Values the PCA fits: linear radiance (weighted sums of "
                   "images fold into the components), srgb-encoded values (the 8-bit codes / 255, "
                   "perceptually closer) or CIELAB (squared error = Delta E 1976 squared; "
                   "docs/btf-table71.md)")->check(CLI::IsMember({"linear", "srgb", "lab"}))->capture_default_str();
    std::string fit_norm = "l2";
    app.add_option("--fit-norm", fit_norm, "l2: the PCA (least squares); l1: the PCA's components then "
                   "refitted towards the least absolute error, the norm of the MAE figures (iteratively "
                   "reweighted least squares; each group in memory)")->check(CLI::IsMember({"l2", "l1"}))->capture_default_str();
    int l1_iterations = 16;
    auto* l1_opt = app.add_option("--l1-iterations", l1_iterations, "--fit-norm l1: rounds of reweighting (each solves every "
                   "row of L and every column of V once)")->check(CLI::Range(1, 1000))->capture_default_str();
    app.add_option("--color-samples", o.color_samples, "Colour triples for the CIELAB, Delta E "
                   "2000 and 8-bit figures (evenly strided)")->check(CLI::Range(int64_t(1), int64_t(1) << 40))->capture_default_str();
    app.add_option("--table-components", o.table_components, "Also report the model cut to each of "
                   "these component counts (Table 7.1 rows from one run), e.g. 1,2,4,8")
        ->delimiter(',')->check(CLI::Range(1, 4096));
    app.add_option("--reference", o.reference, "A second BTF of the same directions and size (e.g. "
                   "an independent capture): the input and the table rows are also measured against it")
        ->check(CLI::ExistingPath);
    bool linear = false;
    add_open_options(app, o.open, linear);
    app::setup(app, common, kCompressExample);
    if (auto code = app::parse(app, argc, argv, 1)) return *code;
    o.open.decode_srgb = !linear;
    o.pca.method = btf::pca_method_from_string(method);
    o.encoding = btf::component_encoding_from_string(format);
    o.fit_space = btf::fit_space_from_string(fit_space);
    o.pca.l1_iterations = fit_norm == "l1" ? l1_iterations : 0;
    o.weights_format = btf::weights_format_from_string(weights_format);
    o.pca.seed = common.seed;
    o.max_memory_bytes = uint64_t(max_memory_mib) << 20;
    return app::run("btf-pca", app, common, argc, argv, [&](Report& report) {
        if (l1_opt->count() > 0 && fit_norm != "l1")
            throw UsageError(str("--l1-iterations ", l1_iterations, ": applies only to --fit-norm l1 (the fit is --fit-norm ", fit_norm, ")"));
        btf::run_pca(o, report);
    });
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
    if (const char* meant = old_mode(argc, argv)) {
        std::cerr << "btf-pca: modes are subcommands now: use 'btf-pca " << meant
                  << "' (see btf-pca --help)\n";
        return app::kExitUsage;
    }
    return app::list_modes("btf-pca", "btf-pca: the codec of a bidirectional texture function: "
                           "PCA compression, and decompression at arbitrary directions",
                           {{"compress", kCompressPurpose, kCompressExample},
                            {"interpolate", kInterpolatePurpose, kInterpolateExample}},
                           "0 ok, 1 runtime error, 2 usage error, 3 quality gate failed.", argc, argv);
}
