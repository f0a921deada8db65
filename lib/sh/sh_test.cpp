// Tests of lib/sh against closed forms, quadrature and R&H 2001.
#include <algorithm>
#include <cmath>
#include <functional>
#include <cstring>
#include <fstream>
#include <random>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>

#include "core/conventions.h"
#include "core/error.h"
#include "core/parallel.h"
#include "sh/fit.h"
#include "sh/quadrature.h"
#include "sh/sh.h"
#include "sh/sh_io.h"
#include "testing/testing.h"

namespace inlight::sh {
namespace {

// Closed forms and recurrence agree to a few ulps of O(1) values.
constexpr double kClosedFormTol = 1e-13;
// The issue asks orthonormality by quadrature to 1e-10; an exact rule reaches ~1e-14.
constexpr double kOrthoTol = 1e-10;

Eigen::Vector3d random_dir(std::mt19937_64& rng) {
    std::normal_distribution<double> g;
    Eigen::Vector3d d(g(rng), g(rng), g(rng));
    return d.normalized();
}

// Real SH without Condon-Shortley phase (Wikipedia's real table, r = 1), l <= 4.
std::vector<double> closed_form(const Eigen::Vector3d& d) {
    const double x = d.x(), y = d.y(), z = d.z(), pi = kPi;
    return {
        0.5 * std::sqrt(1 / pi),
        std::sqrt(3 / (4 * pi)) * y,
        std::sqrt(3 / (4 * pi)) * z,
        std::sqrt(3 / (4 * pi)) * x,
        0.5 * std::sqrt(15 / pi) * x * y,
        0.5 * std::sqrt(15 / pi) * y * z,
        0.25 * std::sqrt(5 / pi) * (3 * z * z - 1),
        0.5 * std::sqrt(15 / pi) * x * z,
        0.25 * std::sqrt(15 / pi) * (x * x - y * y),
        0.25 * std::sqrt(35 / (2 * pi)) * (3 * x * x - y * y) * y,
        0.5 * std::sqrt(105 / pi) * x * y * z,
        0.25 * std::sqrt(21 / (2 * pi)) * y * (5 * z * z - 1),
        0.25 * std::sqrt(7 / pi) * (5 * z * z * z - 3 * z),
        0.25 * std::sqrt(21 / (2 * pi)) * x * (5 * z * z - 1),
        0.25 * std::sqrt(105 / pi) * (x * x - y * y) * z,
        0.25 * std::sqrt(35 / (2 * pi)) * (x * x - 3 * y * y) * x,
        0.75 * std::sqrt(35 / pi) * x * y * (x * x - y * y),
        0.75 * std::sqrt(35 / (2 * pi)) * (3 * x * x - y * y) * y * z,
        0.75 * std::sqrt(5 / pi) * x * y * (7 * z * z - 1),
        0.75 * std::sqrt(5 / (2 * pi)) * y * z * (7 * z * z - 3),
        3.0 / 16.0 * std::sqrt(1 / pi) * (35 * z * z * z * z - 30 * z * z + 3),
        0.75 * std::sqrt(5 / (2 * pi)) * x * z * (7 * z * z - 3),
        3.0 / 8.0 * std::sqrt(5 / pi) * (x * x - y * y) * (7 * z * z - 1),
        0.75 * std::sqrt(35 / (2 * pi)) * (x * x - 3 * y * y) * x * z,
        3.0 / 16.0 * std::sqrt(35 / pi) * (x * x * (x * x - 3 * y * y) - y * y * (3 * x * x - y * y)),
    };
}

TEST(ShEval, MatchesClosedFormsUpToBandFour) {
    std::mt19937_64 rng(7);
    std::vector<Eigen::Vector3d> dirs = {{0, 0, 1}, {0, 0, -1}, {1, 0, 0}, {0, -1, 0}};
    for (int i = 0; i < 200; ++i) dirs.push_back(random_dir(rng));
    for (const auto& d : dirs) {
        const auto ref = closed_form(d);
        const auto y = eval(5, d);
        for (int k = 0; k < 25; ++k) EXPECT_NEAR(y[k], ref[k], kClosedFormTol) << "k=" << k;
    }
}

TEST(ShEval, ConventionHasNoCondonShortleyPhase) {
    // R&H 2001: Y_1,1 = +0.488603 x (the inlight report's Figure 6 has -0.4886 x).
    const auto y = eval(3, Eigen::Vector3d(1, 0, 0));
    EXPECT_NEAR(y[index(1, 1)], 0.488603, 1e-6);
    EXPECT_NEAR(eval(3, Eigen::Vector3d(0, 1, 0))[index(1, -1)], 0.488603, 1e-6);
    const Eigen::Vector3d d = Eigen::Vector3d(1, 1, 0).normalized();
    EXPECT_NEAR(eval(3, d)[index(2, -2)], 1.092548 * 0.5, 1e-6);
}

TEST(ShEval, OrthonormalBySixteenBandQuadrature) {
    const int bands = 16, n = count(bands);
    // Gauss-Legendre in z (17 nodes: exact to degree 33 >= 30) x 34 uniform phi (exact for
    // trigonometric degree < 34 >= 30): the rule integrates every product Y_a Y_b exactly.
    std::vector<double> z, wz;
    gauss_legendre(17, z, wz);
    const int nphi = 34;
    Eigen::MatrixXd gram = Eigen::MatrixXd::Zero(n, n);
    Eigen::VectorXd y(n);
    for (size_t i = 0; i < z.size(); ++i) {
        for (int j = 0; j < nphi; ++j) {
            const double phi = 2 * kPi * (j + 0.5) / nphi;
            const double s = std::sqrt(1 - z[i] * z[i]);
            eval(bands, Eigen::Vector3d(s * std::cos(phi), s * std::sin(phi), z[i]), y.data());
            gram += (wz[i] * 2 * kPi / nphi) * y * y.transpose();
        }
    }
    EXPECT_LT((gram - Eigen::MatrixXd::Identity(n, n)).cwiseAbs().maxCoeff(), kOrthoTol);
}

TEST(ShEval, StableAtHighBandsAndPoles) {
    // Y_l0 at the north pole is sqrt((2l+1)/(4pi)); every other order vanishes there.
    const int bands = kMaxBands;
    const auto y = eval(bands, Eigen::Vector3d(0, 0, 1));
    for (int l = 0; l < bands; ++l) {
        EXPECT_NEAR(y[index(l, 0)], std::sqrt((2 * l + 1) / (4 * kPi)), 1e-12 * (l + 1));
        for (int m = 1; m <= l; ++m) {
            EXPECT_EQ(y[index(l, m)], 0.0);
            EXPECT_EQ(y[index(l, -m)], 0.0);
        }
    }
    std::mt19937_64 rng(3);
    for (int i = 0; i < 50; ++i) {
        for (double v : eval(bands, random_dir(rng))) ASSERT_TRUE(std::isfinite(v));
    }
}

TEST(CosineZonal, MatchesQuadratureOfClampedCosine) {
    // A_l = 2 pi * integral_0^1 t P_l(t) dt; Gauss-Legendre on [0, 1] is exact (degree l + 1).
    std::vector<double> t, w;
    gauss_legendre(40, t, w);
    for (int l = 0; l <= 30; ++l) {
        double integral = 0;
        for (size_t i = 0; i < t.size(); ++i) {
            const double x = 0.5 * (t[i] + 1);  // map [-1,1] -> [0,1]
            double p0 = 1, p1 = x, pl = l == 0 ? 1 : x;
            for (int k = 2; k <= l; ++k) {
                pl = ((2.0 * k - 1) * x * p1 - (k - 1.0) * p0) / k;
                p0 = p1;
                p1 = pl;
            }
            integral += 0.5 * w[i] * x * pl;
        }
        EXPECT_NEAR(cosine_zonal(l), 2 * kPi * integral, 1e-13) << "l=" << l;
    }
    EXPECT_NEAR(cosine_zonal(4), -kPi / 24, 1e-15);
}

TEST(IrradianceMatrix, EqualsZonalConvolutionOfSameCoefficients) {
    // E(n) = n^T M n (R&H eq. 12) and sum A_l L_lm Y_lm(n) must agree when both use the same
    // (phase-free) basis; with the report's phased basis they would not.
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> u(-1, 1);
    for (int trial = 0; trial < 20; ++trial) {
        double L[9];
        for (double& c : L) c = u(rng);
        const Eigen::Matrix4d m = irradiance_matrix(L);
        EXPECT_EQ((m - m.transpose()).cwiseAbs().maxCoeff(), 0.0);  // exactly symmetric
        for (int i = 0; i < 20; ++i) {
            const Eigen::Vector3d n = random_dir(rng);
            const Eigen::Vector4d n4(n.x(), n.y(), n.z(), 1.0);
            EXPECT_NEAR(n4.dot(m * n4), irradiance(3, L, n), 1e-13);
        }
    }
    // The paper's printed constants, to their 6 digits.
    double unit[9] = {0, 0, 0, 0, 0, 0, 0, 0, 1};  // L22 = 1
    EXPECT_NEAR(irradiance_matrix(unit)(0, 0), 0.429043, 1e-6);
    double l11[9] = {0, 0, 0, 1, 0, 0, 0, 0, 0};
    EXPECT_NEAR(irradiance_matrix(l11)(0, 3), 0.511664, 1e-6);
    double l00[9] = {1, 0, 0, 0, 0, 0, 0, 0, 0};
    EXPECT_NEAR(irradiance_matrix(l00)(3, 3), 0.886227, 1e-6);
}

TEST(Window, HannAndLanczosFactors) {
    EXPECT_EQ(window_factor(Window::kNone, 5, 9), 1.0);
    EXPECT_EQ(window_factor(Window::kHann, 0, 9), 1.0);
    EXPECT_NEAR(window_factor(Window::kHann, 3, 6), 0.5, 1e-15);
    EXPECT_NEAR(window_factor(Window::kLanczos, 3, 6), 2 / kPi, 1e-15);
    EXPECT_THROW(window_from_string("box"), Error);
}

TEST(Window, ApplyWindowScalesEachBandByItsFactor) {
    // Band l occupies rows l^2 .. l^2 + 2l. Factors written out: Hann with 4 bands,
    // (1 + cos(pi l / 4)) / 2 = 1, (2 + sqrt 2) / 4, 1/2, (2 - sqrt 2) / 4; Lanczos with 3 bands,
    // sin(pi l / 3) / (pi l / 3) = 1, (3 sqrt 3 / 2) / pi, (3 sqrt 3 / 4) / pi.
    const double hann[4] = {1, (2 + std::sqrt(2.0)) / 4, 0.5, (2 - std::sqrt(2.0)) / 4};
    const double lanczos[3] = {1, 1.5 * std::sqrt(3.0) / kPi, 0.75 * std::sqrt(3.0) / kPi};
    Eigen::MatrixXd c = Eigen::MatrixXd::Ones(16, 2);
    c.col(1) *= -3;
    apply_window(Window::kHann, 4, c);
    for (int k = 0; k < 16; ++k) {
        const int l = k < 1 ? 0 : k < 4 ? 1 : k < 9 ? 2 : 3;
        EXPECT_NEAR(c(k, 0), hann[l], 1e-15) << k;
        EXPECT_NEAR(c(k, 1), -3 * hann[l], 1e-15) << k;
    }
    Eigen::MatrixXd d = Eigen::MatrixXd::Ones(9, 1);
    apply_window(Window::kLanczos, 3, d);
    for (int k = 0; k < 9; ++k) EXPECT_NEAR(d(k, 0), lanczos[k < 1 ? 0 : k < 4 ? 1 : 2], 1e-15);
    Eigen::MatrixXd e = Eigen::MatrixXd::Constant(9, 3, 0.7);
    apply_window(Window::kNone, 3, e);
    EXPECT_EQ(e, Eigen::MatrixXd::Constant(9, 3, 0.7));
}

// A sample set of Gauss-Legendre x uniform-phi nodes restricted to a cap around +z.
class CapSamples : public SampleSet {
  public:
    CapSamples(double half_angle, std::function<double(const Eigen::Vector3d&)> f)
        : m_f(std::move(f)) {
        gauss_legendre(96, m_z, m_wz);
        m_cos_max = std::cos(half_angle);
    }
    int64_t size() const override { return int64_t(m_z.size()) * kPhi; }
    int channels() const override { return 1; }
    bool sample(int64_t i, Eigen::Vector3d& dir, double& w, double* v) const override {
        const size_t iz = size_t(i / kPhi);
        const double z = m_z[iz], phi = 2 * kPi * (double(i % kPhi) + 0.5) / kPhi;
        if (z < m_cos_max) return false;
        const double s = std::sqrt(1 - z * z);
        dir = {s * std::cos(phi), s * std::sin(phi), z};
        w = m_wz[iz] * 2 * kPi / kPhi;
        v[0] = m_f(dir);
        return true;
    }

  private:
    static constexpr int kPhi = 192;
    std::function<double(const Eigen::Vector3d&)> m_f;
    std::vector<double> m_z, m_wz;
    double m_cos_max;
};

// G = sum w y y^T and b = sum w f y over a one-channel sample set, 3 bands, accumulated here.
void normal_equations(const SampleSet& set, Eigen::MatrixXd& gram, Eigen::VectorXd& rhs) {
    gram = Eigen::MatrixXd::Zero(9, 9);
    rhs = Eigen::VectorXd::Zero(9);
    for (int64_t i = 0; i < set.size(); ++i) {
        Eigen::Vector3d d;
        double w, v;
        if (!set.sample(i, d, w, &v)) continue;
        Eigen::VectorXd y(9);
        eval(3, d, y.data());
        gram += w * y * y.transpose();
        rhs += w * v * y;
    }
}

// fit.h's smoothness penalty, (l (l + 1))^2 per coefficient, for 3 bands.
Eigen::VectorXd smoothness_penalty_3bands() {
    Eigen::VectorXd p(9);
    for (int k = 0; k < 9; ++k) {
        const int l = k < 1 ? 0 : k < 4 ? 1 : 2;
        p[k] = double(l * (l + 1)) * (l * (l + 1));
    }
    return p;
}

TEST(Fit, FullSphereProjectionIsExactForBandLimitedFunction) {
    std::vector<double> truth(9);
    for (int k = 0; k < 9; ++k) truth[k] = 0.1 * (k + 1) * (k % 2 ? -1 : 1);
    auto f = [&](const Eigen::Vector3d& d) {
        const auto y = eval(3, d);
        double s = 0;
        for (int k = 0; k < 9; ++k) s += truth[k] * y[k];
        return s;
    };
    const CapSamples sphere(kPi, f);
    const Eigen::MatrixXd c = project(3, sphere);
    for (int k = 0; k < 9; ++k) EXPECT_NEAR(c(k, 0), truth[k], 1e-12);
}

TEST(Fit, PartialSphereLeastSquaresRecoversWhatProjectionLoses) {
    // A 165-degree field of view (half angle 82.5 deg) sees 56% of the sphere. For a function
    // that is exactly band-limited to 3 bands, the unregularised fit recovers it; the
    // projection that takes the unseen part as black does not.
    std::vector<double> truth = {2.0, 0.3, 0.8, -0.4, 0.1, 0.2, 0.25, -0.15, 0.05};
    auto f = [&](const Eigen::Vector3d& d) {
        const auto y = eval(3, d);
        double s = 0;
        for (int k = 0; k < 9; ++k) s += truth[k] * y[k];
        return s;
    };
    const CapSamples cap(82.5 * kPi / 180, f);
    FitOptions exact;
    exact.lambda = 0;
    const FitResult fit = fit_least_squares(3, cap, exact);
    const Eigen::MatrixXd proj = project(3, cap);
    double fit_err = 0, proj_err = 0;
    for (int k = 0; k < 9; ++k) {
        fit_err = std::max(fit_err, std::abs(fit.coeffs(k, 0) - truth[k]));
        proj_err = std::max(proj_err, std::abs(proj(k, 0) - truth[k]));
    }
    // Tolerance: conditioning (reported below, ~1e2) times double rounding of 1e5 samples.
    EXPECT_LT(fit_err, 1e-9);
    EXPECT_GT(proj_err, 0.3);  // the zero-filled half of the sphere costs a large error
    // The rule's rings do not align with the cap's edge: allow one ring (max weight * 2 pi).
    std::vector<double> z, wz;
    gauss_legendre(96, z, wz);
    const double ring_sr = 2 * kPi * *std::max_element(wz.begin(), wz.end());
    EXPECT_NEAR(fit.observed_solid_angle_sr, 2 * kPi * (1 - std::cos(82.5 * kPi / 180)), ring_sr);
    EXPECT_GT(fit.gram_condition, 1.0);
    EXPECT_LT(fit.weighted_residual_rms, 1e-9);
    std::printf("165-deg cap, 3 bands: Gram condition %.1f, max coeff error fit %.2e vs "
                "zero-fill projection %.3f\n",
                fit.gram_condition, fit_err, proj_err);
    // With the default regulariser the fit is biased towards smoothness, by a known amount: for
    // f in the span, c = (G + P)^-1 G c*, so the bias is c* - c = (G + P)^-1 P c* exactly,
    // P = lambda ev_max(G) diag((l (l + 1))^2), with G accumulated here. Tolerance: the sums'
    // rounding (1e-13 relative over 1e4 samples) times the condition number of G + P (< 1e3).
    const FitResult reg = fit_least_squares(3, cap);
    Eigen::MatrixXd gram;
    Eigen::VectorXd rhs;
    normal_equations(cap, gram, rhs);
    const Eigen::VectorXd c_true = Eigen::Map<const Eigen::VectorXd>(truth.data(), 9);
    const double ev_max = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(gram).eigenvalues().maxCoeff();
    const Eigen::MatrixXd penalty =
        (FitOptions{}.lambda * ev_max * smoothness_penalty_3bands()).asDiagonal();
    const Eigen::VectorXd bias = (gram + penalty).ldlt().solve(penalty * c_true);
    EXPECT_LT((reg.coeffs.col(0) - (c_true - bias)).norm(), 1e-10 * c_true.norm());
    EXPECT_GT(bias.norm(), 1e-3);  // the penalty acts: the comparison above has power
    std::printf("default lambda: bias %.2e, predicted %.2e\n", (c_true - reg.coeffs.col(0)).norm(),
                bias.norm());
    EXPECT_LT(reg.regularised_condition, fit.gram_condition);
}

TEST(Fit, LeastSquaresPathSolvesEachRegularisedSystem) {
    // fit_least_squares_path against the definition it documents: for each lambda, the
    // coefficients solve (G + lambda ev_max(G) D) c = b with G = sum w y y^T, b = sum w f y and
    // D = diag((l (l + 1))^2), all accumulated here independently. Tikhonov regularisation makes
    // the penalty c^T D c non-increasing and the weighted residual non-decreasing in lambda.
    std::vector<double> truth = {2.0, 0.3, 0.8, -0.4, 0.1, 0.2, 0.25, -0.15, 0.05};
    auto f = [&](const Eigen::Vector3d& d) {
        const auto y = eval(3, d);
        double s = 0;
        for (int k = 0; k < 9; ++k) s += truth[k] * y[k];
        return s + 0.3 * d.x() * d.y() * d.z();  // plus a band-3 part the fit cannot hold
    };
    const CapSamples cap(82.5 * kPi / 180, f);
    Eigen::MatrixXd gram;
    Eigen::VectorXd rhs;
    normal_equations(cap, gram, rhs);
    const double ev_max = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(gram).eigenvalues().maxCoeff();
    const Eigen::VectorXd penalty_diag = smoothness_penalty_3bands();
    const std::vector<double> lambdas = {0, 1e-4, 1e-2, 1};
    const auto path = fit_least_squares_path(3, cap, lambdas);
    ASSERT_EQ(path.size(), lambdas.size());
    double prev_penalty = INFINITY, prev_residual = 0;
    for (size_t j = 0; j < lambdas.size(); ++j) {
        ASSERT_EQ(path[j].coeffs.rows(), 9);
        EXPECT_EQ(path[j].lambda, lambdas[j]);
        const Eigen::VectorXd c = path[j].coeffs.col(0);
        const Eigen::MatrixXd a =
            gram + Eigen::MatrixXd(lambdas[j] * ev_max * penalty_diag.asDiagonal());
        // Normal-equation residual: rounding of sums over 1e4 samples times |A| |c|.
        EXPECT_LT((a * c - rhs).norm(), 1e-11 * a.norm() * c.norm()) << "lambda " << lambdas[j];
        const double penalty = c.dot(penalty_diag.asDiagonal() * c);
        EXPECT_LE(penalty, prev_penalty * (1 + 1e-12)) << "lambda " << lambdas[j];
        EXPECT_GE(path[j].weighted_residual_rms, prev_residual * (1 - 1e-12)) << lambdas[j];
        prev_penalty = penalty;
        prev_residual = path[j].weighted_residual_rms;
        // One pass for several lambdas gives what separate fits give.
        FitOptions one;
        one.lambda = lambdas[j];
        EXPECT_LT((fit_least_squares(3, cap, one).coeffs - path[j].coeffs).cwiseAbs().maxCoeff(),
                  1e-12);
    }
}

// One observed direction: 9 unknowns from one sample.
class OneSample : public SampleSet {
  public:
    int64_t size() const override { return 1; }
    int channels() const override { return 1; }
    bool sample(int64_t, Eigen::Vector3d& dir, double& w, double* v) const override {
        dir = Eigen::Vector3d(0.48, 0.6, 0.64);
        w = 0.01;
        v[0] = 1;
        return true;
    }
};

TEST(Fit, LeastSquaresPathLeavesSingularEntriesEmpty) {
    // Without the penalty one sample cannot fix 9 coefficients; with it bands 1 and 2 are held
    // by the penalty and band 0 by the sample, so the system is regular.
    const auto path = fit_least_squares_path(3, OneSample(), {0, 1e-2});
    ASSERT_EQ(path.size(), 2u);
    EXPECT_EQ(path[0].coeffs.size(), 0);
    EXPECT_EQ(path[1].coeffs.rows(), 9);
    EXPECT_THROW(fit_least_squares(3, OneSample(), FitOptions{0}), Error);
}

TEST(ShIo, ReadCoefficientsDecodesTheDocumentedBinaryAndJson) {
    // Files written by hand from docs/formats.md (not with write_binary / to_json): binary is
    // "INLSH\0\0\1", uint32 sh_bands, channels, 0, then float32 coefficients k-major, all
    // little-endian.
    const std::string dir = inlight::testing::temp_dir("sh_io");
    const float values[4][2] = {{1.5f, -2.0f}, {0.25f, 3.0f}, {-0.125f, 0.0f}, {7.0f, 0.5f}};
    std::string bytes("INLSH\0\0\1", 8);
    auto put = [&](uint32_t u) {
        for (int i = 0; i < 4; ++i) bytes.push_back(char((u >> (8 * i)) & 0xff));
    };
    put(2);
    put(2);
    put(0);
    for (const auto& row : values) {
        for (float v : row) {
            uint32_t u;
            std::memcpy(&u, &v, 4);
            put(u);
        }
    }
    {
        std::ofstream(dir + "/c.bin", std::ios::binary) << bytes;
    }
    const CoefficientSet b = read_coefficients(dir + "/c.bin");
    ASSERT_EQ(b.sh_bands, 2);
    ASSERT_EQ(b.coeffs.rows(), 4);
    ASSERT_EQ(b.coeffs.cols(), 2);
    for (int k = 0; k < 4; ++k) {
        for (int c = 0; c < 2; ++c) EXPECT_EQ(b.coeffs(k, c), values[k][c]) << k << "," << c;
    }
    std::ofstream(dir + "/c.json") << R"({"format": "inlight.sh_coefficients", "version": 1,
        "sh_bands": 2, "channels": ["r", "g"], "color_space": "acescg",
        "coefficients": [[1.5, -2], [0.25, 3], [-0.125, 0], [7, 0.5]]})";
    const CoefficientSet j = read_coefficients(dir + "/c.json");
    EXPECT_EQ(j.coeffs, b.coeffs);
    EXPECT_EQ(j.color_space, "acescg");
    EXPECT_EQ(j.channel_names, (std::vector<std::string>{"r", "g"}));
    // Errors name the file and the problem.
    std::ofstream(dir + "/short.bin", std::ios::binary) << bytes.substr(0, bytes.size() - 4);
    EXPECT_NE(inlight::testing::error_of([&] { read_coefficients(dir + "/short.bin"); })
                  .find("short.bin: size 48 bytes does not match the header"),
              std::string::npos);
    std::ofstream(dir + "/bad.json") << "{";
    EXPECT_NE(inlight::testing::error_of([&] { read_coefficients(dir + "/bad.json"); })
                  .find("bad.json: not valid JSON"),
              std::string::npos);
    EXPECT_NE(inlight::testing::error_of([&] { read_coefficients(dir + "/c.txt"); })
                  .find("c.txt: expected a .json or .bin"),
              std::string::npos);
}

// Seen by reading, confirmed with fuzz/sh_fuzz.cpp (UBSan): "sh_bands": 1e300 went through
// nlohmann's get<int>(), a float-to-int conversion out of range; 2^32 + 3 would have read as 3.
TEST(ShIo, ShBandsMustBeAnIntegerInRange) {
    const std::string dir = inlight::testing::temp_dir("sh_io_bands");
    for (const char* bands : {"1e300", "2.5", "4294967299", "-1", "\"3\""}) {
        std::ofstream(dir + "/c.json") << R"({"format": "inlight.sh_coefficients", "sh_bands": )"
                                       << bands << R"(, "channels": ["r"], "coefficients": [[1]]})";
        EXPECT_NE(inlight::testing::error_of([&] { read_coefficients(dir + "/c.json"); })
                      .find("c.json: sh_bands must be an integer in [1, "),
                  std::string::npos)
            << bands;
    }
}

TEST(Fit, NothingObservedIsAnError) {
    const CapSamples none(0.0, [](const Eigen::Vector3d&) { return 1.0; });
    EXPECT_THROW(fit_least_squares(3, none), Error);
}

TEST(Fit, IdenticalForAnyThreadCount) {
    const CapSamples cap(1.2, [](const Eigen::Vector3d& d) { return std::exp(3 * d.x()); });
    parallel::set_thread_count(1);
    const Eigen::MatrixXd one = project(6, cap);
    const FitResult f1 = fit_least_squares(6, cap);
    parallel::set_thread_count(2);
    const Eigen::MatrixXd two = project(6, cap);
    const FitResult f2 = fit_least_squares(6, cap);
    parallel::set_thread_count(0);
    EXPECT_EQ((one - two).cwiseAbs().maxCoeff(), 0.0);
    EXPECT_EQ((f1.coeffs - f2.coeffs).cwiseAbs().maxCoeff(), 0.0);
}

}  // namespace
}  // namespace inlight::sh
