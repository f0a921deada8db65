// brdf/cubature.h: adaptive cubature over a rectangle and over the hemisphere in plain
// (theta, phi), the independent reference that the bake's warped Gauss-Legendre rule is judged
// against (validate(), the tests). It shares nothing with that rule: no warp, no half-vector
// parametrisation, no Gauss-Legendre nodes; only the integrand.
//
// Genz and Malik 1980, "An adaptive algorithm for numerical integration over an n-dimensional
// rectangular region", J. Comput. Appl. Math. 6(4), 295-302: the 17-point degree-7 rule in two
// dimensions with its embedded degree-5 rule (their difference is the error estimate of a box)
// and the fourth divided difference that picks the axis to halve. Globally adaptive: the box
// with the largest error estimate is halved until the summed estimate meets the tolerance
// (Berntsen, Espelid and Genz 1991, "An adaptive algorithm for the approximate calculation of
// multiple integrals", ACM TOMS 17(4)).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <vector>

namespace inlight::brdf {

/// Stopping rule of the cubature.
struct CubatureOptions {
    /// Stop when the summed error estimate <= max(abs_tol, rel_tol * max |I_k|) over the first
    /// scale_count components k (all components when scale_count <= 0).
    double rel_tol = 1e-10;
    double abs_tol = 0;
    int scale_count = 0;
    /// Stop here anyway (then converged = false); rounded up to whole boxes of 17 evaluations.
    /// Memory: 8 * dim bytes per box, about max_evals / 34 boxes.
    int64_t max_evals = 500'000;
};

/// Result of a cubature: per-component integrals and the error estimate.
struct CubatureResult {
    Eigen::VectorXd integral;  ///< one value per component
    /// Sum over the final boxes of max over components |degree-7 - degree-5 estimate|: the
    /// error bound of the degree-5 rule, so a pessimistic estimate for the degree-7 values
    /// returned.
    double error = 0;
    int64_t evals = 0;
    bool converged = false;
};

/// f(x, out) writes `dim` values at the point x.
using CubatureIntegrand = std::function<void(const Eigen::Vector2d& x, double* out)>;

/// Integral of f over the rectangle [x_breaks.front(), x_breaks.back()] x [y_breaks.front(),
/// y_breaks.back()], the breaks (ascending, at least two per axis) giving the initial boxes.
/// Deterministic (serial, fixed order). Precondition: dim >= 1 (checked).
CubatureResult cubature_2d(const CubatureIntegrand& f, int dim, const std::vector<double>& x_breaks,
                           const std::vector<double>& y_breaks, const CubatureOptions& options);

/// f(w, out) writes `dim` values for a unit direction w (local frame, w.z >= 0).
using HemisphereIntegrand = std::function<void(const Eigen::Vector3d& w, double* out)>;

/// Integral of f(w) dw over the upper hemisphere w.z >= 0 of the local frame, as the integral of
/// f sin(theta) over theta in [0, pi/2] x phi in [phi_0, phi_0 + 2 pi] (phi_0 is the azimuth of
/// the first feature, or 0). The initial boxes are 4 x 8 equal ones with the polar angles and
/// azimuths of `features` added as breaks, so a peak at a feature lies on box corners and edges
/// the first rule sees (put a peaked lobe's peak there).
CubatureResult hemisphere_cubature(const HemisphereIntegrand& f, int dim,
                                   const std::vector<Eigen::Vector3d>& features,
                                   const CubatureOptions& options);

/// The same integral for a lobe whose peak or integrable singularity sits on the horizon at the
/// horizontal unit vector `axis` (an edge-on facet: the mirror direction of its view). Polar
/// coordinates about `axis`: w = cos(t) axis + sin(t) (cos(p) z + sin(p) (axis x z)), t in [0,
/// pi], p in [-pi/2, pi/2] (w.z = sin(t) cos(p) >= 0), weight sin(t): a 1/|w - axis|
/// singularity becomes bounded and the horizon is the edge p = +-pi/2, not a curve inside.
/// Precondition: |axis.z| < 1e-7 and |axis| = 1 (checked).
CubatureResult hemisphere_cubature_about_horizon(const HemisphereIntegrand& f, int dim,
                                                 const Eigen::Vector3d& axis,
                                                 const CubatureOptions& options);

}  // namespace inlight::brdf
