// envmap/validate.h: irradiance of an environment by brute-force integration over its pixels,
// and the error of the SH approximation against it (the --validate of envmap-project).
#pragma once

#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "envmap/environment.h"

namespace inlight::envmap {

/// A fixed, deterministic set of unit normals: the 6 axis directions followed by a Fibonacci
/// sphere of `count` points. With `max_angle_from_z` < pi only those within that angle of +z
/// (the screen's side, for fisheye frames) are kept.
std::vector<Eigen::Vector3d> validation_normals(int count, double max_angle_from_z = 4.0);

/// Unit normals that neither the scoring set (validation_normals) nor the fit set (fit_normals)
/// contains: a Fibonacci sphere of `count` points turned by its own rotation, without the axes.
/// The held-out check of a budget's choice (budget.h) scores on these. `max_angle_from_z` as in
/// validation_normals.
std::vector<Eigen::Vector3d> holdout_normals(int count, double max_angle_from_z = 4.0);

/// E_c(n) = sum_i L_c(w_i) dw_i max(0, n . w_i) over every sample of the environment, in double,
/// deterministic for any thread count. Returns normals x 3.
Eigen::MatrixXd brute_force_irradiance(const Environment& env,
                                       const std::vector<Eigen::Vector3d>& normals);

/// The brute-force reference's own error: max over normals of |E(n) - pi| / pi when the same
/// quadrature integrates a constant unit environment (exact answer pi). Errors below this are
/// not resolved by the reference. (Full-sphere layouts only; 0 for fisheye frames.)
double brute_force_self_error(const Environment& env, const std::vector<Eigen::Vector3d>& normals);

/// Irradiance from the first count(sh_bands) rows of coeffs (zonal cosine convolution).
Eigen::MatrixXd sh_irradiance(const Eigen::MatrixXd& coeffs, int sh_bands,
                              const std::vector<Eigen::Vector3d>& normals);

/// Error of an irradiance estimate on the Rec.709 luminance of each normal's irradiance.
/// Relative errors divide by max(E_ref(n), kRelFloor * max_n E_ref(n)) so that normals facing
/// a black region do not dominate.
struct IrradianceError {
    double mean_rel = 0;
    double rms_rel = 0;
    double max_rel = 0;
    double max_abs = 0;  ///< max |E - E_ref| (luminance, W/m^2 in the map's units)
    double rms_over_mean = 0;  ///< RMS of E - E_ref over the mean of E_ref (normalised RMSE)
    /// Mean of |E - E_ref| over the mean of E_ref: the error relative to the scene's light level,
    /// which dark normals cannot inflate (mean_rel divides each normal by its own E_ref).
    double abs_over_mean = 0;
};
inline constexpr double kRelFloor = 1e-3;
IrradianceError irradiance_error(const Eigen::MatrixXd& approx, const Eigen::MatrixXd& reference);

/// The --validate block of envmap-project's report: brute force over `normals`, then the error
/// of every band count 1..sh_bands (unwindowed coefficients) and of the final coefficients,
/// the reference's own error and the timings. Keys: see docs/formats.md.
nlohmann::json validation_json(const Environment& env, const Eigen::MatrixXd& coeffs_unwindowed,
                               const Eigen::MatrixXd& coeffs_final, int sh_bands,
                               const std::vector<Eigen::Vector3d>& normals);

/// Rec.709 luminance of a linear RGB triple.
inline double luminance(double r, double g, double b) { return 0.2126 * r + 0.7152 * g + 0.0722 * b; }

}  // namespace inlight::envmap
