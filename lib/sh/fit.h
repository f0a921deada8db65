// sh/fit.h: SH coefficients from sets of directional samples: quadrature projection over the
// whole sphere, and a weighted, regularised least-squares fit for partial-sphere data (a front
// camera sees ~165 degrees; projecting would treat the unseen directions as black).
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "sh/sh.h"

namespace inlight::sh {

/// Directional samples: the i-th has a unit direction, a weight (its solid angle, sr) and
/// channels() values (radiance). Implementations must be safe to call concurrently.
class SampleSet {
  public:
    virtual ~SampleSet() = default;
    virtual int64_t size() const = 0;
    virtual int channels() const = 0;
    /// Fills the i-th sample; returns false when it is not observed (masked out).
    virtual bool sample(int64_t i, Eigen::Vector3d& dir, double& weight_sr,
                        double* values) const = 0;
};

/// Quadrature projection c_k = sum_i w_i f_i Y_k(w_i), count(sh_bands) x channels, accumulated
/// in double in fixed chunks (bit-identical for any thread count). Directions the set does not
/// cover contribute nothing (i.e. are taken as black).
Eigen::MatrixXd project(int sh_bands, const SampleSet& samples);

/// Options of fit_least_squares().
struct FitOptions {
    /// Tikhonov weight of the smoothness penalty sum_k (l_k (l_k + 1))^2 c_k^2, relative to the
    /// largest eigenvalue of the Gram matrix (which is 1 for full-sphere data). 0 = unregularised.
    double lambda = 1e-4;
};

/// Result of fit_least_squares().
struct FitResult {
    Eigen::MatrixXd coeffs;            ///< count(sh_bands) x channels
    double observed_solid_angle_sr = 0;  ///< sum of the weights of observed samples
    double gram_condition = 0;         ///< eigenvalue ratio max/min of the Gram matrix
    double regularised_condition = 0;  ///< the same after adding the penalty
    double weighted_residual_rms = 0;  ///< sqrt(sum w (Yc - f)^2 / sum w), mean over channels
    int64_t samples_used = 0;
    double lambda = 0;                 ///< the regularisation weight used
};

/// The same fit for several regularisation weights from one pass over the samples (the normal
/// equations are accumulated once). An entry whose system is singular has coeffs empty.
std::vector<FitResult> fit_least_squares_path(int sh_bands, const SampleSet& samples,
                                              const std::vector<double>& lambdas);

/// Minimises sum_i w_i (Y(w_i)^T c - f_i)^2 + lambda' sum_k (l_k(l_k+1))^2 c_k^2 over the
/// observed samples (normal equations solved by a symmetric eigen-decomposition, in double).
/// Throws Error if no sample is observed or the system is singular with lambda = 0.
FitResult fit_least_squares(int sh_bands, const SampleSet& samples, const FitOptions& options = {});

}  // namespace inlight::sh
