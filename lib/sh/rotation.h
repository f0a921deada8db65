// sh/rotation.h: rotation of SH coefficient vectors (each band is an invariant subspace).
#pragma once

#include <Eigen/Core>

namespace inlight::sh {

/// Block-diagonal matrix D (count x count) such that, if c are the coefficients of f, then
/// D * c are the coefficients of g(w) = f(R^-1 w), i.e. of f rotated by R = world_from_input.
/// D_kj = integral Y_k(R w) Y_j(w) dw, computed by a quadrature that is exact for band-limited
/// products (Gauss-Legendre x uniform phi), so D is orthogonal to ~1e-13.
/// Precondition: R is a rotation (checked: orthonormal with det +1 to 1e-9).
Eigen::MatrixXd rotation_matrix(int sh_bands, const Eigen::Matrix3d& world_from_input);

}  // namespace inlight::sh
