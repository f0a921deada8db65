// brdf/bake.h: projection of a cosine-weighted BRDF lobe into SH at each normal of a grid
// (brdf-sh-bake), the integrators, and the error of a bake against a converged reference.
//
// What is projected (the inlight report, section 2.4.1, made precise): for a grid normal n and
// the fixed view v (device frame),
//   B_lm(n) = integral over the sphere of f_r(n; v, w) max(0, n.w) Y_lm(w) dw,
// with f_r = eval_baked_lobe() (the specular/sheen lobe; the Lambert lobe only for the kLambert
// model) evaluated in n's local frame (world_from_local(n), Duff et al. 2017), and Y_lm real SH
// in the DEVICE frame (sh/sh.h), so that sum_lm L_lm B_lm(n) is the reflected radiance toward
// v for lighting coefficients L_lm projected in the device frame. B = 0 where n.v < 0 (the
// viewer sees the back of the facet); at |n.v| < kEdgeOnCos (normals exactly edge-on, such as
// the horizon row of thetaphi under the default view) B is the limit n.v -> 0+, computed
// exactly from the lobe's edge-on limit (brdf.h) except for Charlie (see kCharlieEdgeOnCos).
//
// Integrators (per normal; all sums in double, in a fixed order):
//  - stratified-mc: the report's Snippet 1: sqrt(N) x sqrt(N) jittered strata uniform over the
//    whole sphere (theta = 2 acos(sqrt(1 - p)), phi = 2 pi q), weight 4 pi / N.
//  - gauss-legendre: a product rule in the lobe's own variables: Gauss-Legendre in u x uniform
//    phi, mapped through the inverse CDF of the lobe's D(h)(n.h) (half-vector h, local frame;
//    Jacobian 4 (wo.h)); for Lambert, Gauss-Legendre in cos(theta_i) x uniform phi (exact for
//    the polynomial integrand). n = max(1, round(sqrt(samples / 2))) x 2n nodes. For the
//    report's model the lines and the phi halves are split at the kinks of its V-cavity G's
//    min() (docs/brdf.md), so each piece's integrand is smooth; the node count is then ~n x 2n.
//  - sobol-is: the first N points of the 2-D Sobol sequence with a random digital shift per
//    normal, through sample_baked_lobe() (GGX: visible normals, Heitz 2018).
// Random numbers derive from (seed, the normal's quantised coordinates) only: identical output
// for any thread count, and identical nodes (the thetaphi pole row, the report grid's folded
// duplicates) get identical coefficients.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "brdf/brdf.h"
#include "brdf/grid.h"
#include "brdf/table.h"

namespace inlight::brdf {

/// Largest band count a table holds (8 bands = 64 coefficients).
inline constexpr int kMaxBakeBands = 8;

enum class Integrator { kStratifiedMc, kGaussLegendre, kSobolIs };
/// "stratified-mc" | "gauss-legendre" | "sobol-is".
std::string to_string(Integrator integrator);
/// Inverse of to_string; throws UsageError.
Integrator integrator_from_string(const std::string& name);

/// Options of bake() and project_normal().
struct BakeOptions {
    int sh_bands = 3;  ///< 1 .. kMaxBakeBands (checked by bake())
    Integrator integrator = Integrator::kGaussLegendre;
    int samples = 4096;             ///< integrand evaluations per normal (see the file comment)
    Eigen::Vector3d view{0, 0, 1};  ///< toward the viewer, device frame, unit length
    uint64_t seed = 1;
};

/// Parses a view: "x,y,z" (finite, non-zero, z >= 0: in front of the screen or grazing) -> unit
/// vector. Throws UsageError naming the view otherwise.
Eigen::Vector3d parse_view(const std::string& xyz);
/// Parses "THETA[,PHI]" in degrees (PHI defaults to 0; THETA in [0, 90], PHI in [-360, 360],
/// finite) -> view_from_deg. Throws UsageError naming the view otherwise.
Eigen::Vector3d parse_view_deg(const std::string& theta_phi_deg);
/// View at polar angle theta_deg from +z toward azimuth phi_deg (from +x toward +y).
Eigen::Vector3d view_from_deg(double theta_deg, double phi_deg);

/// |n.v| below this makes a facet edge-on (the horizon row of thetaphi or report5x5 under the
/// default view): B is then the limit n.v -> 0+ from the visible side, not the 0 of a
/// back-facing facet, so interpolation toward the horizon stays continuous.
inline constexpr double kEdgeOnCos = 1e-7;
/// The n.v that stands in for n.v -> 0 for Charlie, whose lobe has no finite edge-on limit
/// (brdf.h); its B there grows like 1 / n.v, so this value is a choice, not a limit.
inline constexpr double kCharlieEdgeOnCos = 1e-6;

/// The view in a facet's local frame (world_from_local(n), Duff et al. 2017).
struct FacetView {
    Eigen::Vector3d wo = Eigen::Vector3d::UnitZ();  ///< unit; wo.z < 0: back-facing (B = 0)
    bool edge_on = false;  ///< wo.z = 0 and the lobe is its exact edge-on limit (brdf.h)
    /// True unless the facet faces away from the viewer.
    bool visible() const { return edge_on || wo.z() > 0; }
    /// f_r(wo, wi) wi.z of the baked lobe (1/sr per channel), or its edge-on limit.
    Eigen::Vector3d lobe_cos(const Material& material, const Eigen::Vector3d& wi) const;
};
/// The facet view of normal n for device-frame view `view`: |n.v| < kEdgeOnCos is edge-on
/// (the exact limit where baked_lobe_has_edge_on_limit(), else wo.z = kCharlieEdgeOnCos).
/// Precondition: n and view unit length.
FacetView facet_view(const Material& material, const Eigen::Vector3d& n,
                     const Eigen::Vector3d& view);

/// B_lm(n) for one normal: 3 (linear_srgb channels) x count(sh_bands), double.
/// Precondition: n unit length (checked in Debug), 1 <= sh_bands <= sh::kMaxBands.
Eigen::MatrixXd project_normal(const Material& material, const Eigen::Vector3d& n,
                               const BakeOptions& options);

/// Bakes the table (parallel over nodes, deterministic). channels = 1 when
/// baked_lobe_is_achromatic(material), else 3. Throws UsageError on bad options.
Table bake(const Material& material, const Grid& grid, const BakeOptions& options);

/// An analytic test environment (device frame), radiance per direction (achromatic).
struct TestLighting {
    std::string name;
    std::function<double(const Eigen::Vector3d&)> radiance;
    Eigen::Vector3d peak = Eigen::Vector3d::Zero();  ///< unit direction of a peak, or zero
};
/// The fixed set used for radiance errors: "uniform" (1), "front_gradient" (1 + w.z),
/// "key_vmf10" (exp(10 (mu.w - 1)), mu at theta 35 deg toward +y) and "window_vmf50"
/// (exp(50 (mu.w - 1)), mu at theta 50 deg, phi -20 deg).
std::vector<TestLighting> test_lightings();
/// Their SH coefficients, count(sh_bands) per lighting, by a 128 x 256 product rule (error
/// < 1e-12 for these smooth functions up to 8 bands).
std::vector<Eigen::VectorXd> test_lighting_coeffs(int sh_bands);

/// Options of validate().
struct ValidateOptions {
    /// Reference: adaptive cubature (brdf/cubature.h) at each checked grid node to this error
    /// estimate relative to that node's largest coefficient (8 bands), within this many
    /// evaluations; the estimate is pessimistic (the embedded degree-5 rule's error), so
    /// integration errors down to about this size are resolved.
    double reference_rel_tol = 1e-7;
    int64_t reference_max_evals = 400'000;
    /// The same at the off-grid normals and the other nodes their lookup reads, which serve
    /// the interpolation, truncation and total errors (1e-4 and larger for useful grids).
    double off_grid_rel_tol = 1e-5;
    int max_nodes = 64;     ///< grid nodes checked (evenly strided); 0 = all
    int test_normals = 64;  ///< off-grid normals (spherical Fibonacci inside the grid)
};

/// Errors of a bake (see docs/brdf.md). "rel" errors of radiance are relative to the largest
/// exact radiance of that lighting over the normals checked; all are maxima over lightings,
/// channels and normals unless named rms.
struct Validation {
    // Integration: baked coefficients vs the reference at grid nodes (same bands).
    double integration_coeff_max_abs = 0;
    double integration_coeff_rms = 0;
    double integration_coeff_max_rel = 0;  ///< max abs / largest |reference coefficient|
    double integration_radiance_max_rel = 0;
    // Interpolation: lookup in a table of reference coefficients vs the reference bake at
    // off-grid normals (same bands): the grid's own error.
    double interpolation_coeff_max_abs = 0;
    double interpolation_radiance_max_rel = 0;
    // Truncation: reference SH product at sh_bands vs the exact integral of L f cos.
    double truncation_radiance_max_rel = 0;
    std::vector<double> truncation_radiance_max_rel_by_bands;  ///< [b-1] for b = 1 .. 8
    // Total: lookup in the baked table vs the exact integral at off-grid normals.
    double total_radiance_max_rel = 0;
    // The reference's own error estimate (cubature), max over normals, relative to the
    // largest reference coefficient: what the errors above can resolve.
    double reference_error_max_rel = 0;
    int64_t reference_evals = 0;  ///< integrand evaluations of the whole reference
    int nodes_checked = 0;
    int test_normals = 0;
    nlohmann::json per_lighting = nlohmann::json::object();
    double time_s = 0;
    nlohmann::json to_json() const;
};

/// The checked nodes' reference tolerance that resolves a bake's integration error at a fraction
/// of the cost: ValidateOptions{}.reference_rel_tol for gauss-legendre; for the Monte Carlo
/// integrators, whose relative error is of order 1/sqrt(samples), max(that, 0.01 /
/// sqrt(samples)): about 1% of their standard error.
double reference_rel_tol_for(const BakeOptions& options);

/// The reference at one normal: kMaxBakeBands coefficients and the exact radiance.
struct ReferenceNormal {
    Eigen::MatrixXd coeffs;  ///< 3 x count(kMaxBakeBands)
    Eigen::MatrixXd exact;   ///< 3 x test lightings: integral of L f cos over the sphere
    double error = 0;        ///< the cubature's error estimate (absolute, max component)
    int64_t evals = 0;       ///< integrand evaluations
    bool converged = true;   ///< false if the evaluation budget ran out first
};
/// The reference at one normal by hemisphere_cubature() of f_r cos Y_lm and L f_r cos
/// (FacetView::lobe_cos, so edge-on normals take the same limit as the bake), with the
/// mirror direction of the view and the test lightings' peaks as initial breaks.
ReferenceNormal reference_normal(const Material& material, const Eigen::Vector3d& n,
                                 const Eigen::Vector3d& view, const ValidateOptions& vopt = {});

/// The converged reference at the grid nodes and off-grid normals validate() checks (the
/// expensive part, independent of the bake being checked, so one set serves every band count).
struct ReferenceSet {
    Grid grid;
    std::vector<int> nodes;                  ///< flat indices of the checked nodes
    std::vector<Eigen::Vector3d> normals;    ///< off-grid test normals
    std::map<int, ReferenceNormal> at_node;  ///< checked nodes and the corners of each normal
    std::vector<ReferenceNormal> at_normal;  ///< per test normal
    double error_max_rel = 0;  ///< max cubature error at checked nodes / largest coefficient
    int64_t evals = 0;         ///< integrand evaluations, all normals
    double time_s = 0;
};

/// Computes the reference (parallel, deterministic) for view `view`.
ReferenceSet make_reference(const Material& material, const Grid& grid, const Eigen::Vector3d& view,
                            const ValidateOptions& vopt = {});

/// Truncation error of the reference for b = 1 .. kMaxBakeBands bands (index b - 1).
std::vector<double> truncation_by_bands(const ReferenceSet& reference);

/// Compares `baked` (same grid and view as the reference) with the reference.
Validation validate(const ReferenceSet& reference, const Table& baked);

/// make_reference + validate.
Validation validate(const Material& material, const Table& baked, const BakeOptions& options,
                    const ValidateOptions& vopt = {});

/// The smallest band count b in [1, kMaxBakeBands] whose truncation error meets max_error, or
/// 0 if none does.
int choose_bands(const std::vector<double>& truncation_by_bands, double max_error);
int choose_bands(const Validation& validation, double max_error);

/// The SH spectrum of the lobe at one normal: fraction of the lobe's energy
/// integral (f cos)^2 dw (Parseval) captured by the first b bands, for b = 1 .. max_bands.
/// Uses the gauss-legendre rule with n x 2n nodes (n = gl_n).
std::vector<double> lobe_energy_captured(const Material& material, const Eigen::Vector3d& n,
                                         const Eigen::Vector3d& view, int max_bands,
                                         int gl_n = 256);

/// Smallest b with sqrt(1 - captured(b)) <= rel_l2_error (the relative L2 error of the lobe
/// reconstructed from b bands), or 0 if max_bands is not enough.
int bands_for_lobe_error(const std::vector<double>& captured, double rel_l2_error);

}  // namespace inlight::brdf
