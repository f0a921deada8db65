#include "sh/rotation.h"

#include <cmath>
#include <vector>

#include "core/check.h"
#include "core/conventions.h"
#include "sh/quadrature.h"
#include "sh/sh.h"

namespace inlight::sh {

Eigen::MatrixXd rotation_matrix(int sh_bands, const Eigen::Matrix3d& r) {
    INLIGHT_CHECK((r * r.transpose() - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() < 1e-9 &&
                  std::abs(r.determinant() - 1.0) < 1e-9)
        << "not a rotation matrix";
    const int n = count(sh_bands);
    // Products of two band-(sh_bands-1) functions have degree <= 2(sh_bands-1): sh_bands
    // Gauss-Legendre nodes in z and 2 sh_bands uniform azimuths integrate them exactly.
    std::vector<double> z, wz;
    gauss_legendre(sh_bands + 1, z, wz);
    const int nphi = 2 * sh_bands + 2;
    Eigen::MatrixXd d = Eigen::MatrixXd::Zero(n, n);
    Eigen::VectorXd y(n), yr(n);
    for (size_t i = 0; i < z.size(); ++i) {
        const double s = std::sqrt(std::max(0.0, 1.0 - z[i] * z[i]));
        for (int j = 0; j < nphi; ++j) {
            const double phi = 2.0 * kPi * (j + 0.5) / nphi;
            const Eigen::Vector3d w(s * std::cos(phi), s * std::sin(phi), z[i]);
            eval(sh_bands, w, y.data());
            eval(sh_bands, (r * w).normalized(), yr.data());
            d.noalias() += (wz[i] * 2.0 * kPi / nphi) * yr * y.transpose();
        }
    }
    // Zero the exact-zero cross-band blocks so rounding does not leak between bands.
    for (int l = 0; l < sh_bands; ++l) {
        for (int l2 = 0; l2 < sh_bands; ++l2) {
            if (l != l2) d.block(index(l, -l), index(l2, -l2), 2 * l + 1, 2 * l2 + 1).setZero();
        }
    }
    return d;
}

}  // namespace inlight::sh
