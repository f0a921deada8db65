// envmap-project: project environments (lat-long, cube, angular, fisheye frames) onto SH.
#include <chrono>
#include <filesystem>
#include <sstream>

#include "core/app.h"
#include "core/conventions.h"
#include "core/fs.h"
#include "core/log.h"
#include "envmap/environment.h"
#include "envmap/project.h"
#include "envmap/validate.h"
#include "sh/sh_io.h"

using namespace inlight;

namespace {

struct Args {
    std::vector<std::string> inputs;
    std::string output, input_kind = "latlong", rotate = "none", nonfinite = "reject";
    std::string window = "none", partial = "fit", directions, solid_angle;
    int sh_bands = 3, validate_normals = 128;
    double intensity = 1.0, fit_lambda = 1e-4, max_mean_rel_error = -1;
    bool validate = false;
};

std::string output_stem(const Args& a, const std::string& input) {
    const bool single_file = a.inputs.size() == 1 && fs::extension(a.output) == "json";
    if (single_file) return a.output.substr(0, a.output.size() - 5);
    return (std::filesystem::path(a.output) / std::filesystem::path(input).stem()).string() + "_sh";
}

std::string matrix_text(const Eigen::Matrix4d& m) {
    std::ostringstream os;
    os.precision(6);
    for (int i = 0; i < 4; ++i)
        os << "    [" << m(i, 0) << ", " << m(i, 1) << ", " << m(i, 2) << ", " << m(i, 3) << "]\n";
    return os.str();
}

nlohmann::json process(const Args& a, const std::string& input, Report& report) {
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

    report.add_input(input);
    envmap::InputStats stats;
    envmap::Environment env = [&] {
        ScopedStage stage(report, "load " + input);
        return envmap::load_environment(input, lo, &stats);
    }();
    if (!a.directions.empty()) report.add_input(a.directions);
    if (!a.solid_angle.empty()) report.add_input(a.solid_angle);
    if (stats.negative_values > 0)
        log::info(str(input, ": ", stats.negative_values, " negative values kept (min ",
                      stats.min_value, ")"));

    const auto t0 = std::chrono::steady_clock::now();
    envmap::ProjectResult result = [&] {
        ScopedStage stage(report, "project " + input);
        return envmap::project(env, po);
    }();
    const double project_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

    nlohmann::json m = {{"path", input},
                        {"input_kind", envmap::to_string(env.layout)},
                        {"width", env.radiance.width},
                        {"height", env.radiance.height},
                        {"method", result.method},
                        {"sh_bands", a.sh_bands},
                        {"project_time_s", project_s},
                        {"mpixel_per_s", env.radiance.pixel_count() * 1e-6 / std::max(project_s, 1e-9)},
                        {"peak_value", stats.max_value},
                        {"min_value", stats.min_value},
                        {"negative_values", stats.negative_values},
                        {"nonfinite_values_replaced", stats.nonfinite_values},
                        {"covered_solid_angle_sr", result.covered_solid_angle_sr}};
    if (result.fitted) {
        m["fit"] = nlohmann::json{{"gram_condition", result.fit.gram_condition},
                    {"regularised_condition", result.fit.regularised_condition},
                    {"weighted_residual_rms", result.fit.weighted_residual_rms},
                    {"observed_solid_angle_sr", result.fit.observed_solid_angle_sr},
                    {"lambda", a.fit_lambda}};
        log::info(str(input, ": least-squares fit over ", result.fit.observed_solid_angle_sr,
                      " sr, Gram condition ", result.fit.gram_condition));
    }

    if (a.validate) {
        ScopedStage stage(report, "validate " + input);
        const auto normals = env.full_sphere() ? envmap::validation_normals(a.validate_normals)
                                               : envmap::validation_normals(a.validate_normals, kPi / 3);
        const auto tb = std::chrono::steady_clock::now();
        const Eigen::MatrixXd ref = envmap::brute_force_irradiance(env, normals);
        const double brute_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - tb).count();
        nlohmann::json by_bands = nlohmann::json::object();
        for (int b = 1; b <= a.sh_bands; ++b) {
            const auto e = envmap::irradiance_error(
                envmap::sh_irradiance(result.coeffs_unwindowed, b, normals), ref);
            by_bands[std::to_string(b)] = nlohmann::json{{"mean_rel", e.mean_rel}, {"rms_rel", e.rms_rel},
                                           {"max_rel", e.max_rel}, {"max_abs", e.max_abs},
                                                       {"rms_over_mean", e.rms_over_mean}};
        }
        const auto final_err = envmap::irradiance_error(
            envmap::sh_irradiance(result.coeffs, a.sh_bands, normals), ref);
        m["validation"] = nlohmann::json{{"normals", normals.size()},
                           {"brute_force_time_s", brute_s},
                           {"reference_self_error", envmap::brute_force_self_error(env, normals)},
                           {"rel_floor_of_max", envmap::kRelFloor},
                           {"error_by_sh_bands", by_bands},
                           {"mean_rel", final_err.mean_rel},
                           {"max_rel", final_err.max_rel},
                           {"rms_rel", final_err.rms_rel},
                           {"rms_over_mean", final_err.rms_over_mean},
                           {"window", a.window}};
        log::info(str(input, ": irradiance error vs brute force over ", normals.size(),
                      " normals: mean ", final_err.mean_rel, ", max ", final_err.max_rel,
                      " (", a.sh_bands, " bands, window ", a.window, ")"));
    }

    sh::CoefficientSet set;
    set.sh_bands = a.sh_bands;
    set.coeffs = result.coeffs;
    set.metadata = {{"source", input}, {"input_kind", a.input_kind}, {"rotate", a.rotate},
                    {"intensity", a.intensity}, {"method", result.method}, {"window", a.window},
                    {"tool", "envmap-project"}, {"version", version_string()}};
    const std::string stem = output_stem(a, input);
    fs::write_text_atomic(stem + ".json", sh::to_json(set).dump(2) + "\n");
    sh::write_binary(stem + ".bin", set);
    report.add_output(stem + ".json", "sh_coefficients", "linear_srgb");
    report.add_output(stem + ".bin", "sh_coefficients_binary", "linear_srgb");
    if (a.sh_bands >= 3) {
        std::string text = str(input, ": irradiance matrices E(n) = (n,1)^T M (n,1)\n");
        const char* names[3] = {"r", "g", "b"};
        for (int c = 0; c < 3; ++c) {
            Eigen::VectorXd col = result.coeffs.col(c);
            text += str("  M_", names[c], " =\n", matrix_text(sh::irradiance_matrix(col.data())));
        }
        log::info(text);
    }
    return m;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App cli{"envmap-project: project HDR environments onto real spherical harmonics (R&H 2001 "
                 "convention, z up, Cycles lat-long) and report irradiance error"};
    app::CommonArgs common;
    Args a;
    cli.add_option("inputs", a.inputs, "Environment images (EXR, HDR, ...; linear_srgb)")
        ->required()->check(CLI::ExistingFile);
    cli.add_option("-o,--output", a.output,
                   "Output: X.json for one input (also writes X.bin), else a directory "
                   "receiving <stem>_sh.json and <stem>_sh.bin")->required();
    cli.add_option("--sh-bands,--bands", a.sh_bands, "SH bands (max l + 1; 3 = 9 coefficients)")
        ->check(CLI::Range(1, sh::kMaxBands))->capture_default_str();
    cli.add_option("--input-kind", a.input_kind, "Layout of the inputs")
        ->check(CLI::IsMember({"latlong", "cube", "angular", "fisheye"}))->capture_default_str();
    cli.add_option("--rotate", a.rotate, "Rotation into the z-up frame: none, y-up, or "
                   "axis=degrees list applied left to right (z=90,x=-30)")->capture_default_str();
    cli.add_option("--intensity", a.intensity, "Linear scale applied to the radiance")
        ->check(CLI::PositiveNumber)->capture_default_str();
    cli.add_option("--nonfinite", a.nonfinite, "NaN/Inf pixels: reject (error naming the pixel) "
                   "or zero (replace and count)")
        ->check(CLI::IsMember({"reject", "zero"}))->capture_default_str();
    cli.add_option("--window", a.window, "Band-limiting window (its error cost is reported by "
                   "--validate)")->check(CLI::IsMember({"none", "hann", "lanczos"}))->capture_default_str();
    cli.add_option("--partial", a.partial, "Fisheye frames: least-squares fit over observed "
                   "directions, or projection with the unseen part black")
        ->check(CLI::IsMember({"fit", "zero-fill"}))->capture_default_str();
    cli.add_option("--fit-lambda", a.fit_lambda, "Smoothness regulariser of the fit, relative "
                   "to the Gram matrix's largest eigenvalue")->check(CLI::NonNegativeNumber)->capture_default_str();
    cli.add_option("--directions", a.directions, "Fisheye: direction map EXR from calibrate "
                   "(unit vectors, device frame)")->check(CLI::ExistingFile);
    cli.add_option("--solid-angle", a.solid_angle, "Fisheye: solid-angle map EXR from "
                   "calibrate (sr per pixel)")->check(CLI::ExistingFile);
    cli.add_flag("--validate", a.validate, "Compare SH irradiance with brute-force integration "
                 "of the map, for every band count up to --sh-bands");
    cli.add_option("--validate-normals", a.validate_normals, "Fibonacci normals (+6 axes) for "
                   "--validate")->check(CLI::Range(1, 100000))->capture_default_str();
    cli.add_option("--max-mean-rel-error", a.max_mean_rel_error, "Quality gate on the validated "
                   "mean relative irradiance error (exit 3 above it; implies --validate)");
    app::setup(cli, common, "envmap-project sky.exr -o sky_sh.json --sh-bands 3 --validate "
                            "--report run.json");
    if (auto code = app::parse(cli, argc, argv)) return *code;
    if (a.max_mean_rel_error >= 0) a.validate = true;

    return app::run("envmap-project", cli, common, argc, argv, [&](Report& report) {
        nlohmann::json per_input = nlohmann::json::array();
        double worst = 0;
        for (const auto& input : a.inputs) {
            per_input.push_back(process(a, input, report));
            if (per_input.back().contains("validation"))
                worst = std::max(worst, per_input.back()["validation"]["mean_rel"].get<double>());
        }
        report.metrics()["environments"] = per_input;
        if (a.validate) report.metrics()["worst_mean_rel_error"] = worst;
        if (a.max_mean_rel_error >= 0 && worst > a.max_mean_rel_error)
            throw app::QualityGateFailed(str("mean relative irradiance error ", worst,
                                             " exceeds --max-mean-rel-error ", a.max_mean_rel_error));
    });
}
