// render/sampling.h: random numbers that depend only on (seed, pixel, sample), piecewise-constant
// 1D/2D distributions, and the chi-square statistics used by the sampling tests.
//
// References: O'Neill 2014, "PCG: A Family of Simple Fast Space-Efficient Statistically Good
// Algorithms for Random Number Generation" (PCG32, XSH-RR output); Steele et al. 2014 (SplitMix64
// finaliser, used to hash the counters); Pharr, Jakob and Humphreys, "Physically Based Rendering"
// 3rd ed., sec. 13.6.5 / 14.2.4 (piecewise-constant 2D sampling); Press et al., "Numerical
// Recipes" 3rd ed., sec. 6.2 (incomplete gamma function for the chi-square tail).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "core/bits.h"

namespace inlight::render {

/// SplitMix64 finaliser: a bijective 64-bit mix (one definition, in core/bits.h).
using bits::mix64;

/// PCG32 whose state and stream are derived from hashed counters, so every (seed, pixel, sample)
/// path has its own independent stream and results do not depend on which thread runs it.
class Rng {
  public:
    Rng(uint64_t seed, uint64_t pixel, uint64_t sample);
    /// A placeholder that costs nothing (stream 0 of seed 0; not meant to be drawn from).
    Rng() : m_state(0), m_inc(1) {}
    uint32_t next_u32();
    /// Uniform in [0, 1) with 32 random bits (never returns 1).
    double uniform() { return next_u32() * 0x1p-32; }
    Eigen::Vector2d uniform2() {
        const double a = uniform();
        return {a, uniform()};
    }

  private:
    uint64_t m_state;
    uint64_t m_inc;
};

/// Piecewise-constant distribution over n bins with non-negative weights.
class Distribution1D {
  public:
    Distribution1D() = default;
    /// Precondition: weights finite and >= 0 (checked). A zero total gives an empty
    /// distribution (total() == 0) that must not be sampled.
    explicit Distribution1D(std::vector<double> weights);

    /// Picks bin i with probability pmf(i) (bins of zero weight are never picked) and returns
    /// the position of u inside that bin's CDF interval, remapped to [0, 1).
    /// Precondition: total() > 0, u in [0, 1).
    int sample(double u, double* u_remapped = nullptr) const;
    double pmf(int i) const {
        return m_total > 0 ? m_weights[static_cast<size_t>(i)] / m_total : 0;
    }
    double total() const { return m_total; }
    int size() const { return static_cast<int>(m_weights.size()); }

  private:
    std::vector<double> m_weights;
    std::vector<double> m_cdf;  ///< size n + 1, m_cdf[0] = 0, m_cdf[n] = 1
    double m_total = 0;
};

/// Piecewise-constant distribution over a rows x cols grid: a marginal over rows and one
/// conditional over columns per row.
class Distribution2D {
  public:
    Distribution2D() = default;
    /// weights: row-major rows x cols, finite and >= 0 (checked).
    Distribution2D(const std::vector<double>& weights, int cols, int rows);

    /// Picks a cell (col, row) with probability pmf(col, row); `u_in_cell` receives the two
    /// remapped uniforms (column, row) for placing the sample inside the cell.
    /// Precondition: total() > 0.
    void sample(const Eigen::Vector2d& u, int* col, int* row, Eigen::Vector2d* u_in_cell) const;
    double pmf(int col, int row) const;
    double total() const { return m_rows.total(); }
    int cols() const { return m_cols; }
    int rows() const { return m_rows.size(); }

  private:
    int m_cols = 0;
    Distribution1D m_rows;
    std::vector<Distribution1D> m_cond;
};

/// Cosine-weighted direction on the +z hemisphere (Malley), pdf = z / pi.
Eigen::Vector3d sample_cosine_hemisphere(const Eigen::Vector2d& u);
/// Uniform direction on the unit sphere, pdf = 1 / (4 pi).
Eigen::Vector3d sample_uniform_sphere(const Eigen::Vector2d& u);

/// Regularised upper incomplete gamma Q(a, x) = Gamma(a, x) / Gamma(a), a > 0, x >= 0.
double gamma_q(double a, double x);
/// P(X > x) for X chi-square distributed with `dof` degrees of freedom.
double chi2_survival(double x, int dof);

/// Result of a Pearson chi-square goodness-of-fit test.
struct Chi2Result {
    double statistic = 0;
    int dof = 0;
    double p_value = 1;
    int pooled_bins = 0;  ///< bins with expected < min_expected, merged into one
};
/// Pearson test of observed counts against expected counts (same total). Bins whose expected
/// count is below min_expected are pooled into one bin (pbrt-v4 bsdfs_test.cpp does the same);
/// observations in a bin of zero expectation give p = 0.
Chi2Result chi2_test(const std::vector<double>& observed, const std::vector<double>& expected,
                     double min_expected = 5.0);

}  // namespace inlight::render
