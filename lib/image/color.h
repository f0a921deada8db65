// image/color.h: sRGB transfer curve, linear Rec.709 <-> CIE XYZ (D65), CIELAB, and colour
// differences dE76 and CIEDE2000 (Sharma, Wu and Dalal 2005, eq. 1-22).
//
// Matrices: xyz_from_linear_srgb is derived (once, in double) from the Rec.709 / sRGB primaries
// (x, y) = R (0.64, 0.33), G (0.30, 0.60), B (0.15, 0.06) and the D65 white XYZ
// (0.95047, 1, 1.08883), the same white CIELAB uses below, so RGB (1, 1, 1) maps exactly to the
// Lab white point and to L* = 100, a* = b* = 0. This is the derivation behind Lindbloom's
// published 7-digit sRGB matrix (0.4124564 0.3575761 0.1804375 / ...). The inverse is the exact
// double-precision inverse of that matrix (round trip error ~1e-16), not IEC 61966-2-1's
// separately rounded 4-digit inverse. linear_rec2020 is derived the same way from the BT.2020
// primaries (0.708, 0.292), (0.170, 0.797), (0.131, 0.046) and the same white.
#pragma once

#include <Eigen/Core>

namespace inlight::image {

/// sRGB (IEC 61966-2-1) decode: encoded value in [0, 1] -> linear. Negative inputs are mirrored.
float srgb_decode(float encoded);
/// sRGB encode: linear -> encoded (not clamped; clamp before quantising).
float srgb_encode(float linear);

/// CIE XYZ (D65, Y of white = 1) from linear Rec.709 RGB, and back.
Eigen::Vector3d xyz_from_linear_srgb(const Eigen::Vector3d& rgb);
Eigen::Vector3d linear_srgb_from_xyz(const Eigen::Vector3d& xyz);

/// The D65 white used throughout: XYZ (0.95047, 1, 1.08883).
Eigen::Vector3d d65_white_xyz();

/// The 3x3 matrices behind the conversions above (see the file comment for their derivation).
const Eigen::Matrix3d& xyz_from_linear_srgb_matrix();
const Eigen::Matrix3d& linear_srgb_from_xyz_matrix();
/// XYZ (D65) from linear Rec.2020 RGB, derived the same way.
const Eigen::Matrix3d& xyz_from_linear_rec2020_matrix();

/// CIELAB (L* in [0, 100]) from XYZ relative to the D65 white (0.95047, 1, 1.08883).
/// Uses the exact CIE constants: f(t) = cbrt(t) above (6/29)^3, linear below. Negative and
/// out-of-gamut XYZ give finite (extrapolated) values, never NaN.
Eigen::Vector3d lab_from_xyz(const Eigen::Vector3d& xyz);
/// Convenience: CIELAB of a linear Rec.709 colour.
Eigen::Vector3d lab_from_linear_srgb(const Eigen::Vector3d& rgb);
/// The inverse of lab_from_xyz (CIE 15:2004 eq. 8.6-8.8, the same exact constants): XYZ
/// relative to the D65 white. Every finite Lab maps to a finite XYZ (outside the real colours
/// where Lab is).
Eigen::Vector3d xyz_from_lab(const Eigen::Vector3d& lab);
/// Convenience: the linear Rec.709 colour of a CIELAB value (not clamped).
Eigen::Vector3d linear_srgb_from_lab(const Eigen::Vector3d& lab);

/// CIE 1976 colour difference: Euclidean distance in CIELAB.
double delta_e76(const Eigen::Vector3d& lab1, const Eigen::Vector3d& lab2);
/// CIEDE2000 colour difference with kL = kC = kH = 1.
double delta_e2000(const Eigen::Vector3d& lab1, const Eigen::Vector3d& lab2);

}  // namespace inlight::image
