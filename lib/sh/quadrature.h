// sh/quadrature.h: deterministic quadrature rules on [-1, 1] and on the sphere.
#pragma once

#include <vector>

namespace inlight::sh {

/// Gauss-Legendre rule with n nodes on [-1, 1] (exact for polynomials of degree <= 2n - 1).
/// Nodes ascending; weights sum to 2. Newton iteration on P_n to machine precision.
/// Precondition: n >= 1 (checked).
void gauss_legendre(int n, std::vector<double>& nodes, std::vector<double>& weights);

}  // namespace inlight::sh
