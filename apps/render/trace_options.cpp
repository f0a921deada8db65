// The path tracer's options and steps shared by render trace, compare and convergence.
#include <filesystem>

#include "core/fs.h"
#include "core/log.h"
#include "core/validators.h"
#include "brdf/grid.h"
#include "image/image.h"
#include "modes.h"

namespace inlight::render_cli {

void add_size_options(CLI::App& app, int& width_px, int& height_px, const std::string& what) {
    app.add_option("--width-px", width_px, "Override the camera's width in pixels (0 = " + what)
        ->check(CLI::Range(0, 16384))
        ->capture_default_str();
    app.add_option("--height-px", height_px, "Override the camera's height in pixels (0 = " + what)
        ->check(CLI::Range(0, 16384))
        ->capture_default_str();
}

void add_path_options(CLI::App& app, render::RenderOptions& opt, bool& no_jitter) {
    app.add_option("--max-depth", opt.max_depth, "Surface interactions per path (cap)")
        ->check(CLI::Range(1, 1024))
        ->capture_default_str();
    app.add_option("--rr-depth", opt.rr_depth, "Russian roulette from this interaction on")
        ->check(CLI::Range(1, 1024))
        ->capture_default_str();
    app.add_option("--tile-px", opt.tile_px, "Tile size in pixels (unit of parallel work)")
        ->check(CLI::Range(1, 4096))
        ->capture_default_str();
    app.add_flag("--no-jitter", no_jitter, "Sample pixel centres only (no box filter)");
}

void add_trace_options(CLI::App& app, TraceArgs& a) {
    render::RenderOptions& opt = a.opt;
    app.add_option("scene", a.scene, "Scene file (.toml, see docs/render.md)")
        ->required()
        ->check(CLI::ExistingFile);
    app.add_option("-o,--output", a.output, "Radiance image (.exr, float, linear_srgb)")
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
    add_path_options(app, opt, a.no_jitter);
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
    add_size_options(app, a.width_px, a.height_px, "scene)");
    app.add_option("--max-rel-error", a.max_rel_error,
                   "Quality gate: exit 3 if the final relative noise exceeds this (0 = off)")
        ->check(app::finite_non_negative())
        ->capture_default_str();
}

void add_image_compare_options(CLI::App& app, render::CompareOptions& cmp) {
    app.add_option("--exposure", cmp.exposure,
                   "Linear scale before dE2000 and the PNG panels (0 = 0.18 / mean luminance)")
        ->check(app::finite_non_negative())
        ->capture_default_str();
    app.add_option("--heat-max-rel", cmp.heat_max_rel, "Relative error at the top of the heat map")
        ->check(app::finite_positive())
        ->capture_default_str();
}

void add_bake_options(CLI::App& app, render::CompareOptions& cmp, const std::string& prefix) {
    app.add_option("--" + prefix + "grid", cmp.grid,
                   "BRDF table grid of each material (brdf-sh-bake --grid)")
        ->check(app::parses_with([](const std::string& g) { brdf::parse_grid(g); }, "GRID"))
        ->capture_default_str();
    app.add_option("--" + prefix + "bake-samples", cmp.bake_samples,
                   "BRDF table: evaluations per normal")
        ->check(CLI::Range(16, 1 << 22))
        ->capture_default_str();
}

void prepare_trace(TraceArgs& a, uint64_t seed, Report& report) {
    a.opt.seed = seed;
    a.opt.jitter = !a.no_jitter;
    a.opt.strategy = render::strategy_from_string(a.strategy);
    a.opt.sampler = render::sampler_from_string(a.sampler);
    if (a.stderr_output.empty()) {
        const std::filesystem::path p(a.output);
        a.stderr_output = (p.parent_path() / (p.stem().string() + "_stderr.exr")).string();
    }
    image::check_writable_name(a.output, "-o");
    image::check_writable_name(a.stderr_output, "--stderr-output");
    report.add_input(a.scene);
    fs::declare_output(a.output, "-o");
    fs::declare_output(a.stderr_output, "--stderr-output");
}

std::unique_ptr<render::Scene> load_scene(const std::string& path, int width_px, int height_px,
                                          Report& report) {
    ScopedStage stage(report, "load scene");
    render::SceneDesc desc = render::load_scene_desc(path);
    if (width_px > 0) desc.camera.width_px = width_px;
    if (height_px > 0) desc.camera.height_px = height_px;
    auto scene = std::make_unique<render::Scene>(std::move(desc));
    for (const auto& f : scene->files()) report.add_input(f);
    return scene;
}

render::RenderResult trace(const render::Scene& scene, const TraceArgs& a, Report& report) {
    render::RenderResult r;
    {
        ScopedStage stage(report, "render");
        r = render::render(scene, a.opt,
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
    m["width_px"] = scene.camera().width_px;
    m["height_px"] = scene.camera().height_px;
    m["sampler"] = a.sampler;
    m["adaptive"] = a.opt.adaptive;
    log::summary("render", "path traced",
                 str(r.spp, " spp in ", log::num(r.render_time_s), " s (",
                     log::num(r.rays / std::max(r.render_time_s, 1e-9) / 1e6, 3),
                     " Mrays/s), relative noise ", log::num(r.rel_error), " (stopped: ",
                     r.stop_reason, ")"));
    return r;
}

void check_quality_gate(const TraceArgs& a, const render::RenderResult& r) {
    if (a.max_rel_error > 0 && !(r.rel_error <= a.max_rel_error)) {
        throw app::QualityGateFailed(
            str("rel_error ", r.rel_error, " > --max-rel-error ", a.max_rel_error));
    }
}

}  // namespace inlight::render_cli
