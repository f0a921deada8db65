// render compare: the path-traced image, the real-time model (CPU, and the exported GLES shaders
// through EGL) compared with it, and optionally its error taken apart (docs/render.md
// "Real-time model").
#include <filesystem>
#include <memory>
#include <optional>

#include "core/fs.h"
#include "core/log.h"
#include "core/validators.h"
#include "brdf/table.h"
#include "gles/scene.h"
#include "render/compare_lights.h"
#include "render/decompose.h"
#include "render/gate.h"
#include "modes.h"

namespace inlight::render_cli {
namespace {

struct CompareArgs {
    TraceArgs trace;
    render::CompareOptions cmp;
    std::string rt_lighting;
    std::vector<std::string> brdf_tables;
    bool decompose = false;
    int decompose_map_height = 128;
    double warn_mean_rel = 0, fail_mean_rel = 0, warn_de2000 = 0, fail_de2000 = 0;
    std::vector<CLI::Option*> gate_options;  ///< the four thresholds, in that order
    std::vector<std::string> gate_modes{"consistent", "seed"};
    std::string gles_texture_filter = "bilinear";
};

/// The gate's thresholds as given (unset options stay unset).
render::GateThresholds gate_thresholds(const CompareArgs& a) {
    render::GateThresholds t;
    const double* values[] = {&a.warn_mean_rel, &a.fail_mean_rel, &a.warn_de2000, &a.fail_de2000};
    std::optional<double>* slots[] = {&t.warn_mean_rel, &t.fail_mean_rel, &t.warn_de2000,
                                      &t.fail_de2000};
    for (size_t i = 0; i < 4; ++i)
        if (a.gate_options[i]->count() > 0) *slots[i] = *values[i];
    return t;
}

void add_gate_options(CLI::App& app, CompareArgs& a) {
    const struct {
        const char* name;
        double* value;
        const char* help;
    } options[] = {
        {"--warn-mean-rel", &a.warn_mean_rel,
         "Quality gate: WARNING when a graded image's mean relative error against the truth "
         "(|model - truth| / max(truth, 1e-3), averaged over pixels and channels) exceeds this"},
        {"--fail-mean-rel", &a.fail_mean_rel,
         "Quality gate: FAILURE (exit 3, outputs still written) when a graded image's mean "
         "relative error exceeds this"},
        {"--warn-de2000", &a.warn_de2000,
         "Quality gate: WARNING when a graded image's mean CIEDE2000 against the truth (after "
         "--exposure; 1 is about a just-noticeable difference) exceeds this"},
        {"--fail-de2000", &a.fail_de2000,
         "Quality gate: FAILURE (exit 3, outputs still written) when a graded image's mean "
         "CIEDE2000 exceeds this"},
    };
    for (const auto& o : options) {
        a.gate_options.push_back(app.add_option(o.name, *o.value, o.help)
                                     ->check(app::finite_non_negative())
                                     ->group("Quality gate (docs/render.md)"));
    }
    app.add_option("--gate-modes", a.gate_modes,
                   "Quality gate: the shading modes graded (consistent, seed; both exported, "
                   "so both by default)")
        ->delimiter(',')
        ->check(CLI::IsMember({"consistent", "seed"}))
        ->group("Quality gate (docs/render.md)")
        ->capture_default_str();
}

/// Grades every image the app can show (render::gate_items), prints one line per image and the
/// verdict, records metrics.realtime.gate; true on FAILURE (the message in `failure`).
bool run_gate(const render::GateThresholds& t, const std::vector<std::string>& modes,
              nlohmann::json& realtime, std::string& failure) {
    const render::GateResult g = render::grade(t, render::gate_items(realtime, modes));
    realtime["gate"] = render::to_json(t, g);
    realtime["gate"]["modes"] = modes;
    for (const auto& item : g.items) {
        log::summary("render", str("quality gate: ", item.item.name),
                     str("mean relative error ", log::num(item.item.mean_rel),
                         ", mean Delta E 2000 ", log::num(item.item.mean_de2000), ": ",
                         render::to_string(item.verdict)));
    }
    const std::string verdict = str(render::to_string(g.overall), " (", g.decided_by, ")");
    const bool failed = g.overall == render::Verdict::kFailure;
    // A FAILURE's line is app::run's error line ("render: quality gate failed: FAILURE (...)"),
    // printed even under -q.
    if (!failed) log::summary("render", "quality gate", verdict);
    failure = verdict;
    return failed;
}

/// The user's BRDF tables, read and checked against the scene before the render: one per
/// material with at least 3 bands; the band sweep stops at their bands.
void read_brdf_tables(CompareArgs& a, const render::Scene& scene, bool max_bands_given,
                      Report& report) {
    render::CompareOptions& cmp = a.cmp;
    for (const std::string& f : a.brdf_tables) {
        report.add_input(f);
        cmp.tables.push_back(brdf::read_binary(f));
    }
    if (a.brdf_tables.empty()) {
        log::info(str("render: no --brdf-table: the compare bakes each material's table here (",
                      cmp.grid, ", ", cmp.bake_samples, " samples per normal)"));
        return;
    }
    const size_t n = scene.desc().materials.size();
    if (cmp.tables.size() != n) {
        throw UsageError(str("--brdf-table: ", log::count(int64_t(cmp.tables.size()), "table"),
                             " for ", log::count(int64_t(n), "material"), " of ", a.trace.scene,
                             " (one each, in scene order)"));
    }
    int bands = brdf::kMaxBakeBands;
    for (size_t i = 0; i < n; ++i) {
        if (cmp.tables[i].sh_bands < 3) {
            throw UsageError(str("--brdf-table ", a.brdf_tables[i], ": ", cmp.tables[i].sh_bands,
                                 " SH bands; the compare needs 3 (the app's)"));
        }
        bands = std::min(bands, cmp.tables[i].sh_bands);
    }
    if (cmp.max_bands > bands) {
        if (max_bands_given) {
            throw UsageError(str("--rt-max-bands ", cmp.max_bands, ": the --brdf-table "
                                 "tables have ", bands, " SH bands"));
        }
        log::info(str("render: band sweep 1..", bands, ", the --brdf-table tables' bands"));
        cmp.max_bands = bands;
    }
}

}  // namespace

ModeBody add_compare(CLI::App& app, const app::CommonArgs& common) {
    auto a = std::make_shared<CompareArgs>();
    render::CompareOptions& cmp = a->cmp;
    add_trace_options(app, a->trace);
    add_image_compare_options(app, cmp);
    app.add_option("--rt-lighting", a->rt_lighting,
                   "Also run the model lit by this envmap-project JSON (SH of the residual + "
                   "extracted lights, from --max-error) beside pure SH at its band count: "
                   "<output>_rt_lights.exr, _compare_lights.png, metrics.realtime.lighting_file")
        ->check(CLI::ExistingFile);
    app.add_flag("--decompose", a->decompose,
                 "Take the model's error apart by replacing one approximation at a time with its "
                 "exact counterpart (grid, SH truncation, roughness texture, fixed view, "
                 "visibility, truth noise): metrics.realtime.decomposition; with --rt-lighting "
                 "also for the SH + lights model (with the lights' shading as a part): "
                 "metrics.realtime.decomposition_lighting_file");
    app.add_option("--decompose-map-height", a->decompose_map_height,
                   "Rows of the box-filtered map the exact integrals of --decompose sum over")
        ->check(CLI::Range(4, 4096))
        ->capture_default_str();
    auto* max_bands =
        app.add_option("--rt-max-bands", cmp.max_bands, "Real-time model: largest SH band count swept")
            ->check(CLI::Range(3, 8))
            ->capture_default_str();
    add_bake_options(app, cmp, "rt-");
    app.add_option("--brdf-table", a->brdf_tables,
                   "Validate these BRDF tables (brdf-sh-bake's .bin, one per scene material in "
                   "scene order) instead of baking each material here at --rt-grid; the band "
                   "sweep stops at the tables' bands")
        ->check(CLI::ExistingFile)
        ->excludes("--rt-grid")
        ->excludes("--rt-bake-samples");
    app.add_option("--rt-supersample", cmp.supersample,
                   "Real-time fragments per pixel side (box filter like the path tracer)")
        ->check(CLI::Range(1, 16))
        ->capture_default_str();
    app.add_option("--gles-texture-filter", a->gles_texture_filter,
                   "Texture filter of the GLES column's variants and of the one-fragment-per-pixel "
                   "CPU model they are compared with: bilinear (level 0) or trilinear (the mip "
                   "atlas, docs/gles.md 'Texture filtering')")
        ->check(app::parses_with([](const std::string& s) { gles::texture_filter_from_string(s); }, "NAME"))
        ->capture_default_str();
    add_gate_options(app, *a);
    return [a, max_bands, &common](Report& report) {
        TraceArgs& t = a->trace;
        a->cmp.gles_texture_filter = gles::texture_filter_from_string(a->gles_texture_filter);
        const render::CompareOptions& compare = a->cmp;
        const render::GateThresholds gate = gate_thresholds(*a);
        render::check_gate_thresholds(gate);
        prepare_trace(t, common.seed, report);
        std::unique_ptr<render::LightingFile> lighting;  // read before any rendering
        if (!a->rt_lighting.empty()) {
            fs::declare_input(a->rt_lighting, "--rt-lighting");
            lighting = std::make_unique<render::LightingFile>(
                render::read_lighting_file(a->rt_lighting));
            report.add_input(a->rt_lighting);
        }
        const auto scene = load_scene(t.scene, t.width_px, t.height_px, report);
        read_brdf_tables(*a, *scene, max_bands->count() > 0, report);
        const render::RenderResult r = trace(*scene, t, report);
        auto& m = report.metrics();
        const std::filesystem::path p(t.output);
        const std::string prefix = (p.parent_path() / p.stem()).string();
        {
            ScopedStage stage(report, "compare");
            std::vector<render::WrittenFile> files;
            m["realtime"] = render::compare_realtime(*scene, r, compare, prefix, files);
            if (lighting)
                m["realtime"]["lighting_file"] =
                    render::compare_lighting_file(*scene, r, compare, *lighting, prefix, files);
            for (const auto& f : files) report.add_output(f.path, f.kind, f.color_space);
            render::print_compare_summary(m["realtime"]);
            files.clear();
            m["realtime"]["gles"] =
                gles::compare_scene(*scene, r, compare, prefix, files, lighting.get());
            for (const auto& f : files) report.add_output(f.path, f.kind, f.color_space);
        }
        if (a->decompose) {
            ScopedStage stage(report, "decompose");
            render::DecomposeOptions dopt;
            dopt.max_bands = compare.max_bands;
            // A truth of pixel centres (--no-jitter) is compared at pixel centres.
            dopt.supersample = t.no_jitter ? 1 : compare.supersample;
            dopt.map_height = a->decompose_map_height;
            dopt.bake = render::compare_bake_options(*scene, compare, compare.max_bands);
            const render::RealtimeLighting pure =
                render::compare_lighting(*scene, compare, compare.max_bands);
            const render::Decomposition d = render::decompose_error(*scene, r, pure, dopt);
            m["realtime"]["decomposition"] = render::to_json(d);
            if (lighting) {  // the SH + lights model of --rt-lighting, at the file's bands
                render::RealtimeLighting lit{lighting->sh.coeffs, pure.tables, lighting->lights};
                dopt.max_bands = lighting->sh.sh_bands;
                m["realtime"]["decomposition_lighting_file"] =
                    render::to_json(render::decompose_error(*scene, r, lit, dopt));
            }
            log::info(str("render: truth noise ", d.truth_noise,
                          ", exact unshadowed model vs truth ", d.exact_vs_truth,
                          " (decomposition in ", d.time_s, " s)"));
        }
        std::string gate_failure;
        const bool gate_failed = gate.any() && run_gate(gate, a->gate_modes, m["realtime"], gate_failure);
        check_quality_gate(t, r);
        if (gate_failed) throw app::QualityGateFailed(gate_failure);
    };
}

}  // namespace inlight::render_cli
