// envmap/project.h: SH coefficients of an environment. Full-sphere layouts are projected by
// quadrature over their exact pixel solid angles (lat-long by a separable row/column scheme);
// partial-sphere input (a fisheye frame) is fitted by regularised weighted least squares, or
// projected with the unseen part black when asked.
#pragma once

#include <string>

#include <Eigen/Core>

#include "envmap/environment.h"
#include "sh/fit.h"
#include "sh/sh.h"

namespace inlight::envmap {

/// How to obtain coefficients for partial-sphere input.
enum class PartialMethod {
    kFit,       ///< weighted regularised least squares over the observed directions (default)
    kZeroFill,  ///< projection that treats unobserved directions as black
};
/// "fit" | "zero-fill"; throws UsageError otherwise.
PartialMethod partial_method_from_string(const std::string& name);

/// Precision of project_latlong's row sums (per row, sum over columns of pixel x weight, the
/// weight being the exact azimuthal integral of cos(m phi) or sin(m phi) over the pixel):
/// kFloatRowSums (the default, up to kMaxFloatBands bands) sums in float over blocks of
/// kFloatBlock columns, vectorised, and adds the block sums in double: every row sum is within
/// kFloatRowSumBound of sum_c |pixel| |weight| (measured: <= 1e-6 of the largest coefficient on
/// HDR maps, `ProjectLatLong.FloatRowSums*`). kDouble sums everything in double (the reference,
/// exact to ~1e-15; used above kMaxFloatBands).
enum class LatlongPrecision { kFloatRowSums, kDouble };
constexpr int kMaxFloatBands = 8;
/// Columns summed in float before a block sum is added in double.
constexpr int kFloatBlock = 16;
/// Relative bound on a float row sum: gamma_B (1 + u) + u with u = 2^-24 and B = kFloatBlock,
/// i.e. a length-B float inner product (Higham 2002, eq. 3.5: gamma_B = B u / (1 - B u)) of
/// weights that were rounded to float (u), ~1.01e-6. It bounds the coefficients by linearity:
/// |L_lm(float) - L_lm| <= kFloatRowSumBound * sum over pixels |pixel| |row factor_lm| |weight_m|,
/// which for non-negative maps is <= kFloatRowSumBound sqrt(2l + 1) L_00 (|Y_lm| <= sqrt(2l + 1)
/// Y_00 pointwise), and equal to kFloatRowSumBound L_00 for L_00 itself. The double arithmetic
/// around it adds ~1e-15 relative.
constexpr double kFloatRowSumBound =
    kFloatBlock * 0x1p-24 / (1.0 - kFloatBlock * 0x1p-24) * (1.0 + 0x1p-24) + 0x1p-24;

/// Instruction set of the float row sums. kBest: AVX2 + FMA where the CPU has them (x86-64,
/// GCC/Clang, checked at run time), else the baseline; kBaseline: the code compiled for the
/// build's baseline target (SSE2 on x86-64) on every CPU, the fallback of CPUs without AVX2.
/// Both are within kFloatRowSumBound; their sums differ in rounding only (FMA rounds once per
/// term). kBaseline exists so that tests and benchmarks can run the fallback on an AVX2 CPU.
enum class FloatRowSumIsa { kBest, kBaseline };
/// True when kBest runs the AVX2 + FMA code on this CPU.
bool float_row_sums_use_avx2();

struct ProjectOptions {
    int sh_bands = 3;                       ///< max l + 1, 1..sh::kMaxBands
    sh::Window window = sh::Window::kNone;  ///< optional band-limiting window (off by default)
    PartialMethod partial = PartialMethod::kFit;
    /// Regularisation of the fit (see sh::FitOptions::lambda); negative = automatic: the
    /// smallest weight on a fixed ladder (0, 1e-6 ... 10) whose fitted lighting is physically
    /// possible, i.e. has irradiance E(n) >= min_t k(t) * flux for every normal, where k is the
    /// band-limited clamped-cosine kernel and flux = 2 sqrt(pi) L_00 > 0 (any non-negative
    /// radiance satisfies this; a wild extrapolation into the unseen directions does not).
    double fit_lambda = -1;
    /// Lat-long input: float row sums (default, fast, within kFloatRowSumBound) or the double
    /// reference (exact to ~1e-15, 2-5x slower).
    LatlongPrecision latlong_precision = LatlongPrecision::kFloatRowSums;
};

struct ProjectResult {
    Eigen::MatrixXd coeffs;          ///< count(sh_bands) x 3, world frame, after the window
    Eigen::MatrixXd coeffs_unwindowed;  ///< the same before the window
    std::string method;              ///< "latlong-separable", "quadrature", "least-squares", "zero-fill"
    double covered_solid_angle_sr = 0;
    bool fitted = false;
    sh::FitResult fit;               ///< when fitted (conditioning, residual, lambda used)
    bool fit_lambda_auto = false;    ///< lambda chosen by the rule above
    bool fit_plausible = true;       ///< the chosen fit meets the irradiance condition
};

/// True when every channel of `coeffs` (count(sh_bands) x channels) has L_00 > 0 and irradiance
/// at least min_t k(t) * 2 sqrt(pi) L_00 at 1000 Fibonacci normals: a necessary condition for
/// coefficients of non-negative radiance.
bool irradiance_is_plausible(const Eigen::MatrixXd& coeffs, int sh_bands);

/// Projects or fits `env` into SH. Deterministic for any thread count.
ProjectResult project(const Environment& env, const ProjectOptions& options);

/// Projection of a 2:1 lat-long image (3 channels) in its own frame, taking each pixel as
/// constant over its exact area (box filter): the integral of Y_lm over every pixel is exact in
/// phi (dphi sinc(m dphi/2) cos(m phi_c)) and Gauss-Legendre over the row (in z, exact, for
/// even m; in theta, to ~1e-15, for odd m). A constant map therefore gives L_00 = 2 sqrt(pi) value and L_lm = 0 for
/// l > 0 for any resolution, a 2x1 map included (kDouble to ~1e-15; kFloatRowSums within its
/// bound: its m = 0 weights are exactly 1, so only m != 0 terms see the weights' rounding). Separable: per row the column sums
/// f cos(m phi), f sin(m phi) cost O(W sh_bands), the row factors O(sh_bands^2).
///
/// `isa` only affects kFloatRowSums.
Eigen::MatrixXd project_latlong(const image::Image& img, int sh_bands,
                                LatlongPrecision precision = LatlongPrecision::kFloatRowSums,
                                FloatRowSumIsa isa = FloatRowSumIsa::kBest);
/// "float" | "double"; throws UsageError otherwise.
LatlongPrecision latlong_precision_from_string(const std::string& name);

}  // namespace inlight::envmap
