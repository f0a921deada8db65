// sh/sh.h: real spherical harmonics of any band count, the clamped-cosine (irradiance)
// convolution and the 4x4 irradiance matrix.
//
// Papers: Ramamoorthi and Hanrahan 2001, "An Efficient Representation for Irradiance
// Environment Maps" (eq. 3 basis, eq. 8-9 cosine coefficients A_l, eq. 11-12 matrix form);
// normalised associated-Legendre recurrence as in Sloan 2013, "Efficient Spherical Harmonic
// Evaluation" (JCGT 2(2)).
//
// Convention (docs/conventions.md): real SH WITHOUT the Condon-Shortley phase, as R&H 2001:
//   Y_0,0 = 0.282095, Y_1,-1 = 0.488603 y, Y_1,0 = 0.488603 z, Y_1,1 = 0.488603 x,
//   Y_2,-2 = 1.092548 xy, Y_2,-1 = 1.092548 yz, Y_2,0 = 0.315392 (3z^2 - 1),
//   Y_2,1 = 1.092548 xz, Y_2,2 = 0.546274 (x^2 - y^2);
// in general Y_l,m = sqrt(2) K_l^|m| P_l^|m|(z) * {cos(m phi) for m > 0, sin(|m| phi) for m < 0}
// with P_l^m free of the (-1)^m factor. Band l, order m, flat index l*(l+1)+m. Counts are
// always `sh_bands` = max l + 1, so sh_bands = 3 gives 9 coefficients.
// The inlight report's basis (its Figure 6) carries the phase (Y_1,1 = -0.4886 x) while its
// irradiance matrix assumes none; this module follows R&H throughout.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

namespace inlight::sh {

/// Largest supported band count (l <= 63). The recurrence is stable in double far beyond.
inline constexpr int kMaxBands = 64;

/// Number of coefficients for `sh_bands` bands: sh_bands^2.
constexpr int count(int sh_bands) { return sh_bands * sh_bands; }
/// Flat index of (l, m), -l <= m <= l.
constexpr int index(int l, int m) { return l * (l + 1) + m; }

/// Evaluates Y_lm(dir) for all l < sh_bands into out[0 .. count(sh_bands)).
/// Precondition: 1 <= sh_bands <= kMaxBands (checked); dir has unit length (checked in Debug).
void eval(int sh_bands, const Eigen::Vector3d& dir, double* out);
/// As above, returning a new vector.
std::vector<double> eval(int sh_bands, const Eigen::Vector3d& dir);

/// R&H eq. 9: A_l, the coefficient by which the clamped cosine max(cos, 0) scales band l of a
/// function under convolution (A_0 = pi, A_1 = 2pi/3, A_2 = pi/4, A_odd>1 = 0, A_4 = -pi/24).
double cosine_zonal(int l);

/// Irradiance E(n) = sum_lm A_l L_lm Y_lm(n) for one channel of coefficients.
/// Precondition: coeffs.size() == count(sh_bands); n unit length.
double irradiance(int sh_bands, const double* coeffs, const Eigen::Vector3d& n);

/// Band-limiting windows against ringing (off by default). Factor w_l multiplies band l.
enum class Window {
    kNone,     ///< w_l = 1
    kHann,     ///< w_l = (1 + cos(pi l / sh_bands)) / 2
    kLanczos,  ///< w_l = sinc(l / sh_bands) (sigma factors)
};
double window_factor(Window window, int l, int sh_bands);
/// "none" | "hann" | "lanczos"; throws UsageError otherwise.
Window window_from_string(const std::string& name);
/// Multiplies each band of coeffs (count(sh_bands) x channels) by its window factor.
void apply_window(Window window, int sh_bands, Eigen::MatrixXd& coeffs);

/// R&H eq. 12: symmetric M with E(n) = (x y z 1) M (x y z 1)^T for unit n, built from the first
/// 9 coefficients of one channel (l <= 2; higher bands are ignored, as the cosine lobe keeps
/// 99% of its energy there). The constants c1..c5 are computed exactly, not from the paper's
/// 6-digit values. Precondition: at least 9 coefficients.
Eigen::Matrix4d irradiance_matrix(const double* coeffs9);

}  // namespace inlight::sh
