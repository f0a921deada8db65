// render: the ground-truth path tracer. Renders a scene file to a float EXR (linear_srgb) and
// its per-pixel standard error, progressively, deterministically for a seed and any --threads.
#include <filesystem>
#include <memory>

#include "core/app.h"
#include "core/fs.h"
#include "core/log.h"
#include "core/validators.h"
#include "brdf/grid.h"
#include "brdf/table.h"
#include "gles/cli.h"
#include "gles/scene.h"
#include "image/image.h"
#include "render/capture_cli.h"
#include "render/compare.h"
#include "render/compare_lights.h"
#include "render/decompose.h"
#include "render/path_tracer.h"
#include "render/scene.h"

using namespace inlight;

namespace {

struct Args {
    std::string scene, output, stderr_output, strategy = "mis", rt_lighting, sampler = "sobol";
    std::string convergence_ref_image;
    bool convergence_ref_irradiance = false;
    int width_px = 0, height_px = 0, convergence_ref_spp = 0, decompose_map_height = 128;
    double max_rel_error = 0;
    bool no_jitter = false, compare = false, decompose = false;
};

std::string default_stderr_path(const std::string& output) {
    std::filesystem::path p(output);
    return (p.parent_path() / (p.stem().string() + "_stderr.exr")).string();
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"render: ground-truth path tracer (Embree) of a scene file, float EXR output",
                 "render"};
    app::CommonArgs common;
    render::RenderOptions opt;
    render::CompareOptions cmp;
    Args a;
    render::CaptureArgs cap;
    gles::ExportArgs gles_args;
    app.add_option("scene", a.scene,
                   "Scene file (.toml, see docs/render.md); with --btf-capture a fabric file")
        ->required()
        ->check(CLI::ExistingFile);
    app.add_option("-o,--output", a.output,
                   "Radiance image (.exr, float, linear_srgb); with --btf-capture a folder")
        ->required();
    app.add_option("--stderr-output", a.stderr_output,
                   "Per-pixel standard error of the mean (.exr; default <output>_stderr.exr)");
    app.add_option("--spp", opt.spp, "Samples per pixel (the maximum with a stop rule)")
        ->check(CLI::Range(1, 1 << 20))
        ->capture_default_str();
    app.add_option("--time-budget-s", opt.time_budget_s,
                   "Stop after the pass that reaches this render time, seconds (0 = none)")
        ->check(app::finite_non_negative())
        ->capture_default_str();
    app.add_option("--target-rel-error", opt.target_rel_error,
                   "Stop when the image's relative noise (RMS standard error of luminance / mean "
                   "luminance) is at most this (0 = none)")
        ->check(app::finite_non_negative())
        ->capture_default_str();
    app.add_option("--max-depth", opt.max_depth, "Surface interactions per path (cap)")
        ->check(CLI::Range(1, 1024))
        ->capture_default_str();
    app.add_option("--rr-depth", opt.rr_depth, "Russian roulette from this interaction on")
        ->check(CLI::Range(1, 1024))
        ->capture_default_str();
    app.add_option("--strategy", a.strategy, "Light transport estimator: mis | bsdf | light")
        ->check(CLI::IsMember({"mis", "bsdf", "light"}))
        ->capture_default_str();
    app.add_option("--sampler", a.sampler,
                   "Sample numbers: sobol (Owen-scrambled, Morton-ordered pixels) | independent")
        ->check(CLI::IsMember({"sobol", "independent"}))
        ->capture_default_str();
    app.add_option("--scramble-groups", opt.scramble_groups,
                   "Sobol: independently scrambled groups per pixel that estimate its noise")
        ->check(CLI::Range(2, 16))
        ->capture_default_str();
    app.add_flag("--adaptive", opt.adaptive,
                 "Adaptive sampling: --spp becomes the mean over the image; passes go to the "
                 "pixels whose noise falls most per sample (stop with --spp, --time-budget-s or "
                 "--target-rel-error)");
    app.add_option("--adaptive-min-spp", opt.adaptive_min_spp,
                   "Adaptive: uniform samples per pixel before the first choice")
        ->check(CLI::Range(2, 1 << 16))
        ->capture_default_str();
    app.add_option("--adaptive-max-factor", opt.adaptive_max_factor,
                   "Adaptive: one pixel takes at most this x --spp samples")
        ->check(CLI::Range(1, 1024))
        ->capture_default_str();
    app.add_option("--tile-px", opt.tile_px, "Tile size in pixels (unit of parallel work)")
        ->check(CLI::Range(1, 4096))
        ->capture_default_str();
    app.add_flag("--no-jitter", a.no_jitter, "Sample pixel centres only (no box filter)");
    app.add_option("--width-px", a.width_px, "Override the camera's width in pixels (0 = scene)")
        ->check(CLI::Range(0, 16384))
        ->capture_default_str();
    app.add_option("--height-px", a.height_px, "Override the camera's height in pixels (0 = scene)")
        ->check(CLI::Range(0, 16384))
        ->capture_default_str();
    app.add_option("--convergence-ref-spp", a.convergence_ref_spp,
                   "Also measure error against samples: reference with this many spp, snapshots "
                   "at 1, 4, 16, ... up to --spp; slope into the report (0 = off)")
        ->check(CLI::Range(0, 1 << 20))
        ->capture_default_str();
    auto* ref_image = app.add_option("--convergence-ref-image", a.convergence_ref_image,
                                     "Error against samples, against this EXR (a converged "
                                     "render; its _stderr.exr is used when present)")
                          ->check(CLI::ExistingFile)
                          ->excludes("--convergence-ref-spp");
    app.add_flag("--convergence-ref-irradiance", a.convergence_ref_irradiance,
                 "Error against samples, against the exact image of a Lambert sphere from "
                 "brute-force irradiance (needs --no-jitter)")
        ->excludes("--convergence-ref-spp")
        ->excludes(ref_image);
    app.add_option("--max-rel-error", a.max_rel_error,
                   "Quality gate: exit 3 if the final relative noise exceeds this (0 = off)")
        ->check(app::finite_non_negative())
        ->capture_default_str();
    app.add_flag(
        "--compare", a.compare,
        "Also run the real-time model (consistent and seed modes, bands 1..--rt-max-bands) "
        "and compare it with the path tracer: <output>_rt_*, _compare_*.png, _relerr_*, "
        "_de2000_*, metrics.realtime in the report; and the exported GLES shaders run through "
        "EGL: <output>_gles_*, _compare3_*.png (truth | CPU model | GLES | error), "
        "metrics.realtime.gles");
    app.add_option("--rt-lighting", a.rt_lighting,
                   "With --compare: also run the model lit by this envmap-project JSON (SH of "
                   "the residual + extracted lights, from --max-error) beside pure SH at its "
                   "band count: <output>_rt_lights.exr, _compare_lights.png, "
                   "metrics.realtime.lighting_file")
        ->check(CLI::ExistingFile)
        ->needs("--compare");
    app.add_flag("--rt-decompose", a.decompose,
                 "With --compare: take the model's error apart by replacing one approximation at "
                 "a time with its exact counterpart (grid, SH truncation, roughness texture, "
                 "fixed view, visibility, truth noise): metrics.realtime.decomposition; with "
                 "--rt-lighting also for the SH + lights model (with the lights' shading as a "
                 "part): metrics.realtime.decomposition_lighting_file")
        ->needs("--compare");
    app.add_option("--rt-decompose-map-height", a.decompose_map_height,
                   "Rows of the box-filtered map the exact integrals of --rt-decompose sum over")
        ->check(CLI::Range(4, 4096))
        ->capture_default_str();
    app.add_option("--exposure", cmp.exposure,
                   "Linear scale before dE2000 and the PNG panels (0 = 0.18 / mean luminance)")
        ->check(app::finite_non_negative())
        ->capture_default_str();
    app.add_option("--heat-max-rel", cmp.heat_max_rel, "Relative error at the top of the heat map")
        ->check(app::finite_positive())
        ->capture_default_str();
    app.add_option("--rt-max-bands", cmp.max_bands, "Real-time model: largest SH band count swept")
        ->check(CLI::Range(3, 8))
        ->capture_default_str();
    app.add_option("--rt-grid", cmp.grid, "Real-time model: BRDF table grid (brdf-sh-bake --grid)")
        ->check(app::parses_with([](const std::string& g) { brdf::parse_grid(g); }, "GRID"))
        ->capture_default_str();
    app.add_option("--rt-bake-samples", cmp.bake_samples, "BRDF table: evaluations per normal")
        ->check(CLI::Range(16, 1 << 22))
        ->capture_default_str();
    std::vector<std::string> brdf_tables;
    app.add_option("--brdf-table", brdf_tables,
                   "With --compare: validate these BRDF tables (brdf-sh-bake's .bin, one per "
                   "scene material in scene order) instead of baking each material here at "
                   "--rt-grid; the band sweep stops at the tables' bands")
        ->check(CLI::ExistingFile)
        ->needs("--compare")
        ->excludes("--rt-grid")
        ->excludes("--rt-bake-samples");
    app.add_option("--rt-supersample", cmp.supersample,
                   "Real-time fragments per pixel side (box filter like the path tracer)")
        ->check(CLI::Range(1, 16))
        ->capture_default_str();
    render::add_capture_options(app, cap);
    render::ShadeArgs shade;
    render::add_shade_options(app, shade);
    gles::add_export_options(app, gles_args);
    app::setup(app, common,
               "render configs/scenes/patch_city.toml -o patch.exr --spp 256 --seed 7 "
               "--threads 2 --report patch.json");
    if (auto code = app::parse(app, argc, argv)) return *code;

    return app::run("render", app, common, argc, argv, [&](Report& report) {
        if (a.convergence_ref_irradiance && !a.no_jitter)
            throw UsageError("--convergence-ref-irradiance needs --no-jitter (the brute force "
                             "gives each pixel centre's value)");
        opt.seed = common.seed;
        opt.jitter = !a.no_jitter;
        opt.strategy = render::strategy_from_string(a.strategy);
        opt.sampler = render::sampler_from_string(a.sampler);
        if (cap.enabled || !shade.btf.empty()) {
            if (cap.enabled) render::check_capture_folder(a.output);
            render::CaptureOptions co;
            co.width_px = a.width_px > 0 ? a.width_px : co.width_px;
            co.height_px = a.height_px > 0 ? a.height_px : co.height_px;
            co.spp = app.get_option("--spp")->count() > 0 ? opt.spp : cap.default_spp;
            co.seed = opt.seed;
            co.max_depth = opt.max_depth;
            co.rr_depth = opt.rr_depth;
            co.jitter = opt.jitter;
            co.tile_px = opt.tile_px;
            if (!shade.btf.empty()) {
                render::run_shade(shade, a.scene, a.output, co, cmp, report);
            } else {
                render::run_capture(cap, a.scene, a.output, co, report);
            }
            return;
        }
        if (a.stderr_output.empty()) a.stderr_output = default_stderr_path(a.output);
        image::check_writable_name(a.output, "-o");
        image::check_writable_name(a.stderr_output, "--stderr-output");
        report.add_input(a.scene);
        fs::declare_output(a.output, "-o");
        fs::declare_output(a.stderr_output, "--stderr-output");
        std::unique_ptr<render::LightingFile> lighting;  // read before any rendering
        if (!a.rt_lighting.empty()) {
            fs::declare_input(a.rt_lighting, "--rt-lighting");
            lighting = std::make_unique<render::LightingFile>(
                render::read_lighting_file(a.rt_lighting));
            report.add_input(a.rt_lighting);
        }
        gles::ExportSet gles_set;
        if (!gles_args.dir.empty()) gles_set = gles_args.prepare(report);
        std::unique_ptr<render::Scene> scene;
        {
            ScopedStage stage(report, "load scene");
            render::SceneDesc desc = render::load_scene_desc(a.scene);
            if (a.width_px > 0) desc.camera.width_px = a.width_px;
            if (a.height_px > 0) desc.camera.height_px = a.height_px;
            scene = std::make_unique<render::Scene>(std::move(desc));
            for (const auto& f : scene->files()) report.add_input(f);
        }
        // The user's BRDF tables, checked against the scene before the render.
        for (const std::string& f : brdf_tables) {
            report.add_input(f);
            cmp.tables.push_back(brdf::read_binary(f));
        }
        if (!brdf_tables.empty()) {
            const size_t n = scene->desc().materials.size();
            if (cmp.tables.size() != n) {
                throw UsageError(str("--brdf-table: ", log::count(int64_t(cmp.tables.size()), "table"),
                                     " for ", log::count(int64_t(n), "material"), " of ", a.scene,
                                     " (one each, in scene order)"));
            }
            int bands = brdf::kMaxBakeBands;
            for (size_t i = 0; i < n; ++i) {
                if (cmp.tables[i].sh_bands < 3) {
                    throw UsageError(str("--brdf-table ", brdf_tables[i], ": ",
                                         cmp.tables[i].sh_bands,
                                         " SH bands; the compare needs 3 (the app's)"));
                }
                bands = std::min(bands, cmp.tables[i].sh_bands);
            }
            if (cmp.max_bands > bands) {
                if (app.get_option("--rt-max-bands")->count() > 0) {
                    throw UsageError(str("--rt-max-bands ", cmp.max_bands, ": the --brdf-table "
                                         "tables have ", bands, " SH bands"));
                }
                log::info(str("render: band sweep 1..", bands, ", the --brdf-table tables' bands"));
                cmp.max_bands = bands;
            }
        } else if (a.compare) {
            log::info(str("render: no --brdf-table: the compare bakes each material's table here (",
                          cmp.grid, ", ", cmp.bake_samples, " samples per normal)"));
        }
        // The reference image is read before the render: a wrong size or a bad file was found
        // only after path tracing, and an -o naming it was not caught as an input.
        std::unique_ptr<render::ConvergenceReference> file_ref;
        if (!a.convergence_ref_image.empty()) {
            const std::filesystem::path p(a.convergence_ref_image);
            const std::string se = (p.parent_path() / (p.stem().string() + "_stderr.exr")).string();
            report.add_input(a.convergence_ref_image);
            if (std::filesystem::exists(se)) report.add_input(se);
            file_ref = std::make_unique<render::ConvergenceReference>(
                render::file_reference(*scene, a.convergence_ref_image));
        }
        // Every GLES variant is built now on tables of the baked shape, so one that does not fit
        // is refused before the render and the bakes.
        gles::SceneExportOptions gles_export;
        gles_export.set = gles_set;
        gles_export.grid = cmp.grid;
        gles_export.bake_samples = cmp.bake_samples;
        if (!gles_args.dir.empty())
            gles::check_before_work([&] { gles::check_scene_export(*scene, gles_export); });
        render::RenderResult r;
        {
            ScopedStage stage(report, "render");
            r = render::render(*scene, opt,
                               [](int spp) { log::verbose(str("render: ", spp, " spp")); });
        }
        {
            ScopedStage stage(report, "write");
            image::WriteOptions wo;
            image::write_image(a.output, r.radiance, wo);
            report.add_output(a.output, "radiance", "linear_srgb");
            image::write_image(a.stderr_output, r.std_error, wo);
            report.add_output(a.stderr_output, "radiance_std_error", "data");
        }
        auto& m = report.metrics();
        m = render::to_json(r);
        m["width_px"] = scene->camera().width_px;
        m["height_px"] = scene->camera().height_px;
        m["sampler"] = a.sampler;
        m["adaptive"] = opt.adaptive;
        log::summary("render", "path traced",
                     str(r.spp, " spp in ", log::num(r.render_time_s), " s (",
                         log::num(r.rays / std::max(r.render_time_s, 1e-9) / 1e6, 3),
                         " Mrays/s), relative noise ", log::num(r.rel_error), " (stopped: ",
                         r.stop_reason, ")"));
        if (a.convergence_ref_spp > 0 || a.convergence_ref_irradiance ||
            !a.convergence_ref_image.empty()) {
            ScopedStage stage(report, "convergence");
            std::vector<int> spps;
            for (int s = 1; s <= opt.spp; s *= 4) spps.push_back(s);
            if (spps.back() != opt.spp) spps.push_back(opt.spp);
            const render::ConvergenceReference ref =
                a.convergence_ref_irradiance ? render::irradiance_reference(*scene)
                : a.convergence_ref_image.empty()
                    ? render::render_reference(*scene, opt, a.convergence_ref_spp)
                    : std::move(*file_ref);
            const auto c = render::convergence_study(*scene, opt, ref, spps);
            m["convergence"] = render::to_json(c);
            log::summary("render", "convergence", str("error ~ spp^", log::num(c.slope, 3),
                                                      " (expected -0.5)"));
        }
        if (a.compare) {
            ScopedStage stage(report, "compare");
            std::vector<render::WrittenFile> files;
            const std::filesystem::path p(a.output);
            m["realtime"] = render::compare_realtime(*scene, r, cmp,
                                                     (p.parent_path() / p.stem()).string(), files);
            if (lighting)
                m["realtime"]["lighting_file"] = render::compare_lighting_file(
                    *scene, r, cmp, *lighting, (p.parent_path() / p.stem()).string(), files);
            for (const auto& f : files) report.add_output(f.path, f.kind, f.color_space);
            render::print_compare_summary(m["realtime"]);
            files.clear();
            const std::string prefix = (p.parent_path() / p.stem()).string();
            m["realtime"]["gles"] =
                gles::compare_scene(*scene, r, cmp, prefix, files, lighting.get());
            for (const auto& f : files) report.add_output(f.path, f.kind, f.color_space);
        }
        if (a.decompose) {
            ScopedStage stage(report, "decompose");
            render::DecomposeOptions dopt;
            dopt.max_bands = cmp.max_bands;
            // A truth of pixel centres (--no-jitter) is compared at pixel centres.
            dopt.supersample = a.no_jitter ? 1 : cmp.supersample;
            dopt.map_height = a.decompose_map_height;
            dopt.bake = render::compare_bake_options(*scene, cmp, cmp.max_bands);
            const render::RealtimeLighting pure =
                render::compare_lighting(*scene, cmp, cmp.max_bands);
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
        if (!gles_args.dir.empty()) {
            ScopedStage stage(report, "export gles");
            const auto exports = gles::export_scene(*scene, gles_export);
            for (const auto& path : gles::write_exports(gles_args.dir, exports)) {
                report.add_output(path, "gles_export");
            }
            m["gles_export"] = {{"dir", gles_args.dir}, {"variants", exports.size()}};
        }
        if (a.max_rel_error > 0 && !(r.rel_error <= a.max_rel_error)) {
            throw app::QualityGateFailed(
                str("rel_error ", r.rel_error, " > --max-rel-error ", a.max_rel_error));
        }
    });
}
