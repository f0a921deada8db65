#include "render/capture_cli.h"

#include <algorithm>

#include "core/error.h"
#include "core/fs.h"
#include "core/log.h"
#include "core/validators.h"
#include "render/weave_geometry.h"

namespace inlight::render {
namespace {

/// Reads a direction file, naming the option in the error.
template <typename Fn>
auto read_option_file(const std::string& option, const std::string& path, Fn read) {
    try {
        return read(path);
    } catch (const Error& e) {
        throw UsageError(str(option, ": ", e.what()));
    }
}

}  // namespace

void add_capture_options(CLI::App& app, CaptureArgs& a) {
    auto* cap = app.add_flag(
        "--btf-capture", a.enabled,
        "Synthetic BTF capture: the positional input is a fabric file (configs/fabrics/*.toml), "
        "-o a folder; one image per (light, view) in UBO2003 naming, one folder per view "
        "(docs/btf.md). --width-px/--height-px (default 128), --spp (default 16), --max-depth, "
        "--rr-depth, --no-jitter, --seed apply");
    app.add_option("--btf-lights", a.lights,
                   "Capture: light directions file (theta_deg phi_deg or x y z per line; default "
                   "the UBO2003 dome)")
        ->check(CLI::ExistingFile)
        ->needs(cap);
    app.add_option("--btf-views", a.views, "Capture: view directions file (default the dome)")
        ->check(CLI::ExistingFile)
        ->needs(cap);
    app.add_option("--btf-pairs", a.pairs,
                   "Capture: (light, view) pairs file (theta_l phi_l theta_v phi_v per line) "
                   "instead of every light for every view")
        ->check(CLI::ExistingFile)
        ->needs(cap)
        ->excludes("--btf-lights")
        ->excludes("--btf-views");
    app.add_option("--btf-format", a.format,
                   "Capture: png (8-bit sRGB, as Bonn ships) or exr (float, linear_srgb)")
        ->check(CLI::IsMember({"png", "exr"}))
        ->capture_default_str()
        ->needs(cap);
    app.add_option("--irradiance-w-m2", a.irradiance_w_m2,
                   "Capture: the point light's irradiance perpendicular to it; images hold "
                   "radiance, btf = image / irradiance (default pi: a white Lambertian plate lit "
                   "from the normal reads 1)")
        ->check(app::finite_range(1e-6, 1e6))
        ->needs(cap);
}

void run_capture(const CaptureArgs& a, const std::string& fabric, const std::string& out_dir,
                 const CaptureOptions& options, Report& report) {
    std::vector<CaptureJob> jobs;
    if (!a.pairs.empty()) {
        report.add_input(a.pairs);
        jobs = pair_jobs(read_option_file("--btf-pairs", a.pairs, btf::read_direction_pairs));
    } else {
        std::vector<btf::Direction> lights = btf::ubo2003_dome(), views = btf::ubo2003_dome();
        if (!a.lights.empty()) {
            report.add_input(a.lights);
            lights = read_option_file("--btf-lights", a.lights, btf::read_directions);
        }
        if (!a.views.empty()) {
            report.add_input(a.views);
            views = read_option_file("--btf-views", a.views, btf::read_directions);
        }
        jobs = full_jobs(views, lights);
    }
    double max_theta = 0;
    for (const auto& j : jobs) {
        if (!(j.view.vector().z() > 1e-9)) {
            throw UsageError(str(a.pairs.empty() ? "--btf-views" : "--btf-pairs", ": view (",
                                 j.view.theta_deg, ", ", j.view.phi_deg,
                                 ") deg lies in the sample's plane and cannot see it"));
        }
        max_theta = std::max(max_theta, j.view.theta_deg);
        for (const auto& l : j.lights) max_theta = std::max(max_theta, std::min(l.theta_deg, 89.0));
    }
    report.add_input(fabric);
    CaptureOptions opt = options;
    opt.irradiance_w_m2 = a.irradiance_w_m2;
    std::unique_ptr<CaptureScene> scene;
    {
        ScopedStage stage(report, "build fabric");
        auto weave = std::make_shared<weave::Weave>(weave::build(weave::load_weave(fabric)));
        scene = std::make_unique<CaptureScene>(std::move(weave), opt, max_theta);
    }
    CaptureWriteOptions wo;
    wo.extension = a.format;
    CaptureResult r;
    {
        ScopedStage stage(report, "capture");
        r = capture_btf(*scene, jobs, out_dir, wo, [](int done, int total) {
            log::verbose(str("capture: view ", done, " / ", total));
        });
    }
    const weave::Weave& w = scene->weave();
    nlohmann::json meta = {
        {"fabric", fabric},
        {"width_px", opt.width_px},
        {"height_px", opt.height_px},
        {"window_mm", {opt.origin_mm.x(), opt.origin_mm.y(), w.period_x_mm, w.period_y_mm}},
        {"irradiance_w_m2", opt.irradiance_w_m2},
        {"values", "reflected radiance, W sr^-1 m^-2, linear_srgb (png: sRGB-encoded, clipped "
                   "to 1); btf = value / irradiance_w_m2"},
        {"frame", "docs/conventions.md, BTF sample frame: +z normal, +x image right, +y image up"},
        {"spp", opt.spp},
        {"seed", opt.seed},
        {"max_depth", opt.max_depth},
        {"views", jobs.size()},
        {"images", r.images}};
    const std::string meta_path = out_dir + "/capture.json";
    fs::write_text_atomic(meta_path, meta.dump(2) + "\n");
    report.add_output(out_dir, "btf_folder", a.format == "png" ? "srgb" : "linear_srgb");
    report.add_output(meta_path, "btf_capture_metadata", "");
    auto& m = report.metrics();
    m["capture"] = to_json(r);
    m["capture"]["views"] = jobs.size();
    m["capture"]["width_px"] = opt.width_px;
    m["capture"]["height_px"] = opt.height_px;
    m["capture"]["spp"] = opt.spp;
    m["capture"]["segments"] = scene->segments();
    m["capture"]["margin_mm"] = scene->margin_mm();
    m["capture"]["period_mm"] = {w.period_x_mm, w.period_y_mm};
    log::info(str("capture: ", r.images, " images in ", r.wall_time_s, " s (", r.images_per_s,
                  " images/s), rel_error median ", r.rel_error_median, ", p90 ", r.rel_error_p90));
}

}  // namespace inlight::render
