// Tests of weave/weave.h: the interlacing patterns against their textile definitions, the
// centre-lines' exact periodicity, interpolation of the crossings and C2 continuity, the
// Embree control points against the spline they describe, and the fabric files' checks.
#include "weave/weave.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <random>

#include "testing/testing.h"

namespace inlight::weave {
namespace {

/// B-spline sums of a few terms of size ~1 mm in double: exact to ~1e-15 mm; 1e-12 leaves room
/// for the (s / knot spacing) rounding of shifted arguments, far below any geometric scale.
constexpr double kSplineTolMm = 1e-12;
/// Control heights come from a dense LU solve of a well-conditioned (eigenvalues >= 1/3)
/// system of size <= 64: residuals ~1e-15 mm.
constexpr double kSolveTolMm = 1e-12;

std::string source_dir() { return INLIGHT_SOURCE_DIR; }

WeaveSpec spec_of(const std::string& text) { return parse_weave(text, "test.toml"); }

TEST(Pattern, PlainIsACheckerboard) {
    const Weave w = build(spec_of("pattern = \"plain\""));
    ASSERT_EQ(w.warp_count, 2);
    ASSERT_EQ(w.weft_count, 2);
    for (int i = -3; i < 5; ++i)
        for (int j = -3; j < 5; ++j) EXPECT_EQ(w.over(i, j), ((i + j) % 2 + 2) % 2 == 0);
}

TEST(Pattern, TwillFloatsMoveOneWeftPerWarp) {
    const Weave w = build(spec_of("pattern = \"twill\"\ntwill = [2, 1]"));
    ASSERT_EQ(w.warp_count, 3);
    for (int i = 0; i < 3; ++i) {
        int over = 0;
        for (int j = 0; j < 3; ++j) over += w.over(i, j);
        EXPECT_EQ(over, 2) << "warp " << i << " floats over 2 of 3 wefts";
        // The float of warp i + 1 is that of warp i moved up one weft (a Z twill).
        for (int j = 0; j < 3; ++j) EXPECT_EQ(w.over(i + 1, j + 1), w.over(i, j));
    }
}

TEST(Pattern, SatinInterlacesOncePerThreadAndNeverNextToAnother) {
    const Weave w = build(spec_of("pattern = \"satin\"\nsatin = [8, 3]"));
    ASSERT_EQ(w.warp_count, 8);
    for (int i = 0; i < 8; ++i) {
        int under_w = 0, under_f = 0;
        for (int j = 0; j < 8; ++j) {
            under_w += !w.over(i, j);
            under_f += !w.over(j, i);
            if (!w.over(i, j)) {  // no interlacing beside it on the neighbouring warps
                EXPECT_TRUE(w.over(i + 1, j) && w.over(i - 1, j) && w.over(i + 1, j + 1) &&
                            w.over(i + 1, j - 1));
            }
        }
        EXPECT_EQ(under_w, 1) << "warp " << i;
        EXPECT_EQ(under_f, 1) << "weft " << i;
    }
}

TEST(Pattern, MatrixIsDrawnTopRowFirst) {
    const Weave w = build(spec_of("pattern = \"matrix\"\nmatrix = \"110/011\""));
    ASSERT_EQ(w.warp_count, 3);
    ASSERT_EQ(w.weft_count, 2);
    // Top row (j = 1) "110", bottom row (j = 0) "011".
    EXPECT_TRUE(w.over(0, 1) && w.over(1, 1) && !w.over(2, 1));
    EXPECT_TRUE(!w.over(0, 0) && w.over(1, 0) && w.over(2, 0));
}

TEST(Pattern, ColourSequencesSetTheTileSize) {
    const Weave w = build(spec_of(
        "pattern = \"plain\"\nwarp_colors = \"aab\"\ncolor_a = [1, 0, 0]\ncolor_b = 0.25\n"));
    EXPECT_EQ(w.warp_count, 6);  // lcm(2, 3)
    EXPECT_EQ(w.weft_count, 2);
    ASSERT_EQ(w.yarns.size(), 8u);
    const char* expect = "aabaab";
    for (int i = 0; i < 6; ++i) {
        const Eigen::Vector3d c =
            expect[i] == 'a' ? Eigen::Vector3d(1, 0, 0) : Eigen::Vector3d::Constant(0.25);
        EXPECT_EQ(w.yarns[static_cast<size_t>(i)].albedo, c) << i;
    }
    EXPECT_EQ(w.yarns[6].albedo, w.spec.weft_albedo);
}

TEST(Yarn, CentreLinesPassThroughTheCrossingsAndTileExactly) {
    for (const char* text : {"pattern = \"plain\"", "pattern = \"twill\"\ntwill = [3, 1]",
                             "pattern = \"satin\"\nsatin = [5, 3]\ncrimp_mm = 0.13"}) {
        const Weave w = build(spec_of(text));
        for (const Yarn& y : w.yarns) {
            const int n = static_cast<int>(y.control_z_mm.size());
            for (int k = 0; k < n; ++k) {
                const double s = (k + 0.5) * y.knot_spacing_mm;
                const bool top =
                    y.set == ThreadSet::kWarp ? w.over(y.index, k) : !w.over(k, y.index);
                EXPECT_NEAR(y.z(s), top ? w.crimp_mm : -w.crimp_mm, kSolveTolMm) << text;
            }
            std::mt19937 rng(7);
            std::uniform_real_distribution<double> u(-5, 5);
            for (int t = 0; t < 50; ++t) {
                const double s = u(rng);
                for (int p = -2; p <= 2; ++p) {
                    EXPECT_NEAR(y.z(s + p * y.period_mm()), y.z(s), kSplineTolMm);
                    EXPECT_NEAR(y.dz_ds(s + p * y.period_mm()), y.dz_ds(s), kSplineTolMm);
                }
            }
        }
    }
}

TEST(Yarn, SegmentsJoinWithContinuousValueSlopeAndCurvature) {
    // At u = 1 of one segment and u = 0 of the next the basis functions, shifted by one
    // control point, give equal value, first and second derivatives (C2).
    const Eigen::Vector4d b1 = bspline_basis(1), b0 = bspline_basis(0);
    const Eigen::Vector4d d1 = bspline_basis_du(1), d0 = bspline_basis_du(0);
    const Eigen::Vector4d e1 = bspline_basis_du2(1), e0 = bspline_basis_du2(0);
    for (int m = 0; m < 3; ++m) {
        EXPECT_NEAR(b1[m + 1], b0[m], 1e-15);
        EXPECT_NEAR(d1[m + 1], d0[m], 1e-15);
        EXPECT_NEAR(e1[m + 1], e0[m], 1e-15);
    }
    EXPECT_NEAR(b1[0], 0, 1e-15);
    EXPECT_NEAR(d1[0], 0, 1e-15);
    EXPECT_NEAR(e1[0], 0, 1e-15);
    EXPECT_NEAR(b0.sum(), 1, 1e-15);  // partition of unity
    // The derivatives are those of the basis (central differences, error ~h^2 = 1e-10).
    for (double u : {0.1, 0.5, 0.9}) {
        const double h = 1e-5;
        EXPECT_LT(
            (bspline_basis_du(u) - (bspline_basis(u + h) - bspline_basis(u - h)) / (2 * h)).norm(),
            1e-9);
        EXPECT_LT(
            (bspline_basis_du2(u) - (bspline_basis_du(u + h) - bspline_basis_du(u - h)) / (2 * h))
                .norm(),
            1e-9);
    }
}

TEST(Yarn, ControlPointsDescribeTheSameCurveAndShiftByOnePeriod) {
    const Weave w = build(spec_of("pattern = \"twill\"\ntwill = [2, 1]\nweft_spacing_mm = 0.7"));
    for (const Yarn& y : w.yarns) {
        double s_start = 0;
        const auto cp = y.control_points(-0.3, 2.1, {0.0, 0.0}, &s_start);
        const int segments = static_cast<int>(cp.size()) - 3;
        EXPECT_LE(s_start, -0.3);
        EXPECT_GE(s_start + segments * y.knot_spacing_mm, 2.1);
        for (int k = 0; k < segments; ++k) {
            for (double u : {0.0, 0.37, 1.0}) {
                const Eigen::Vector4d b = bspline_basis(u);
                Eigen::Vector4d p = Eigen::Vector4d::Zero();
                for (int m = 0; m < 4; ++m) p += b[m] * cp[static_cast<size_t>(k + m)];
                const Eigen::Vector3d expect = y.point(s_start + (k + u) * y.knot_spacing_mm);
                EXPECT_LT((p.head<3>() - expect).norm(), kSplineTolMm);
                EXPECT_NEAR(p[3], y.radius_mm, kSplineTolMm);
            }
        }
        // The same window one period later: the same points moved by exactly one period.
        double s2 = 0;
        const double period = y.period_mm();
        const auto cp2 = y.control_points(-0.3 + period, 2.1 + period, {0.0, 0.0}, &s2);
        ASSERT_EQ(cp2.size(), cp.size());
        EXPECT_NEAR(s2, s_start + period, kSplineTolMm);
        const Eigen::Vector4d shift = y.set == ThreadSet::kWarp ? Eigen::Vector4d(0, period, 0, 0)
                                                                : Eigen::Vector4d(period, 0, 0, 0);
        for (size_t k = 0; k < cp.size(); ++k)
            EXPECT_LT((cp2[k] - cp[k] - shift).norm(), kSplineTolMm);
    }
}

TEST(Weave, DefaultCrimpMakesRoundYarnsTouchAtEveryCrossing) {
    const Weave w =
        build(spec_of("pattern = \"plain\"\nwarp_radius_mm = 0.15\nweft_radius_mm = 0.21"));
    for (int i = 0; i < w.warp_count; ++i) {
        for (int j = 0; j < w.weft_count; ++j) {
            const Yarn& warp = w.yarns[static_cast<size_t>(i)];
            const Yarn& weft = w.yarns[static_cast<size_t>(w.warp_count + j)];
            const Eigen::Vector3d a = warp.point((j + 0.5) * warp.knot_spacing_mm);
            const Eigen::Vector3d b = weft.point((i + 0.5) * weft.knot_spacing_mm);
            EXPECT_NEAR((a - b).norm(), 0.15 + 0.21, kSolveTolMm);  // axes meet where they cross
            EXPECT_NEAR(a.x(), b.x(), kSplineTolMm);
            EXPECT_NEAR(a.y(), b.y(), kSplineTolMm);
        }
    }
    EXPECT_LE(w.z_min_mm, -w.crimp_mm - 0.21);
    EXPECT_GE(w.z_max_mm, w.crimp_mm + 0.21);
}

TEST(Weave, SingleThreadWeaveHasStraightYarns) {
    const Weave w = build(spec_of("pattern = \"matrix\"\nmatrix = \"1\"\ncrimp_mm = 0.25"));
    ASSERT_EQ(w.yarns.size(), 2u);
    for (double s : {-1.3, 0.0, 0.2, 0.77}) {
        EXPECT_NEAR(w.yarns[0].z(s), 0.25, kSolveTolMm);
        EXPECT_NEAR(w.yarns[1].z(s), -0.25, kSolveTolMm);
    }
}

TEST(WeaveFile, SampleFabricsParse) {
    for (const char* name : {"wool-twill", "satin", "denim-plain"}) {
        const WeaveSpec s = load_weave(source_dir() + "/configs/fabrics/" + name + ".toml");
        EXPECT_EQ(s.name, name);
        const Weave w = build(s);
        EXPECT_GT(w.yarns.size(), 3u);
    }
}

TEST(WeaveFile, BadValuesNameTheKey) {
    using testing::error_of;
    EXPECT_NE(error_of([] { spec_of("patern = \"plain\""); }).find("unknown key 'patern'"),
              std::string::npos);
    EXPECT_NE(error_of([] { spec_of("pattern = \"felt\""); }).find("pattern"), std::string::npos);
    EXPECT_NE(
        error_of([] { spec_of("pattern = \"satin\"\nsatin = [6, 3]"); }).find("satin = [6, 3]"),
        std::string::npos);
    EXPECT_NE(error_of([] { spec_of("pattern = \"satin\"\nsatin = [5, 1]"); }).find("move"),
              std::string::npos);
    EXPECT_NE(
        error_of([] { spec_of("spacing_mm = 0.4\nyarn_radius_mm = 0.5"); }).find("warp_radius_mm"),
        std::string::npos);
    EXPECT_NE(error_of([] { spec_of("spacing_mm = nan"); }).find("spacing_mm"), std::string::npos);
    EXPECT_NE(error_of([] { spec_of("crimp_mm = -0.1"); }).find("crimp_mm"), std::string::npos);
    EXPECT_NE(error_of([] { spec_of("warp_colors = \"ab\"\ncolor_a = 0.3"); }).find("letter 'b'"),
              std::string::npos);
    EXPECT_NE(
        error_of([] { spec_of("pattern = \"matrix\"\nmatrix = \"10/1\""); }).find("equal length"),
        std::string::npos);
    EXPECT_NE(error_of([] { spec_of("[material]\nalbedo = 0.5"); }).find("warp_albedo"),
              std::string::npos);
    EXPECT_NE(error_of([] { spec_of("[yarn]\nx = 1"); }).find("unknown table [yarn]"),
              std::string::npos);
    EXPECT_NE(error_of([] { spec_of("[material]\nalpha = 2"); }).find("alpha"), std::string::npos);
    EXPECT_NE(error_of([] { spec_of("twill = [2.5, 1]\npattern = \"twill\""); }).find("integers"),
              std::string::npos);
}

}  // namespace
}  // namespace inlight::weave
