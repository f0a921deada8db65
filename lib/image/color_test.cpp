#include "image/color.h"
#include "image/sharma2005_testing.h"

#include <gtest/gtest.h>
#include <lcms2.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

namespace inlight::image {
namespace {

using testdata::kSharma;
using testdata::SharmaPair;

// float carries 24 bits: a few ulps of values in [0, 1].
constexpr double kFloatTol = 3e-7;
// Matrix products and exact inverse in double: well above 1e-16 rounding, far below any real error.
constexpr double kDoubleTol = 1e-12;

TEST(Srgb, DecodeKnownPoints) {
    EXPECT_EQ(srgb_decode(0.0f), 0.0f);
    EXPECT_NEAR(srgb_decode(1.0f), 1.0, kFloatTol);
    // ((0.5 + 0.055) / 1.055)^2.4 = 0.21404114048...
    EXPECT_NEAR(srgb_decode(0.5f), 0.21404114048, kFloatTol);
    // Linear segment: x / 12.92 at and below the 0.04045 threshold.
    EXPECT_NEAR(srgb_decode(0.04045f), 0.04045 / 12.92, kFloatTol * 0.01);
    EXPECT_NEAR(srgb_decode(0.02f), 0.02 / 12.92, kFloatTol * 0.01);
    // Power segment just above it.
    EXPECT_NEAR(srgb_decode(0.2f), std::pow((0.2 + 0.055) / 1.055, 2.4), kFloatTol);
}

TEST(Srgb, ContinuousAtThreshold) {
    // The two IEC 61966-2-1 segments meet at 0.04045 to ~1e-8 (the standard's rounded
    // constants leave a tiny step); one float ulp either side must not jump more than that
    // plus the slope (1/12.92) times the step.
    const float lo = 0.04045f, hi = std::nextafter(lo, 1.0f);
    const double jump = srgb_decode(hi) - srgb_decode(lo);
    EXPECT_GE(jump, 0.0);
    EXPECT_LT(jump, 1e-8 + (hi - lo) / 12.92 * 1.01);
}

TEST(Srgb, EncodeKnownPoints) {
    EXPECT_EQ(srgb_encode(0.0f), 0.0f);
    EXPECT_NEAR(srgb_encode(1.0f), 1.0, kFloatTol);
    EXPECT_NEAR(srgb_encode(0.21404114f), 0.5, kFloatTol);
    EXPECT_NEAR(srgb_encode(0.002f), 0.002 * 12.92, kFloatTol * 0.01);
}

TEST(Srgb, RoundTripEveryEightAndSixteenBitCode) {
    double worst = 0;
    for (int code = 0; code <= 65535; ++code) {
        const float e = code / 65535.0f;
        worst = std::max(worst, std::fabs(double(srgb_encode(srgb_decode(e))) - e));
    }
    EXPECT_LT(worst, kFloatTol);
    // 8-bit codes map back to the same code after quantisation.
    for (int code = 0; code <= 255; ++code) {
        const float e = srgb_encode(srgb_decode(code / 255.0f));
        EXPECT_EQ(std::lround(e * 255.0), code);
    }
}

TEST(Srgb, RoundTripLinearValuesAndMirrorsNegatives) {
    for (float x : {1e-6f, 1e-3f, 0.0031308f, 0.01f, 0.18f, 0.5f, 1.0f, 4.0f}) {
        EXPECT_NEAR(srgb_decode(srgb_encode(x)), x, kFloatTol * std::max(1.0f, x));
        EXPECT_EQ(srgb_encode(-x), -srgb_encode(x));
        EXPECT_EQ(srgb_decode(-x), -srgb_decode(x));
    }
}

TEST(RgbXyz, WhiteMapsToD65) {
    const Eigen::Vector3d w = xyz_from_linear_srgb(Eigen::Vector3d::Ones());
    EXPECT_NEAR(w.x(), 0.95047, kDoubleTol);
    EXPECT_NEAR(w.y(), 1.0, kDoubleTol);
    EXPECT_NEAR(w.z(), 1.08883, kDoubleTol);
    const Eigen::Vector3d w2020 = xyz_from_linear_rec2020_matrix() * Eigen::Vector3d::Ones();
    EXPECT_NEAR((w2020 - d65_white_xyz()).norm(), 0.0, kDoubleTol);
}

TEST(RgbXyz, MatrixMatchesPublishedValues) {
    // Bruce Lindbloom, "RGB/XYZ Matrices", sRGB with reference white D65 (0.95047, 1, 1.08883),
    // published to 7 decimals: agreement within half a unit of the last digit.
    constexpr double kPublishedRounding = 0.5e-7 + 1e-12;
    const double lindbloom[3][3] = {{0.4124564, 0.3575761, 0.1804375},
                                    {0.2126729, 0.7151522, 0.0721750},
                                    {0.0193339, 0.1191920, 0.9503041}};
    const Eigen::Matrix3d& m = xyz_from_linear_srgb_matrix();
    for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(m(r, c), lindbloom[r][c], kPublishedRounding);
    }
}

TEST(RgbXyz, PrimariesHaveTheirChromaticities) {
    // By construction each RGB primary maps to XYZ with chromaticity (x, y) = X, Y / (X+Y+Z).
    auto check = [](const Eigen::Matrix3d& m, const double xy[3][2], const char* what) {
        for (int i = 0; i < 3; ++i) {
            const Eigen::Vector3d p = m.col(i);
            EXPECT_NEAR(p.x() / p.sum(), xy[i][0], kDoubleTol) << what << " primary " << i;
            EXPECT_NEAR(p.y() / p.sum(), xy[i][1], kDoubleTol) << what << " primary " << i;
        }
    };
    const double srgb[3][2] = {{0.64, 0.33}, {0.30, 0.60}, {0.15, 0.06}};
    const double rec2020[3][2] = {{0.708, 0.292}, {0.170, 0.797}, {0.131, 0.046}};
    check(xyz_from_linear_srgb_matrix(), srgb, "sRGB");
    check(xyz_from_linear_rec2020_matrix(), rec2020, "Rec.2020");
}

TEST(RgbXyz, RoundTrip) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-0.5, 50.0);
    for (int i = 0; i < 1000; ++i) {
        const Eigen::Vector3d rgb(u(rng), u(rng), u(rng));
        const Eigen::Vector3d back = linear_srgb_from_xyz(xyz_from_linear_srgb(rgb));
        EXPECT_LT((back - rgb).norm(), kDoubleTol * std::max(1.0, rgb.norm()));
    }
    const Eigen::Matrix3d prod = linear_srgb_from_xyz_matrix() * xyz_from_linear_srgb_matrix();
    EXPECT_LT((prod - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff(), kDoubleTol);
}

TEST(Lab, WhiteBlackAndGrey) {
    const Eigen::Vector3d white = lab_from_xyz(d65_white_xyz());
    EXPECT_NEAR(white[0], 100.0, kDoubleTol);
    EXPECT_NEAR(white[1], 0.0, kDoubleTol);
    EXPECT_NEAR(white[2], 0.0, kDoubleTol);
    // RGB white through the derived matrix lands on the same white.
    const Eigen::Vector3d rgb_white = lab_from_linear_srgb(Eigen::Vector3d::Ones());
    EXPECT_NEAR((rgb_white - Eigen::Vector3d(100, 0, 0)).norm(), 0.0, 1e-10);
    EXPECT_NEAR(lab_from_xyz(Eigen::Vector3d::Zero()).norm(), 0.0, kDoubleTol);
    // Grey 0.18: L* = 116 * 0.18^(1/3) - 16 = 49.4961..., neutral a* = b* = 0.
    const Eigen::Vector3d grey = lab_from_linear_srgb(Eigen::Vector3d::Constant(0.18));
    EXPECT_NEAR(grey[0], 116.0 * std::cbrt(0.18) - 16.0, 1e-10);
    EXPECT_NEAR(grey[1], 0.0, 1e-10);
    EXPECT_NEAR(grey[2], 0.0, 1e-10);
}

TEST(Lab, LinearSegmentForDarkColours) {
    // Below (6/29)^3 = 0.008856, L* = (29/3)^3 * Y = 903.2963 * Y (CIE 15:2004).
    const double y = 0.001;
    EXPECT_NEAR(lab_from_xyz(d65_white_xyz() * y)[0], std::pow(29.0 / 3.0, 3.0) * y, 1e-10);
    // Continuous at the junction: both segments give L* = 8 at Y = (6/29)^3.
    const double yj = std::pow(6.0 / 29.0, 3.0);
    EXPECT_NEAR(lab_from_xyz(d65_white_xyz() * yj)[0], 8.0, 1e-10);
    EXPECT_NEAR(lab_from_xyz(d65_white_xyz() * (yj * (1 + 1e-9)))[0], 8.0, 1e-7);
    // Negative input is finite.
    EXPECT_TRUE(lab_from_xyz(Eigen::Vector3d(-0.1, -0.1, -0.1)).allFinite());
}

TEST(Lab, InverseRoundTripsOnBothSegmentsAndOutOfGamut) {
    // Closed-form inverse: XYZ -> Lab -> XYZ is the identity up to double rounding of the cube
    // root (relative 1e-12 covers a few ulps through cbrt and the 3x3 products).
    constexpr double kRoundTripTol = 1e-12;
    const double yj = std::pow(6.0 / 29.0, 3.0);
    const std::vector<Eigen::Vector3d> colours = {Eigen::Vector3d(0.18, 0.18, 0.18), Eigen::Vector3d(1, 0, 0),
                                                  Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(0.001, 0.002, 0.0005),
                                                  Eigen::Vector3d(yj, yj, yj), Eigen::Vector3d(1.7, -0.05, 0.3),
                                                  Eigen::Vector3d(0, 0, 0)};
    for (const Eigen::Vector3d& rgb : colours) {
        const Eigen::Vector3d back = linear_srgb_from_lab(lab_from_linear_srgb(rgb));
        EXPECT_NEAR((back - rgb).norm(), 0.0, kRoundTripTol * std::max(1.0, rgb.norm())) << rgb.transpose();
    }
    // Lab -> XYZ -> Lab also for values no real colour has (what a fitted model may produce).
    const Eigen::Vector3d lab(35.0, 90.0, -120.0);
    EXPECT_NEAR((lab_from_xyz(xyz_from_lab(lab)) - lab).norm(), 0.0, 1e-10);
    EXPECT_NEAR(xyz_from_lab(Eigen::Vector3d(100, 0, 0)).y(), 1.0, kDoubleTol);
    EXPECT_NEAR(xyz_from_lab(Eigen::Vector3d(8, 0, 0)).y(), yj, kDoubleTol);
}

TEST(DeltaE76, IsEuclidean) {
    EXPECT_DOUBLE_EQ(delta_e76({50, 0, 0}, {53, 4, 0}), 5.0);
    EXPECT_DOUBLE_EQ(delta_e76({50, 10, -3}, {50, 10, -3}), 0.0);
}

TEST(DeltaE2000, SharmaWuDalal2005Table1) {
    // The published dE00 are rounded to 4 decimals (error <= 5e-5); 1e-4 allows that rounding
    // with margin for libm differences but is far tighter than any formula mistake (a wrong
    // hue-mean branch, as pairs 9-15 probe, moves the result by > 0.04).
    constexpr double kPublishedTol = 1e-4;
    for (int i = 0; i < 34; ++i) {
        const SharmaPair& p = kSharma[i];
        const Eigen::Vector3d a(p.lab1[0], p.lab1[1], p.lab1[2]);
        const Eigen::Vector3d b(p.lab2[0], p.lab2[1], p.lab2[2]);
        EXPECT_NEAR(delta_e2000(a, b), p.de2000, kPublishedTol) << "pair " << i + 1;
        // The formula is symmetric in its two arguments (Sharma et al., section 3).
        EXPECT_NEAR(delta_e2000(b, a), p.de2000, kPublishedTol) << "pair " << i + 1 << " swapped";
    }
}

TEST(DeltaE2000, AgreesWithLittleCms) {
    // An independent implementation: Little CMS 2's cmsCIE2000DeltaE (Debian liblcms2-dev), over
    // random pairs far apart and close together (half within a few units, where dE00's hue and
    // chroma weights matter most). Both evaluate the same closed form in double: measured worst
    // difference 1.7e-13 over 2e5 pairs; 1e-11 leaves room for another libm and stays far below
    // any formula mistake (the Sharma pairs move by > 1e-4 for a wrong branch or constant).
    constexpr double kTwoDoubleImplementationsTol = 1e-11;
    std::mt19937_64 rng(12);
    std::uniform_real_distribution<double> lightness(0, 100), ab(-128, 128), step(-2.5, 2.5);
    double worst = 0;
    for (int i = 0; i < 20000; ++i) {
        cmsCIELab a{lightness(rng), ab(rng), ab(rng)};
        cmsCIELab b{lightness(rng), ab(rng), ab(rng)};
        if (i % 2) b = {a.L + step(rng), a.a + step(rng), a.b + step(rng)};
        const double ours = delta_e2000({a.L, a.a, a.b}, {b.L, b.a, b.b});
        const double lcms = cmsCIE2000DeltaE(&a, &b, 1.0, 1.0, 1.0);
        worst = std::max(worst, std::fabs(ours - lcms));
        ASSERT_NEAR(ours, lcms, kTwoDoubleImplementationsTol)
            << "Lab (" << a.L << ", " << a.a << ", " << a.b << ") vs (" << b.L << ", " << b.a
            << ", " << b.b << ")";
    }
    RecordProperty("worst_abs_difference", std::to_string(worst));
}

TEST(DeltaE2000, ZeroForIdenticalAndPureLightness) {
    EXPECT_EQ(delta_e2000({40, 12, -7}, {40, 12, -7}), 0.0);
    // Neutral colours differing only in L*: dE00 = |dL| / SL with
    // SL = 1 + 0.015 (Lbar - 50)^2 / sqrt(20 + (Lbar - 50)^2) (eq. 18).
    const double l1 = 30, l2 = 40, lbar = 35, d2 = (lbar - 50) * (lbar - 50);
    const double sl = 1 + 0.015 * d2 / std::sqrt(20 + d2);
    EXPECT_NEAR(delta_e2000({l1, 0, 0}, {l2, 0, 0}), 10.0 / sl, kDoubleTol);
}

}  // namespace
}  // namespace inlight::image
