// render convergence: the path-traced image, and its error against samples per pixel measured
// against a reference (docs/render.md "Convergence").
#include <filesystem>
#include <memory>

#include "core/log.h"
#include "render/reference.h"
#include "modes.h"

namespace inlight::render_cli {
namespace {

struct ConvergenceArgs {
    TraceArgs trace;
    int ref_spp = 0;
    std::string ref_image;
    bool ref_irradiance = false;
};

}  // namespace

ModeBody add_convergence(CLI::App& app, const app::CommonArgs& common) {
    auto a = std::make_shared<ConvergenceArgs>();
    add_trace_options(app, a->trace);
    auto* spp = app.add_option("--ref-spp", a->ref_spp,
                               "Reference: a render with this many spp; snapshots at 1, 4, 16, "
                               "... up to --spp; the slope goes into the report")
                    ->check(CLI::Range(1, 1 << 20));
    auto* image = app.add_option("--ref-image", a->ref_image,
                                 "Reference: this EXR (a converged render; its _stderr.exr is "
                                 "used when present)")
                      ->check(CLI::ExistingFile)
                      ->excludes(spp);
    app.add_flag("--ref-irradiance", a->ref_irradiance,
                 "Reference: the exact image of a Lambert sphere from brute-force irradiance "
                 "(needs --no-jitter)")
        ->excludes(spp)
        ->excludes(image);
    return [a, &common](Report& report) {
        if (a->ref_spp == 0 && a->ref_image.empty() && !a->ref_irradiance)
            throw UsageError("convergence needs a reference: --ref-spp N, --ref-image EXR or "
                             "--ref-irradiance");
        if (a->ref_irradiance && !a->trace.no_jitter)
            throw UsageError("--ref-irradiance needs --no-jitter (the brute force gives each "
                             "pixel centre's value)");
        TraceArgs& t = a->trace;
        prepare_trace(t, common.seed, report);
        const auto scene = load_scene(t.scene, t.width_px, t.height_px, report);
        // The reference image is read before the render: a wrong size or a bad file was found
        // only after path tracing, and an -o naming it was not caught as an input.
        std::unique_ptr<render::ConvergenceReference> file_ref;
        if (!a->ref_image.empty()) {
            const std::filesystem::path p(a->ref_image);
            const std::string se = (p.parent_path() / (p.stem().string() + "_stderr.exr")).string();
            report.add_input(a->ref_image);
            if (std::filesystem::exists(se)) report.add_input(se);
            file_ref = std::make_unique<render::ConvergenceReference>(
                render::file_reference(*scene, a->ref_image));
        }
        const render::RenderResult r = trace(*scene, t, report);
        {
            ScopedStage stage(report, "convergence");
            std::vector<int> spps;
            for (int s = 1; s <= t.opt.spp; s *= 4) spps.push_back(s);
            if (spps.back() != t.opt.spp) spps.push_back(t.opt.spp);
            const render::ConvergenceReference ref =
                a->ref_irradiance    ? render::irradiance_reference(*scene)
                : a->ref_image.empty() ? render::render_reference(*scene, t.opt, a->ref_spp)
                                       : std::move(*file_ref);
            const auto c = render::convergence_study(*scene, t.opt, ref, spps);
            report.metrics()["convergence"] = render::to_json(c);
            log::summary("render", "convergence",
                         str("error ~ spp^", log::num(c.slope, 3), " (expected -0.5)"));
        }
        check_quality_gate(t, r);
    };
}

}  // namespace inlight::render_cli
