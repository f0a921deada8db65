// envmap-project: project environments (lat-long, cube, angular, fisheye frames) onto SH.
#include <filesystem>
#include <future>
#include <sstream>

#include "calib/response.h"
#include "core/app.h"
#include "core/conventions.h"
#include "core/fs.h"
#include "core/json_out.h"
#include "core/log.h"
#include "core/parallel.h"
#include "core/sha256.h"
#include "core/validators.h"
#include "envmap/budget_cli.h"
#include "envmap/environment.h"
#include "envmap/project.h"
#include "envmap/validate.h"
#include "sh/sh_io.h"

using namespace inlight;

namespace {

struct Args {
    std::vector<std::string> inputs;
    std::string output, input_kind = "latlong", rotate = "none", nonfinite = "reject";
    std::string window = "none", partial = "fit", directions, solid_angle, response;
    std::string latlong_precision = "float";
    int sh_bands = 3, validate_normals = 128, saturation_code = 255;
    double intensity = 1.0, fit_lambda = -1, max_mean_rel_error = -1, exposure_s = 0;
    bool validate = false;
};

std::string output_stem(const Args& a, const std::string& input) {
    if (a.inputs.size() == 1 && fs::extension(a.output) == "json")
        return a.output.substr(0, a.output.size() - 5);
    return (std::filesystem::path(a.output) / std::filesystem::path(input).stem()).string() + "_sh";
}

// An 8-bit camera frame through the response curve: radiance, and how much light clipping hides.
image::Image frame_radiance(const Args& a, const std::string& input, nlohmann::json& m,
                            image::Image& saturated) {
    const calib::ResponseCurve curve = calib::read_response(a.response);
    image::Image sa, mask;
    if (!a.solid_angle.empty()) {
        sa = image::read_image(a.solid_angle, {false});
        mask = image::Image(sa.width, sa.height, 1, image::ColorSpace::kData);
        for (size_t i = 0; i < sa.pixels.size(); ++i) mask.pixels[i] = sa.pixels[i] > 0 ? 1.f : 0.f;
    }
    const auto fr = calib::radiance_from_frame(calib::read_codes(input), curve, a.exposure_s,
                                               sa.pixels.empty() ? nullptr : &sa,
                                               sa.pixels.empty() ? nullptr : &mask, a.saturation_code);
    double clipped = 0, total = 0;
    for (size_t c = 0; c < fr.clipped_light_lower_bound.size(); ++c) {
        clipped += fr.clipped_light_lower_bound[c];
        total += fr.clipped_light_lower_bound[c] + fr.unclipped_light[c];
    }
    m["camera"] = {{"response", a.response}, {"exposure_s", a.exposure_s},
                   {"saturation_code", a.saturation_code}, {"saturated_pixels", fr.saturated_pixels},
                   {"saturated_fraction", fr.saturated_fraction},
                   {"clipped_light_lower_bound", fr.clipped_light_lower_bound},
                   {"unclipped_light", fr.unclipped_light},
                   {"clipped_light_fraction_lower_bound", total > 0 ? clipped / total : 0.0}};
    if (fr.saturated_pixels > 0)
        log::warn(str(input, ": ", fr.saturated_pixels, " saturated pixels hide at least ",
                      100 * (total > 0 ? clipped / total : 0.0), "% of the light seen"));
    saturated = fr.saturated;
    return fr.radiance;
}

// The console summary (docs/report.md, "Console summary"): what the run chose and how close it
// came, from the figures the report holds (`m` is the input's entry of metrics.environments).
void print_summary(const std::string& input, const nlohmann::json& m, bool validated) {
    const std::string tool = "envmap-project";
    const std::string name = std::filesystem::path(input).filename().string();
    const int bands = m["sh_bands"].get<int>();
    if (m.contains("budget")) {
        const nlohmann::json& b = m["budget"];
        const nlohmann::json& c = b["chosen"];
        log::summary(tool, str(name, ": --max-error ", log::num(b["max_error"].get<double>()), " (",
                               b["metric"].get<std::string>(), ")"),
                     str(b["met"].get<bool>() ? "met" : "NOT met", " with ",
                         log::count(c["sh_bands"].get<int>(), "SH band"), " + ",
                         log::count(c["lights"].get<int>(), "light"), ": error ",
                         log::num(c["error"].get<double>()), " over ",
                         log::count(b["normals"].get<int>(), "normal")));
        return;
    }
    log::summary(tool, str(name, ": projection"),
                 str(log::count(bands, "SH band"), " (", log::count(bands * bands, "coefficient"),
                     " per channel)"));
    if (validated) {
        const nlohmann::json& v = m["validation"];
        log::summary(tool, str(name, ": irradiance error vs brute force (relative)"),
                     str("mean ", log::num(v["mean_rel"].get<double>()), ", max ",
                         log::num(v["max_rel"].get<double>()), " over ",
                         log::count(v["normals"].get<int>(), "normal")));
    }
}

nlohmann::json process(const Args& a, const envmap::BudgetSetup* budget, const std::string& input,
                       Report& report) {
    envmap::LoadOptions lo;
    lo.layout = envmap::layout_from_string(a.input_kind);
    lo.rotate = a.rotate;
    lo.intensity = a.intensity;
    lo.nonfinite = a.nonfinite == "zero" ? envmap::NonFinitePolicy::kZero
                                         : envmap::NonFinitePolicy::kReject;
    lo.directions_path = a.directions;
    lo.solid_angle_path = a.solid_angle;
    envmap::ProjectOptions po;
    po.sh_bands = a.sh_bands;
    po.window = sh::window_from_string(a.window);
    po.partial = envmap::partial_method_from_string(a.partial);
    po.fit_lambda = a.fit_lambda;
    po.latlong_precision = envmap::latlong_precision_from_string(a.latlong_precision);

    nlohmann::json m = {{"path", input}, {"input_kind", a.input_kind}, {"sh_bands", a.sh_bands}};
    // The input's SHA-256 for the report is computed on its own thread while the map is read
    // and decoded: hashing is serial (~0.1 s for a 4096 x 2048 float EXR), the decode is not.
    // With --threads 1 it runs after the load, on the one thread asked for.
    auto input_sha256 = std::async(parallel::thread_count() > 1 ? std::launch::async : std::launch::deferred,
                                   [&input] { return sha256_file(input); });
    envmap::InputStats stats;
    image::Image saturated;
    envmap::Environment env = [&] {
        ScopedStage stage(report, "load " + input);
        try {
            if (a.response.empty()) return envmap::load_environment(input, lo, &stats);
            return envmap::environment_from_image(frame_radiance(a, input, m, saturated), input,
                                                  lo, &stats);
        } catch (...) {
            try {  // a failed run's report names the input too; the load's error is the one shown
                report.add_input(input, input_sha256.get());
            } catch (...) {
            }
            throw;
        }
    }();
    report.add_input(input, input_sha256.get());
    for (const auto& p : {a.directions, a.solid_angle, a.response})
        if (!p.empty()) report.add_input(p);
    envmap::ProjectResult result;
    int sh_bands = a.sh_bands;
    std::vector<envmap::DirectionalLight> lights;
    {
        ScopedStage stage(report, "project " + input);
        if (budget) {  // bands and lights from the error budget (docs/budget.md)
            envmap::BudgetOptions bo = budget->options();
            bo.project = po;
            const auto plan = envmap::plan_budget(env, bo, saturated.pixels.empty() ? nullptr : &saturated);
            result = plan.projection;
            sh_bands = plan.sh_bands;
            lights = plan.chosen_lights;
            m["budget"] = envmap::to_json(plan, bo);
            m["sh_bands"] = sh_bands;
        } else {
            result = envmap::project(env, po);
        }
        m["project_time_s"] = stage.elapsed_s();
    }
    m.update({{"width", env.radiance.width}, {"height", env.radiance.height},
              {"method", result.method}, {"latlong_precision", a.latlong_precision}, {"color_space", image::to_string(env.radiance.color_space)},
              {"mpixel_per_s", env.radiance.pixel_count() * 1e-6 / std::max(m["project_time_s"].get<double>(), 1e-9)},
              {"peak_value", stats.max_value}, {"min_value", stats.min_value},
              {"negative_values", stats.negative_values},
              {"nonfinite_values_replaced", stats.nonfinite_values},
              {"covered_solid_angle_sr", result.covered_solid_angle_sr}});
    if (result.fitted) {
        m["fit"] = {{"gram_condition", result.fit.gram_condition},
                    {"regularised_condition", result.fit.regularised_condition},
                    {"weighted_residual_rms", result.fit.weighted_residual_rms},
                    {"observed_solid_angle_sr", result.fit.observed_solid_angle_sr},
                    {"lambda", result.fit.lambda}, {"lambda_auto", result.fit_lambda_auto},
                    {"irradiance_plausible", result.fit_plausible}};
        log::info(str(input, ": least-squares fit over ", result.fit.observed_solid_angle_sr,
                      " sr, Gram condition ", result.fit.gram_condition, ", lambda ", result.fit.lambda));
    }
    if (a.validate) {
        ScopedStage stage(report, "validate " + input);
        const auto normals = envmap::validation_normals(a.validate_normals, env.full_sphere() ? 4.0 : kPi / 3);
        m["validation"] = envmap::validation_json(env, result.coeffs_unwindowed, result.coeffs,
                                                  a.sh_bands, normals);
        m["validation"]["window"] = a.window;
    }
    print_summary(input, m, a.validate);

    sh::CoefficientSet set;
    set.sh_bands = sh_bands;
    set.coeffs = result.coeffs;
    set.color_space = image::to_string(env.radiance.color_space);
    set.metadata = {{"source", input}, {"input_kind", a.input_kind}, {"rotate", a.rotate},
                    {"intensity", a.intensity}, {"method", result.method}, {"window", a.window},
                    {"tool", "envmap-project"}, {"version", version_string()}};
    nlohmann::json doc = sh::to_json(set);
    if (budget) {  // the SH above are of the map without these lights
        doc["lights"] = nlohmann::json::array();
        for (const auto& l : lights) doc["lights"].push_back(envmap::to_json(l));
    }
    const std::string stem = output_stem(a, input);
    fs::write_text_atomic(stem + ".json", dump_finite(doc, 2, stem + ".json"));
    sh::write_binary(stem + ".bin", set);
    report.add_output(stem + ".json", "sh_coefficients", set.color_space);
    report.add_output(stem + ".bin", "sh_coefficients_binary", set.color_space);
    if (sh_bands >= 3) {
        std::ostringstream os;
        os << input << ": irradiance matrices E(n) = (n,1)^T M (n,1)\n";
        for (int c = 0; c < 3; ++c) {
            Eigen::VectorXd col = result.coeffs.col(c);
            os << "  M_" << "rgb"[c] << " =\n" << sh::irradiance_matrix(col.data()) << "\n";
        }
        log::verbose(os.str());  // detail for -v: the default prints the one summary line
    }
    return m;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App cli{"envmap-project: project HDR environments onto real spherical harmonics (R&H 2001 "
                 "convention, z up, Cycles lat-long) and report irradiance error",
                 "envmap-project"};
    app::CommonArgs common;
    Args a;
    cli.add_option("inputs", a.inputs, "Environment images (EXR, HDR, ...; linear_srgb), or 8-bit "
                   "camera frames with --response")->required()->check(CLI::ExistingFile);
    cli.add_option("-o,--output", a.output, "Output: X.json for one input (also writes X.bin), "
                   "else a directory receiving <stem>_sh.json and <stem>_sh.bin")->required();
    cli.add_option("--sh-bands,--bands", a.sh_bands, "SH bands (max l + 1; 3 = 9 coefficients)")
        ->check(CLI::Range(1, sh::kMaxBands))->capture_default_str();
    cli.add_option("--input-kind", a.input_kind, "Layout of the inputs")
        ->check(CLI::IsMember({"latlong", "cube", "angular", "fisheye"}))->capture_default_str();
    cli.add_option("--rotate", a.rotate, "Rotation into the z-up frame: none, y-up, or "
                   "axis=degrees list applied left to right (z=90,x=-30)")
        ->check(app::rotation())->capture_default_str();
    cli.add_option("--intensity", a.intensity, "Linear scale applied to the radiance")
        ->check(app::finite_positive())->capture_default_str();
    cli.add_option("--nonfinite", a.nonfinite, "NaN/Inf pixels: reject (error naming the pixel) "
                   "or zero (replace and count)")->check(CLI::IsMember({"reject", "zero"}))->capture_default_str();
    cli.add_option("--window", a.window, "Band-limiting window (its error cost is reported by "
                   "--validate)")->check(CLI::IsMember({"none", "hann", "lanczos"}))->capture_default_str();
    cli.add_option("--latlong-precision", a.latlong_precision, "Lat-long row sums: float "
                   "(vectorised, each within 1.01e-6 of the sum of |terms|) or double (exact to "
                   "~1e-15, 2-5x slower)")->check(CLI::IsMember({"float", "double"}))->capture_default_str();
    cli.add_option("--partial", a.partial, "Fisheye frames: least-squares fit over observed "
                   "directions, or projection with the unseen part black")
        ->check(CLI::IsMember({"fit", "zero-fill"}))->capture_default_str();
    cli.add_option("--fit-lambda", a.fit_lambda, "Smoothness regulariser of the fit, relative to "
                   "the Gram matrix's largest eigenvalue; -1 = the smallest whose irradiance "
                   "non-negative light could produce")->check(app::finite_range_or(0, 1e6, -1))->capture_default_str();
    cli.add_option("--directions", a.directions, "Fisheye: directions.exr from calibrate (unit "
                   "vectors, device frame)")->check(CLI::ExistingFile);
    cli.add_option("--solid-angle", a.solid_angle, "Fisheye: solid_angle.exr from calibrate (sr "
                   "per pixel; 0 = unobserved)")->check(CLI::ExistingFile);
    auto* resp = cli.add_option("--response", a.response, "Camera response (calibrate response): "
                                "inputs are 8-bit frames turned into relative radiance")->check(CLI::ExistingFile);
    cli.add_option("--exposure-s", a.exposure_s, "Exposure time of the 8-bit frames, seconds")
        ->check(app::finite_positive())->needs(resp);
    resp->needs("--exposure-s");
    cli.add_option("--saturation-code", a.saturation_code, "8-bit code at and above which a pixel "
                   "counts as clipped")->check(CLI::Range(1, 255))->capture_default_str();
    envmap::BudgetArgs budget;
    envmap::add_budget_options(cli, budget);
    auto* validate = cli.add_flag("--validate", a.validate, "Compare SH irradiance with brute-force integration of "
                 "the map, for every band count up to --sh-bands");
    cli.add_option("--validate-normals", a.validate_normals, "Fibonacci normals (+6 axes) for "
                   "--validate only (the budget's are --budget-normals)")->check(CLI::Range(1, 100000))->capture_default_str();
    auto* gate = cli.add_option("--max-mean-rel-error", a.max_mean_rel_error, "Quality gate on the validated "
                   "mean relative irradiance error (exit 3 above it; implies --validate; off unless given)")
        ->check(app::finite_non_negative());
    cli.get_option("--max-error")->excludes(validate)->excludes(gate);
    app::setup(cli, common, "envmap-project sky.exr -o sky_sh.json --sh-bands 3 --validate --report run.json");
    if (auto code = app::parse(cli, argc, argv)) return *code;
    if (a.max_mean_rel_error >= 0) a.validate = true;

    return app::run("envmap-project", cli, common, argc, argv, [&](Report& report) {
        // Every input and output named before any work: no output may overwrite an input or
        // another output (two inputs with one stem into one folder).
        for (const auto& [path, flag] : {std::pair{a.directions, "--directions"},
                                         {a.solid_angle, "--solid-angle"}, {a.response, "--response"}})
            if (!path.empty()) fs::declare_input(path, flag);
        for (const auto& input : a.inputs) fs::declare_input(input, "input");
        for (const auto& input : a.inputs)
            for (const char* ext : {".json", ".bin"})
                fs::declare_output(output_stem(a, input) + ext, str("-o, for ", input));
        nlohmann::json per_input = nlohmann::json::array();
        double worst = 0;
        int unmet = 0;
        std::unique_ptr<envmap::BudgetSetup> setup;  // reads --brdf-table and --material first
        if (budget.enabled()) setup = std::make_unique<envmap::BudgetSetup>(budget);
        for (const auto& input : a.inputs) {
            per_input.push_back(process(a, setup.get(), input, report));
            if (a.validate) worst = std::max(worst, per_input.back()["validation"]["mean_rel"].get<double>());
            if (budget.enabled()) unmet += per_input.back()["budget"]["met"].get<bool>() ? 0 : 1;
        }
        report.metrics()["environments"] = per_input;
        if (a.validate) report.metrics()["worst_mean_rel_error"] = worst;
        if (unmet > 0)
            throw app::QualityGateFailed(str(unmet, " input(s) miss the --max-error budget of ",
                                             budget.max_error, " (outputs hold the least error)"));
        if (a.max_mean_rel_error >= 0 && worst > a.max_mean_rel_error)
            throw app::QualityGateFailed(str("mean relative irradiance error ", worst,
                                             " exceeds --max-mean-rel-error ", a.max_mean_rel_error));
    });
}
