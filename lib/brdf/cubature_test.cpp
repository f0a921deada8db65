// Tests of the independent reference (brdf/cubature.h) against closed forms, and of the bake's
// warped Gauss-Legendre rule and its exact edge-on limit against that reference.
#include "brdf/cubature.h"

#include <gtest/gtest.h>

#include <cmath>

#include "brdf/bake.h"
#include "core/conventions.h"
#include "sh/sh.h"

namespace inlight::brdf {
namespace {

Material ggx(double alpha, double f0) {
    Material m;
    m.specular = Model::kGgx;
    m.alpha = alpha;
    m.f0 = Eigen::Vector3d::Constant(f0);
    return m;
}

Material report(double f, double r) {
    Material m;
    m.specular = Model::kCookTorranceReport;
    m.report_f = f;
    m.report_r = r;
    return m;
}

Material charlie(double alpha) {
    Material m;
    m.specular = Model::kCharlie;
    m.alpha = alpha;
    return m;
}

// Directional albedo integral f cos dw by the cubature alone (no bake code).
CubatureResult albedo_by_cubature(const Material& m, const Eigen::Vector3d& wo, double rel_tol) {
    CubatureOptions o;
    o.rel_tol = rel_tol;
    return hemisphere_cubature(
        [&](const Eigen::Vector3d& wi, double* out) {
            out[0] = eval_baked_lobe(m, wo, wi)[0] * wi.z();
        },
        1, {Eigen::Vector3d(-wo.x(), -wo.y(), wo.z())}, o);
}

// Polynomials over the hemisphere: integral cos^k = 2 pi / (k + 1); the degree-7 rule on 32
// boxes integrates cos^k sin(theta) (smooth) to rounding after a few splits.
constexpr double kPolynomialTol = 1e-12;

TEST(Cubature, IntegratesPolynomialsOverTheHemisphere) {
    for (int k : {0, 1, 2, 5}) {
        CubatureOptions o;
        o.rel_tol = 1e-14;
        const CubatureResult r = hemisphere_cubature(
            [&](const Eigen::Vector3d& w, double* out) { out[0] = std::pow(w.z(), k); }, 1, {}, o);
        EXPECT_TRUE(r.converged);
        EXPECT_NEAR(r.integral[0], 2 * kPi / (k + 1), kPolynomialTol) << "k " << k;
    }
}

// GGX alpha = 1, F = 1: D = 1/pi and G2 = 2 mu_o mu_i / (mu_o + mu_i), so the directional
// albedo is 1 - mu ln(1 + 1/mu) at view cosine mu (derived in docs/brdf.md). The cubature
// reaches its requested 1e-10 (its estimate is an upper bound), at an off-axis view.
constexpr double kAlbedoCubatureTol = 1e-10;

TEST(Cubature, GgxAlbedoAtAlphaOneMatchesClosedFormAtEveryView) {
    for (double mu : {1.0, 0.6, 0.3, 0.05}) {
        const Eigen::Vector3d wo(std::sqrt(1 - mu * mu) * std::cos(0.7),
                                 std::sqrt(1 - mu * mu) * std::sin(0.7), mu);
        const CubatureResult r = albedo_by_cubature(ggx(1.0, 1.0), wo, 1e-11);
        EXPECT_NEAR(r.integral[0], 1 - mu * std::log(1 + 1 / mu), kAlbedoCubatureTol) << mu;
    }
}

// The exact edge-on limit through the bake, against closed forms (docs/brdf.md): with F = 1,
// GGX (any alpha) has albedo 1 (Smith: integral D (w.h)+ dh = (1 + Lambda(w)) cos -> alpha/2
// at grazing) and the report's model r^2 / (1 + r^2) (half its unnormalised D, doubled).
// The edge-on rule is smooth in its variables: spectral convergence; 2 x 64 x 64 samples give
// rounding (measured 1e-13); the former n.v = 1e-6 substitution was 1.4e-5 off for GGX alpha 1.
constexpr double kEdgeOnClosedFormTol = 1e-11;

TEST(EdgeOn, AlbedoMatchesClosedForms) {
    BakeOptions o;
    o.sh_bands = 1;
    o.samples = 2 * 64 * 64;
    const Eigen::Vector3d n = view_from_deg(90, 37);  // edge-on under the default view +z
    for (double alpha : {1.0, 0.3, 0.1}) {
        EXPECT_NEAR(std::sqrt(4 * kPi) * project_normal(ggx(alpha, 1.0), n, o)(0, 0), 1.0,
                    kEdgeOnClosedFormTol)
            << "alpha " << alpha;
    }
    for (double r : {0.3, 1.0}) {
        EXPECT_NEAR(std::sqrt(4 * kPi) * project_normal(report(1.0, r), n, o)(0, 0),
                    r * r / (1 + r * r), kEdgeOnClosedFormTol)
            << "r " << r;
    }
}

// The limit is the limit of the BRDF: the cubature of the real eval_baked_lobe at n.v = t
// approaches the limit's albedo as t -> 0. The gap is O(t log(1/t)) (masking's correction is
// O(t) except where n.l < t), so from t = 1e-2 to 1e-4 it must fall by more than 20 (predicted
// ~50); a wrong limit (a lost factor) would leave a gap that does not fall.
TEST(EdgeOn, LimitIsTheLimitOfTheBrdf) {
    for (const Material& m : {ggx(0.3, 0.04), report(0.04, 0.3)}) {
        const Eigen::Vector3d wo0(std::cos(0.4), std::sin(0.4), 0);
        CubatureOptions o;
        o.rel_tol = 1e-9;
        const double limit = hemisphere_cubature_about_horizon(
                                 [&](const Eigen::Vector3d& wi, double* out) {
                                     out[0] = eval_baked_lobe_edge_on(m, wo0, wi)[0] * wi.z();
                                 },
                                 1, -wo0, o)
                                 .integral[0];
        std::vector<double> gap;
        for (double t : {1e-2, 1e-4}) {
            const Eigen::Vector3d wo =
                Eigen::Vector3d(wo0.x(), wo0.y(), t / std::sqrt(1 - t * t)).normalized();
            gap.push_back(std::abs(albedo_by_cubature(m, wo, 1e-9).integral[0] - limit));
        }
        EXPECT_GT(gap[0], 0.0);
        EXPECT_LT(gap[1], gap[0] / 20) << to_string(m.specular) << " limit " << limit;
    }
}

// The warped Gauss-Legendre rule against the independent cubature: all 64 coefficients (8
// bands) at off-axis normals and views, for every warp (GGX, the report's, Charlie) and at an
// edge-on normal. Tolerance, relative to the largest coefficient and computed per case: the
// cubature's own error estimate plus GL's error bound from self-convergence: with error(n) ~
// n^-p, error(n) = d / (1 - 2^-p), d = |GL(n) - GL(2n)|; 4 d covers every p >= 0.42 (GL is
// spectral where the integrand is smooth; the report's min() in G and Charlie's substituted
// n.v = 1e-6 make it algebraic, measured p ~ 1.3, and this term says by how much). A wrong warp or
// Jacobian converges, to the wrong value: GL(n) = GL(2n) and the cubature disagrees.
TEST(GaussLegendre, AgreesWithIndependentCubatureForEveryWarp) {
    BakeOptions o, fine;
    o.sh_bands = fine.sh_bands = kMaxBakeBands;
    o.samples = 2 * 64 * 64;
    fine.samples = 2 * 128 * 128;
    ValidateOptions v;
    v.reference_rel_tol = 1e-8;  // its estimate enters the tolerance, converged or not
    for (const Material& m : {ggx(0.3, 0.04), report(0.04, 0.3), charlie(0.4)}) {
        for (const auto& [view, n] : {std::pair{view_from_deg(35, 20), view_from_deg(50, 150)},
                                      std::pair{view_from_deg(70, -60), view_from_deg(25, 40)},
                                      std::pair{view_from_deg(0, 0), view_from_deg(90, 80)}}) {
            o.view = fine.view = view;
            const Eigen::MatrixXd gl = project_normal(m, n, o);
            const Eigen::MatrixXd gl_fine = project_normal(m, n, fine);
            const ReferenceNormal ref = reference_normal(m, n, view, v);
            const double scale = ref.coeffs.cwiseAbs().maxCoeff();
            ASSERT_GT(scale, 0);
            const double tol = (ref.error + 4 * (gl - gl_fine).cwiseAbs().maxCoeff()) / scale;
            EXPECT_LT((gl - ref.coeffs).cwiseAbs().maxCoeff() / scale, tol)
                << to_string(m.specular) << " n " << n.transpose() << " view " << view.transpose();
            EXPECT_LT(tol, 1e-4) << "the check must stay sharp: " << to_string(m.specular);
        }
    }
}

// Sobol IS at an edge-on normal samples the limit (GGX by visible normals at grazing): its
// B_00 is unbiased, so with 2^16 points it lands within 5 standard errors of the exact albedo
// 1 (GGX F = 1). Standard error: the weight F/pdf ratio is 1 here (pdf = D / (2 alpha) = the
// lobe), so the estimator of sqrt(4 pi) B_00 is exactly 1 for every valid sample.
constexpr double kEdgeOnSobolTol = 1e-12;

TEST(EdgeOn, SobolIsSamplesTheLimitExactly) {
    BakeOptions o;
    o.sh_bands = 1;
    o.samples = 1 << 12;
    o.integrator = Integrator::kSobolIs;
    for (double alpha : {1.0, 0.3}) {
        EXPECT_NEAR(
            std::sqrt(4 * kPi) * project_normal(ggx(alpha, 1.0), view_from_deg(90, -20), o)(0, 0),
            1.0, kEdgeOnSobolTol);
    }
}

}  // namespace
}  // namespace inlight::brdf
