// envmap/light_fit.h: the extracted lights' parameters fitted by least squares against the
// brute-force irradiance, with the SH of the map minus the lights (docs/budget.md, "The fit").
//
// A light of flux Phi, direction d and angular radius alpha is taken as a uniform cap: its
// radiance has the SH coefficients Phi k_l(alpha) Y_lm(d) (Funk-Hecke), with
//   k_l(alpha) = (integral over [cos alpha, 1] of P_l(t) dt) / (1 - cos alpha)
//              = (P_{l-1}(cos alpha) - P_{l+1}(cos alpha)) / ((2l + 1)(1 - cos alpha)),
// k_0 = 1 and k_l -> 1 as alpha -> 0 (a point light). The model of b bands and k lights is
//   SH_b(map - lights)(n) + sum_j E_j(n) = SH_b(map)(n) + sum_j Phi_j H_b[e(n.d_j; alpha_j)],
// where e is the unit-flux light's irradiance (lights.h) and H_b removes its bands l < b:
//   H_b[e](t) = e(t) - sum_{l<b} A_l k_l(alpha) (2l + 1) / (4 pi) P_l(t).
// Its error against the reference is H_b[E_ref] - sum_j Phi_j H_b[e_j]: the lights must carry
// the part of the irradiance that b bands cannot. The fit minimises its sum of squares over a
// set of normals DISTINCT from the validation normals (so the reported error is not the fitted
// one) by Levenberg-Marquardt on (tangent offset of d, alpha, Phi_Y) per light, from the
// extracted lights; then each channel's flux by linear least squares at the fitted geometry.
// The SH written out are SH_b(map) - sum_j (cap coefficients of light j): the residual of the
// map with the fitted lights removed, to any band count (the specular term uses them too).
#pragma once

#include <Eigen/Core>
#include <functional>
#include <utility>
#include <vector>

#include "core/conventions.h"
#include "envmap/lights.h"

namespace inlight::envmap {

/// k_l(alpha) for l = 0 .. sh_bands - 1 (above).
std::vector<double> cap_zonal_factors(int sh_bands, double alpha);

/// SH coefficients (count(sh_bands) x 3) of a light's radiance as a uniform cap (above).
Eigen::MatrixXd cap_coefficients(const DirectionalLight& light, int sh_bands);

struct LightFitOptions {
    int max_iterations = 60;
    double max_radius_deg = 30;  ///< the fitted cap's radius stays in [0, this]
    /// fit_light_sets: also start k lights from the best k - 1 with one of them split in two
    /// (split_light, both axes): an extended source (a skylight, a window) may be carried
    /// better by two caps than by one and a weaker region.
    bool split_starts = false;
};

/// Radii below this split as if this wide (a point light's halves still move apart).
inline constexpr double kMinSplitRadius = 2 * kPi / 180;

/// A light split in two along a tangent axis of its direction (axis 0: d.unitOrthogonal(),
/// 1: d x that): halves of its flux, each half its radius, their centres max(alpha,
/// kMinSplitRadius) / 2 either side of d.
std::pair<DirectionalLight, DirectionalLight> split_light(const DirectionalLight& light, int axis);

struct LightFitResult {
    std::vector<DirectionalLight> lights;  ///< fitted (the fit-set description fields kept)
    Eigen::MatrixXd coeffs;                ///< count(sh_bands) x 3: SH_b(map) - sum of caps
    double rms_start = 0, rms_fitted = 0;  ///< luminance RMS of the error on the fit normals
    int iterations = 0;
};

/// Fits `start` (k >= 1 lights) for a model of `sh_bands` bands. `map_coeffs` are the map's own
/// SH (at least count(sh_bands) rows x 3), `e_ref` the brute-force irradiance (normals x 3) at
/// `normals`. Deterministic. The fitted lights never raise the fit-set RMS above the start.
LightFitResult fit_lights(const std::vector<DirectionalLight>& start, int sh_bands,
                          const Eigen::MatrixXd& map_coeffs,
                          const std::vector<Eigen::Vector3d>& normals,
                          const Eigen::MatrixXd& e_ref, const LightFitOptions& options = {});

/// Lights fitted for a model whose SH coefficients (those with A_l != 0, l < sh_bands) and
/// fluxes are free (budget.h, ShFit::kMetric): Levenberg-Marquardt over each light's direction
/// and radius, the linear unknowns solved at every step by least squares of the luminance
/// weighted by `weights` (one per normal; variable projection: the SH part is projected out
/// once, each step solves for the fluxes only). rms_start / rms_fitted are the weighted RMS;
/// `coeffs` is left empty and the fluxes are the luminance fit's (the caller fits each
/// channel). Never ends above its start. Deterministic.
LightFitResult fit_lights_free_sh(const std::vector<DirectionalLight>& start, int sh_bands,
                                  const std::vector<Eigen::Vector3d>& normals,
                                  const Eigen::MatrixXd& e_ref, const Eigen::VectorXd& weights,
                                  const LightFitOptions& options = {});

/// One light count's best fit among several starts (fit_light_sets).
struct LightSetFit {
    std::vector<DirectionalLight> lights;  ///< fitted
    Eigen::MatrixXd coeffs;                ///< count(sh_bands) x 3: SH_b(map) - sum of caps
    double rms_fitted = 0;                 ///< luminance RMS on the fit normals
    /// The value the starts were compared by: rms_fitted, or the refinement's (LightSetRefine).
    double score = 0;
    std::vector<int> regions;  ///< the indices into `regions` the lights started from, in order
    int starts = 0;            ///< starts tried for this light count
};

/// Optional refinement of every start's fit: replaces the lights and the coefficients
/// (count(sh_bands) x 3) in place and returns the value by which the starts are compared (lower
/// is better), e.g. the budget's metric after fitting the SH to it (budget.h, ShFit::kMetric).
/// Called concurrently on different starts: it must not share mutable state.
using LightSetRefine =
    std::function<double(std::vector<DirectionalLight>& lights, Eigen::MatrixXd& coeffs)>;

/// Lights for k = 1 .. max_lights (element k - 1), each the best, by the fit-set RMS (or by
/// `refine`'s value after refining every start's fit, when given), of
/// several starts fitted by fit_lights:
///   - the k strongest regions as extracted (`regions` is strongest first);
///   - the best k - 1 lights, fitted, plus any one region not among them (every region for
///     k = 1): a greedy search over the regions;
///   - with options.split_starts, the best k - 1 lights with one of them split in two (each
///     light, both axes; its region index appears twice in `regions`).
/// So the k-th light can start from a weaker region that carries what the bands leave (a
/// region's flux says how bright it is, not how much of it b bands miss), and adding a region
/// to a fitted set starts the fit next to the k - 1 optimum rather than from raw regions.
/// Starts are fitted in parallel; the result does not depend on the thread count (ties: the
/// order above, then the region's index). max_lights <= regions.size().
std::vector<LightSetFit> fit_light_sets(const std::vector<DirectionalLight>& regions,
                                        int max_lights, int sh_bands,
                                        const Eigen::MatrixXd& map_coeffs,
                                        const std::vector<Eigen::Vector3d>& normals,
                                        const Eigen::MatrixXd& e_ref,
                                        const LightFitOptions& options = {},
                                        const LightSetRefine& refine = {});

/// The fit normals: `count` Fibonacci normals turned by a fixed rotation off the validation set
/// (validate.h), so no fit normal is a validation normal.
std::vector<Eigen::Vector3d> fit_normals(int count);

}  // namespace inlight::envmap
