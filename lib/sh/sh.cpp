#include "sh/sh.h"

#include <cmath>

#include "core/check.h"
#include "core/conventions.h"
#include "core/enum_names.h"
#include "core/error.h"

namespace inlight::sh {

void eval(int sh_bands, const Eigen::Vector3d& dir, double* out) {
    INLIGHT_CHECK(sh_bands >= 1 && sh_bands <= kMaxBands) << "sh_bands = " << sh_bands;
    INLIGHT_DCHECK(std::abs(dir.squaredNorm() - 1.0) < 1e-6);
    const double x = dir.x(), y = dir.y(), z = dir.z();

    // Normalised Legendre part N_lm = K_lm P_l^m(z) / sin^m(theta), by the recurrence
    //   N_mm = N_{m-1,m-1} sqrt((2m+1)/(2m)),  N_{m+1,m} = z sqrt(2m+3) N_mm,
    //   N_lm = a_lm (z N_{l-1,m} - b_lm N_{l-2,m}),
    // and the azimuthal part C_m + i S_m = (x + i y)^m = sin^m(theta) e^{i m phi}.
    // Everything stays O(1) in magnitude, so it is stable for any l.
    double nmm = 0.5 / std::sqrt(kPi);  // N_00 = 1 / sqrt(4 pi)
    double cm = 1.0, sm = 0.0;          // (x + iy)^0
    for (int m = 0; m < sh_bands; ++m) {
        if (m > 0) {
            nmm *= std::sqrt((2.0 * m + 1.0) / (2.0 * m));
            const double c = cm * x - sm * y;
            sm = cm * y + sm * x;
            cm = c;
        }
        const double scale_c = m == 0 ? 1.0 : std::sqrt(2.0) * cm;
        const double scale_s = std::sqrt(2.0) * sm;
        double n_l2 = 0.0, n_l1 = nmm;  // N_{l-2,m}, N_{l-1,m} while stepping l
        for (int l = m; l < sh_bands; ++l) {
            double n_l;
            if (l == m) {
                n_l = nmm;
            } else if (l == m + 1) {
                n_l = z * std::sqrt(2.0 * m + 3.0) * nmm;
            } else {
                const double ll = l, mm = m;
                const double a = std::sqrt((4.0 * ll * ll - 1.0) / (ll * ll - mm * mm));
                const double b = std::sqrt(((ll - 1) * (ll - 1) - mm * mm) /
                                           (4.0 * (ll - 1) * (ll - 1) - 1.0));
                n_l = a * (z * n_l1 - b * n_l2);
            }
            if (l > m) {
                n_l2 = n_l1;
                n_l1 = n_l;
            }
            out[index(l, m)] = n_l * scale_c;
            if (m > 0) out[index(l, -m)] = n_l * scale_s;
        }
    }
}

std::vector<double> eval(int sh_bands, const Eigen::Vector3d& dir) {
    std::vector<double> out(static_cast<size_t>(count(sh_bands)));
    eval(sh_bands, dir, out.data());
    return out;
}

double cosine_zonal(int l) {
    INLIGHT_CHECK_GE(l, 0);
    if (l == 0) return kPi;
    if (l == 1) return 2.0 * kPi / 3.0;
    if (l % 2 == 1) return 0.0;
    // R&H eq. 9: 2 pi (-1)^{l/2-1} / ((l+2)(l-1)) * l! / (2^l (l/2)!^2); the last factor is the
    // central binomial C(l, l/2) / 2^l, built as a running product to avoid overflow.
    double central = 1.0;
    for (int k = 1; k <= l / 2; ++k) central *= (2.0 * k - 1.0) / (2.0 * k);
    const double sign = ((l / 2 - 1) % 2 == 0) ? 1.0 : -1.0;
    return 2.0 * kPi * sign / ((l + 2.0) * (l - 1.0)) * central;
}

double irradiance(int sh_bands, const double* coeffs, const Eigen::Vector3d& n) {
    double y[count(kMaxBands)];
    eval(sh_bands, n, y);
    double e = 0.0;
    for (int l = 0; l < sh_bands; ++l) {
        const double a = cosine_zonal(l);
        if (a == 0.0) continue;
        for (int m = -l; m <= l; ++m) e += a * coeffs[index(l, m)] * y[index(l, m)];
    }
    return e;
}

double window_factor(Window window, int l, int sh_bands) {
    switch (window) {
        case Window::kNone:
            return 1.0;
        case Window::kHann:
            return 0.5 * (1.0 + std::cos(kPi * l / sh_bands));
        case Window::kLanczos: {
            if (l == 0) return 1.0;
            const double x = kPi * l / sh_bands;
            return std::sin(x) / x;
        }
    }
    return 1.0;
}

constexpr EnumName<Window> kWindowNames[] = {
    {Window::kNone, "none"},
    {Window::kHann, "hann"},
    {Window::kLanczos, "lanczos"},
};

Window window_from_string(const std::string& name) {
    return enum_from_string(kWindowNames, name, "window");
}

void apply_window(Window window, int sh_bands, Eigen::MatrixXd& coeffs) {
    INLIGHT_CHECK_EQ(coeffs.rows(), count(sh_bands));
    for (int l = 0; l < sh_bands; ++l) {
        const double w = window_factor(window, l, sh_bands);
        coeffs.middleRows(index(l, -l), 2 * l + 1) *= w;
    }
}

Eigen::Matrix4d irradiance_matrix(const double* L) {
    // Exact forms of R&H's constants: c1 = A2 * (1/4) sqrt(15/pi), c2 = A1 * (1/2) sqrt(3/pi) / 2 (it appears twice, as M(0,3) and M(3,0)),
    // c3 = 3 * A2 * (1/4) sqrt(5/pi), c4 = A0 * (1/2) sqrt(1/pi), c5 = A2 * (1/4) sqrt(5/pi).
    const double c1 = kPi / 4.0 * 0.25 * std::sqrt(15.0 / kPi);
    const double c2 = 2.0 * kPi / 3.0 * 0.5 * std::sqrt(3.0 / kPi) / 2.0;
    const double c5 = kPi / 4.0 * 0.25 * std::sqrt(5.0 / kPi);
    const double c3 = 3.0 * c5;
    const double c4 = kPi * 0.5 * std::sqrt(1.0 / kPi);
    const double l00 = L[index(0, 0)], l1m1 = L[index(1, -1)], l10 = L[index(1, 0)],
                 l11 = L[index(1, 1)], l2m2 = L[index(2, -2)], l2m1 = L[index(2, -1)],
                 l20 = L[index(2, 0)], l21 = L[index(2, 1)], l22 = L[index(2, 2)];
    Eigen::Matrix4d m;
    m << c1 * l22, c1 * l2m2, c1 * l21, c2 * l11,  //
        c1 * l2m2, -c1 * l22, c1 * l2m1, c2 * l1m1,  //
        c1 * l21, c1 * l2m1, c3 * l20, c2 * l10,     //
        c2 * l11, c2 * l1m1, c2 * l10, c4 * l00 - c5 * l20;
    return m;
}

}  // namespace inlight::sh
