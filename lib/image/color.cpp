#include "image/color.h"

#include <Eigen/LU>
#include <cmath>

namespace inlight::image {
namespace {

constexpr double kPiD = 3.14159265358979323846;

double deg_from_rad(double r) { return r * (180.0 / kPiD); }
double rad_from_deg(double d) { return d * (kPiD / 180.0); }

// RGB -> XYZ from chromaticities: the columns are the primaries' XYZ (Y = 1) scaled so that
// RGB (1, 1, 1) lands on the white (the standard derivation, e.g. SMPTE RP 177).
Eigen::Matrix3d xyz_from_rgb(const double xy[3][2], const Eigen::Vector3d& white) {
    Eigen::Matrix3d p;
    for (int i = 0; i < 3; ++i) {
        const double x = xy[i][0], y = xy[i][1];
        p.col(i) = Eigen::Vector3d(x / y, 1.0, (1.0 - x - y) / y);
    }
    const Eigen::Vector3d s = p.partialPivLu().solve(white);
    return p * s.asDiagonal();
}

// CIE f(t) with the exact constants delta = 6/29 (CIE 15:2004, eq. 8.3-8.5).
double lab_f(double t) {
    constexpr double kDelta = 6.0 / 29.0;
    constexpr double kDelta3 = kDelta * kDelta * kDelta;
    if (t > kDelta3) return std::cbrt(t);
    return t / (3.0 * kDelta * kDelta) + 4.0 / 29.0;
}

// The inverse of lab_f: cube above f = 6/29, linear below.
double lab_f_inverse(double f) {
    constexpr double kDelta = 6.0 / 29.0;
    if (f > kDelta) return f * f * f;
    return 3.0 * kDelta * kDelta * (f - 4.0 / 29.0);
}

// Hue angle in degrees in [0, 360); 0 for the achromatic axis (Sharma et al. eq. 4).
double pow7(double x) {
    const double x2 = x * x;
    return x2 * x2 * x2 * x;
}

double hue_deg(double b, double a_prime) {
    if (b == 0.0 && a_prime == 0.0) return 0.0;
    double h = deg_from_rad(std::atan2(b, a_prime));
    if (h < 0.0) h += 360.0;
    return h;
}

}  // namespace

float srgb_decode(float encoded) {
    const double v = std::fabs(static_cast<double>(encoded));
    const double lin = v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
    return static_cast<float>(encoded < 0 ? -lin : lin);
}

float srgb_encode(float linear) {
    const double v = std::fabs(static_cast<double>(linear));
    const double enc = v <= 0.0031308 ? v * 12.92 : 1.055 * std::pow(v, 1.0 / 2.4) - 0.055;
    return static_cast<float>(linear < 0 ? -enc : enc);
}

Eigen::Vector3d d65_white_xyz() { return Eigen::Vector3d(0.95047, 1.0, 1.08883); }

const Eigen::Matrix3d& xyz_from_linear_srgb_matrix() {
    static const Eigen::Matrix3d m = [] {
        const double xy[3][2] = {{0.64, 0.33}, {0.30, 0.60}, {0.15, 0.06}};
        return xyz_from_rgb(xy, d65_white_xyz());
    }();
    return m;
}

const Eigen::Matrix3d& linear_srgb_from_xyz_matrix() {
    static const Eigen::Matrix3d m = xyz_from_linear_srgb_matrix().inverse();
    return m;
}

const Eigen::Matrix3d& xyz_from_linear_rec2020_matrix() {
    static const Eigen::Matrix3d m = [] {
        const double xy[3][2] = {{0.708, 0.292}, {0.170, 0.797}, {0.131, 0.046}};
        return xyz_from_rgb(xy, d65_white_xyz());
    }();
    return m;
}

Eigen::Vector3d xyz_from_linear_srgb(const Eigen::Vector3d& rgb) {
    return xyz_from_linear_srgb_matrix() * rgb;
}

Eigen::Vector3d linear_srgb_from_xyz(const Eigen::Vector3d& xyz) {
    return linear_srgb_from_xyz_matrix() * xyz;
}

Eigen::Vector3d lab_from_xyz(const Eigen::Vector3d& xyz) {
    const Eigen::Vector3d w = d65_white_xyz();
    const double fx = lab_f(xyz.x() / w.x());
    const double fy = lab_f(xyz.y() / w.y());
    const double fz = lab_f(xyz.z() / w.z());
    return Eigen::Vector3d(116.0 * fy - 16.0, 500.0 * (fx - fy), 200.0 * (fy - fz));
}

Eigen::Vector3d lab_from_linear_srgb(const Eigen::Vector3d& rgb) {
    return lab_from_xyz(xyz_from_linear_srgb(rgb));
}

Eigen::Vector3d xyz_from_lab(const Eigen::Vector3d& lab) {
    const Eigen::Vector3d w = d65_white_xyz();
    const double fy = (lab[0] + 16.0) / 116.0;
    return Eigen::Vector3d(w.x() * lab_f_inverse(fy + lab[1] / 500.0), w.y() * lab_f_inverse(fy),
                           w.z() * lab_f_inverse(fy - lab[2] / 200.0));
}

Eigen::Vector3d linear_srgb_from_lab(const Eigen::Vector3d& lab) {
    return linear_srgb_from_xyz(xyz_from_lab(lab));
}

double delta_e76(const Eigen::Vector3d& lab1, const Eigen::Vector3d& lab2) {
    return (lab1 - lab2).norm();
}

// Sharma, Wu and Dalal (2005), eq. 2-22, with kL = kC = kH = 1.
double delta_e2000(const Eigen::Vector3d& lab1, const Eigen::Vector3d& lab2) {
    constexpr double k25_7 = 6103515625.0;  // 25^7
    const double L1 = lab1[0], a1 = lab1[1], b1 = lab1[2];
    const double L2 = lab2[0], a2 = lab2[1], b2 = lab2[2];

    // eq. 2-5: a' stretched by G, C', h'.
    const double c_ab = 0.5 * (std::hypot(a1, b1) + std::hypot(a2, b2));
    const double c_ab7 = pow7(c_ab);
    const double g = 0.5 * (1.0 - std::sqrt(c_ab7 / (c_ab7 + k25_7)));
    const double a1p = (1.0 + g) * a1, a2p = (1.0 + g) * a2;
    const double c1p = std::hypot(a1p, b1), c2p = std::hypot(a2p, b2);
    const double h1p = hue_deg(b1, a1p), h2p = hue_deg(b2, a2p);
    const bool achromatic = c1p * c2p == 0.0;

    // eq. 8-10: differences.
    const double dLp = L2 - L1;
    const double dCp = c2p - c1p;
    double dhp = 0.0;
    if (!achromatic) {
        dhp = h2p - h1p;
        if (dhp > 180.0) {
            dhp -= 360.0;
        } else if (dhp < -180.0) {
            dhp += 360.0;
        }
    }
    const double dHp = 2.0 * std::sqrt(c1p * c2p) * std::sin(rad_from_deg(0.5 * dhp));

    // eq. 12-22: weights and rotation.
    const double Lbp = 0.5 * (L1 + L2);
    const double Cbp = 0.5 * (c1p + c2p);
    double hbp = h1p + h2p;
    if (!achromatic) {
        if (std::fabs(h1p - h2p) <= 180.0) {
            hbp *= 0.5;
        } else if (hbp < 360.0) {
            hbp = 0.5 * (hbp + 360.0);
        } else {
            hbp = 0.5 * (hbp - 360.0);
        }
    }
    const double t = 1.0 - 0.17 * std::cos(rad_from_deg(hbp - 30.0)) +
                     0.24 * std::cos(rad_from_deg(2.0 * hbp)) +
                     0.32 * std::cos(rad_from_deg(3.0 * hbp + 6.0)) -
                     0.20 * std::cos(rad_from_deg(4.0 * hbp - 63.0));
    const double hr = (hbp - 275.0) / 25.0;
    const double dtheta = 30.0 * std::exp(-hr * hr);
    const double cbp7 = pow7(Cbp);
    const double rc = 2.0 * std::sqrt(cbp7 / (cbp7 + k25_7));
    const double l50 = (Lbp - 50.0) * (Lbp - 50.0);
    const double sl = 1.0 + 0.015 * l50 / std::sqrt(20.0 + l50);
    const double sc = 1.0 + 0.045 * Cbp;
    const double sh = 1.0 + 0.015 * Cbp * t;
    const double rt = -std::sin(rad_from_deg(2.0 * dtheta)) * rc;

    const double tl = dLp / sl, tc = dCp / sc, th = dHp / sh;
    return std::sqrt(tl * tl + tc * tc + th * th + rt * tc * th);
}

}  // namespace inlight::image
