// btf-pca compress: PCA per group of k neighbouring views, components stored for streaming.
#include <string>

#include "btf/interp_run.h"
#include "btf/pca_run.h"
#include "core/app.h"
#include "core/validators.h"
#include "modes.h"

namespace inlight::btf_pca_cli {

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
                   "group (1 = PCA RF; >= the view count = one PCA). Larger k: fewer bytes for the same C, more error "
                   "where neighbouring views differ (woven captures, k 1 -> 3 at C = 8: +12-47% MAE Lab for 2.2x the "
                   "ratio; docs/btf.md)")->check(CLI::Range(1, 100000))->capture_default_str();
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
                   "(small components then use few codes and fewer bytes), and with --weights-format "
                   "uint8-deflate V's columns likewise (as much again); 0 = each on 256 levels. Measured: wool-twill "
                   "k = 1, C = 8 at 0.1: 33% fewer component bytes for +0.01 MAE Lab")
        ->check(app::finite_range_or(0, 10, 0))->capture_default_str();
    std::string weights_format = "float32";
    app.add_option("--weights-format", weights_format, "How V (weights.bin) is stored: float32, float16, "
                   "uint8 with a scale and offset per component, or uint8-deflate: those codes, each column a "
                   "zlib stream, and with --quant-noise each column's step chosen as the components' (few "
                   "codes, about 4x fewer bytes for V at --quant-noise 0.1). V is 19683 x C values on the Bonn "
                   "dome whatever k: 30% of a 64 x 64 px k = 3, C = 8 folder, most of a k = 81 one. uint8: +0.3% MAE Lab; "
                   "uint8-deflate with --quant-noise 0.02: the folder 1:131 -> 1:152 for +3% MAE Lab (denim, k = 3, "
                   "C = 8, lab). The BTF shaders draw every format at the same cost (V is folded at export)")
        ->check(CLI::IsMember({"float32", "float16", "uint8", "uint8-deflate"}))->capture_default_str();
    app.add_option("--fit-space", fit_space, "Values the PCA fits: linear radiance (weighted sums of "
                   "images fold into the components), srgb-encoded values (the 8-bit codes / 255, "
                   "perceptually closer) or CIELAB (squared error = Delta E 1976 squared; "
                   "docs/btf-table71.md). srgb: 10-47% less MAE Lab than linear at equal parameters; but only linear "
                   "folds the app's per-frame lighting into C weights, so export-gles draws linear folders only "
                   "(an sRGB or Lab one would cost a pixel ~60x the arithmetic; docs/btf-gles.md)")->check(CLI::IsMember({"linear", "srgb", "lab"}))->capture_default_str();
    std::string fit_norm = "l2";
    app.add_option("--fit-norm", fit_norm, "l2: the PCA (least squares); l1: the PCA's components then "
                   "refitted towards the least absolute error, the norm of the MAE figures (iteratively "
                   "reweighted least squares; each group in memory). l1 with lab against l2 with srgb: 14-22% less "
                   "MAE Lab, 14-29% more RMSE, ~10x the time (wool-twill 64 x 64, k = 1, C = 8: 64 s against 6 s)")->check(CLI::IsMember({"l2", "l1"}))->capture_default_str();
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
    std::string codec = "inlight";
    app.add_option("--codec", codec, "inlight: these options; thesis: the BTF thesis' method as the "
                   "baseline (k consecutive views, the PCA of the 8-bit sRGB values, U and V on 8 bits as "
                   "(x + 1) / 2 after a power-of-ten factor, Sigma as four digits, streamed component by "
                   "component; implies --fit-space srgb --weights-format uint8 --method gram, and refuses options that "
                   "change its method)")->check(CLI::IsMember({"inlight", "thesis"}))->capture_default_str();
    bool linear = false;
    add_open_options(app, o.open, linear);
    app::setup(app, common, kCompressExample);
    if (auto code = app::parse(app, argc, argv, 1)) return *code;
    o.codec = btf::codec_from_string(codec);
    if (o.codec == btf::Codec::kThesis) {
        // The thesis' settings where none is given; a conflicting one is named by run_pca.
        if (app.count("--fit-space") == 0) fit_space = "srgb";
        if (app.count("--weights-format") == 0) weights_format = "uint8";
        // Its SVD: an exact decomposition (the Gram matrix's, in double), not the randomized one.
        if (app.count("--method") == 0) method = "gram";
        o.pca.grouping = btf::ViewGrouping::kConsecutive;
    }
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

}  // namespace inlight::btf_pca_cli
