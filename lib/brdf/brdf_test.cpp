// Tests of the BRDF models (brdf/brdf.h) against closed forms, quadrature and sampling statistics.
#include "brdf/brdf.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <random>

#include "brdf/cubature.h"
#include "core/conventions.h"
#include "core/error.h"
#include "sh/quadrature.h"
#include "testing/testing.h"

namespace inlight::brdf {
namespace {

// Gauss-Legendre in cos(theta) x uniform phi over the upper hemisphere (phi rule exact for
// trigonometric polynomials of degree < n_phi).
double hemisphere_integral(int n_cos, int n_phi,
                           const std::function<double(const Eigen::Vector3d&)>& f) {
    std::vector<double> x, w;
    sh::gauss_legendre(n_cos, x, w);
    double sum = 0;
    for (int i = 0; i < n_cos; ++i) {
        const double c = 0.5 * (x[i] + 1.0);
        const double s = std::sqrt(std::max(0.0, 1.0 - c * c));
        for (int j = 0; j < n_phi; ++j) {
            const double phi = 2.0 * kPi * (j + 0.5) / n_phi;
            sum += 0.5 * w[i] * (2.0 * kPi / n_phi) *
                   f(Eigen::Vector3d(s * std::cos(phi), s * std::sin(phi), c));
        }
    }
    return sum;
}

Eigen::Vector3d dir(double theta_deg, double phi_deg) {
    return direction_from_spherical(theta_deg * kPi / 180, phi_deg * kPi / 180);
}

// Uniform direction on the whole sphere.
Eigen::Vector3d from_spherical_uniform(double u1, double u2) {
    const double z = 1 - 2 * u1, r = std::sqrt(std::max(0.0, 1 - z * z));
    return {r * std::cos(2 * kPi * u2), r * std::sin(2 * kPi * u2), z};
}

Material with_model(Model model, double alpha = 0.3) {
    Material m;
    m.specular = model;
    m.alpha = alpha;
    m.report_r = alpha;
    return m;
}

const Model kAllModels[] = {Model::kLambert, Model::kCookTorranceReport, Model::kGgx,
                            Model::kCharlie};

// Polynomial integrands (cos * constant) are exact in 8-node GL up to rounding.
constexpr double kExactQuadTol = 1e-13;

TEST(Lambert, WhiteFurnaceIsOne) {
    Material m;
    m.specular = Model::kLambert;
    m.albedo = Eigen::Vector3d::Ones();
    for (const Eigen::Vector3d& wo : {dir(0, 0), dir(60, 30), dir(89, 200)}) {
        const double e = hemisphere_integral(
            8, 8, [&](const Eigen::Vector3d& wi) { return eval(m, wo, wi)[1] * wi.z(); });
        EXPECT_NEAR(e, 1.0, kExactQuadTol);
    }
}

// GGX, alpha = 1, wo = +z, F = 1: f cos = G1(wi) / (4 pi) = c / (2 pi (1 + c)), whose integral is
// 1 - ln 2. The integrand's pole at c = -1 gives GL convergence ~ (3 + sqrt 8)^(-2n): 64 nodes
// are exact to rounding; the phi rule is exact (no phi dependence).
constexpr double kGgxAlbedoTol = 1e-12;

TEST(Ggx, SingleScatterAlbedoAtAlphaOneIsOneMinusLn2) {
    Material m = with_model(Model::kGgx, 1.0);
    m.albedo.setZero();
    m.f0 = Eigen::Vector3d::Ones();
    const double e = hemisphere_integral(64, 4, [&](const Eigen::Vector3d& wi) {
        return eval(m, Eigen::Vector3d::UnitZ(), wi)[0] * wi.z();
    });
    EXPECT_NEAR(e, 1.0 - std::log(2.0), kGgxAlbedoTol);
}

// Reciprocity holds to rounding of the (symmetric) formulas.
constexpr double kReciprocityRelTol = 1e-12;

TEST(AllModels, ReciprocalAndNonNegative) {
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(0, 1);
    for (Model model : kAllModels) {
        for (double alpha : {0.05, 0.3, 1.0}) {
            const Material m = with_model(model, alpha);
            for (int k = 0; k < 2000; ++k) {
                const Eigen::Vector3d a = from_spherical_uniform(u(rng), u(rng));
                const Eigen::Vector3d b = from_spherical_uniform(u(rng), u(rng));
                const Eigen::Vector3d fab = eval(m, a, b), fba = eval(m, b, a);
                for (int c = 0; c < 3; ++c) {
                    ASSERT_GE(fab[c], 0.0) << to_string(model);
                    ASSERT_TRUE(std::isfinite(fab[c])) << to_string(model);
                    ASSERT_NEAR(fab[c], fba[c], kReciprocityRelTol * std::max(1.0, fab[c]))
                        << to_string(model) << " alpha " << alpha;
                }
                if (a.z() <= 0 || b.z() <= 0) {
                    ASSERT_EQ(fab.norm(), 0.0);
                }
            }
        }
    }
}

// Integral of D (N.H) over the hemisphere of h: 1 for a normalised NDF; the report's D gives
// r^2 / (1 + r^2). 512 GL nodes resolve the alpha = 0.1 GGX peak (width ~alpha) to < 1e-8.
constexpr double kNdfNormTol = 1e-8;

TEST(ReportD, IsNotNormalisedUnlikeGgxAndCharlie) {
    for (double r : {0.1, 0.3, 1.0, 3.0}) {
        const double report = hemisphere_integral(
            512, 4, [&](const Eigen::Vector3d& h) { return report_d(r, h.z()) * h.z(); });
        EXPECT_NEAR(report, r * r / (1 + r * r), kNdfNormTol) << "r = " << r;
        const double ggx = hemisphere_integral(512, 4, [&](const Eigen::Vector3d& h) {
            return ggx_d(r < 1 ? r : 1.0, h.z()) * h.z();
        });
        EXPECT_NEAR(ggx, 1.0, kNdfNormTol) << "alpha = " << r;
        const double charlie = hemisphere_integral(512, 4, [&](const Eigen::Vector3d& h) {
            return charlie_d(r < 1 ? r : 1.0, h.z()) * h.z();
        });
        EXPECT_NEAR(charlie, 1.0, kNdfNormTol) << "alpha = " << r;
    }
    // The report's D decreases from grazing to normal half vectors: no peak at H = N.
    for (double r : {0.1, 0.3, 1.0, 3.0}) {
        EXPECT_GT(report_d(r, 0.0), report_d(r, 0.5));
        EXPECT_GT(report_d(r, 0.5), report_d(r, 1.0));
    }
    EXPECT_GT(ggx_d(0.3, 1.0), ggx_d(0.3, 0.5));
}

// Closed forms for V = +z, L at polar angle theta: H at theta/2, so the report's G is
// min(1, 2 cos theta) while Smith's height-correlated G2 is G1(L) = 2 / (1 + sqrt(1 + a^2 tan^2)).
constexpr double kClosedFormTol = 1e-14;

TEST(ReportG, VCavityDiffersFromSmith) {
    const double a = 0.3;
    for (double theta_deg : {0.0, 30.0, 60.0, 75.0, 85.0, 89.9}) {
        const Eigen::Vector3d wi = dir(theta_deg, 40);
        const double t = std::tan(theta_deg * kPi / 180);
        EXPECT_NEAR(report_g(Eigen::Vector3d::UnitZ(), wi), std::min(1.0, 2 * wi.z()),
                    kClosedFormTol);
        EXPECT_NEAR(ggx_g2(a, Eigen::Vector3d::UnitZ(), wi), 2 / (1 + std::sqrt(1 + a * a * t * t)),
                    kClosedFormTol);
    }
    // At 75 degrees the V-cavity G (0.518) shadows far more than Smith at alpha 0.3 (0.800).
    EXPECT_LT(report_g(Eigen::Vector3d::UnitZ(), dir(75, 0)),
              ggx_g2(a, Eigen::Vector3d::UnitZ(), dir(75, 0)) - 0.25);
}

TEST(AllModels, NearDeltaRoughnessIsFinite) {
    for (Model model : kAllModels) {
        for (double alpha : {0.0, 1e-12, 1e-6, kMinAlpha, 1e-3}) {
            const Material m = with_model(model, alpha);
            for (double tv : {0.0, 10.0, 45.0, 80.0, 89.99}) {
                const Eigen::Vector3d wo = dir(tv, 0);
                // The mirror direction and its neighbours.
                for (double dt : {0.0, 1e-6, 1e-3, 1.0}) {
                    const Eigen::Vector3d wi = dir(std::min(tv + dt, 89.999), 180);
                    const Eigen::Vector3d f = eval(m, wo, wi);
                    ASSERT_TRUE(f.allFinite()) << to_string(model) << " " << alpha;
                    ASSERT_GE(f.minCoeff(), 0.0);
                    ASSERT_TRUE(std::isfinite(pdf(m, wo, wi)));
                }
                for (double u1 : {0.0, 0.3, 0.999999}) {
                    const Sample s = sample(m, wo, Eigen::Vector2d(u1, 0.25), 0.05);
                    if (!s.valid) continue;
                    ASSERT_TRUE(s.value.allFinite());
                    ASSERT_TRUE(std::isfinite(s.pdf));
                    ASSERT_GT(s.pdf, 0.0);
                }
            }
        }
    }
}

TEST(AllModels, GrazingIsFiniteAndZeroBelowHorizon) {
    for (Model model : kAllModels) {
        const Material m = with_model(model, 0.2);
        for (double c : {1e-300, 1e-12, 1e-9, 1e-6, 1e-3}) {
            const double s = std::sqrt(1 - c * c);
            const Eigen::Vector3d wo(s, 0, c), wi(-s, 0, c), wi2(s * 0.6, s * 0.8, c);
            for (const Eigen::Vector3d& l : {wo, wi, wi2}) {
                const Eigen::Vector3d f = eval(m, wo, l);
                ASSERT_TRUE(f.allFinite()) << to_string(model) << " cos " << c;
                ASSERT_GE(f.minCoeff(), 0.0);
            }
        }
        EXPECT_EQ(eval(m, Eigen::Vector3d(1, 0, 0), dir(10, 0)).norm(), 0.0);
        EXPECT_EQ(eval(m, dir(10, 0), dir(100, 0)).norm(), 0.0);
        EXPECT_EQ(eval(m, dir(100, 0), dir(10, 0)).norm(), 0.0);
        EXPECT_FALSE(sample(m, dir(100, 0), Eigen::Vector2d(0.5, 0.5), 0.5).valid);
    }
}

// Directional albedo by the adaptive cubature of brdf/cubature.h (an independent rule: plain
// theta-phi, nothing shared with this file's GL product rule or the bake), with its error
// estimate; 1e-10 requested.
struct Albedo {
    double value, error;
};
Albedo directional_albedo(const Material& m, const Eigen::Vector3d& wo, int channel) {
    CubatureOptions o;
    o.rel_tol = 1e-10;
    const CubatureResult r = hemisphere_cubature(
        [&](const Eigen::Vector3d& wi, double* out) {
            out[0] = eval_specular(m, wo, wi)[channel] * wi.z();
        },
        1, {Eigen::Vector3d(-wo.x(), -wo.y(), wo.z())}, o);
    return {r.integral[0], r.error};
}

// The albedo by this file's GL product rule at 512 x 512 nodes with an error bound from its
// self-convergence: error(n) ~ n^-p gives error(512) = d / (2^p - 1), d = |GL(256) - GL(512)|;
// 4 d covers p >= 0.33 (the sqrt(1 - c^2) of a lobe's pole in cos(theta) makes it algebraic).
Albedo gl_albedo(const Material& m, const Eigen::Vector3d& wo) {
    auto at = [&](int n) {
        return hemisphere_integral(
            n, n, [&](const Eigen::Vector3d& wi) { return eval_specular(m, wo, wi)[0] * wi.z(); });
    };
    const double fine = at(512);
    return {fine, 4 * std::abs(fine - at(256))};
}

// GGX, F = 1: at alpha = 1 the albedo is 1 - mu ln(1 + 1/mu) at every view (D = 1/pi,
// G2 = 2 mu mu_i / (mu + mu_i); docs/brdf.md); at other alphas the cubature against the GL
// product rule within both error bounds; single scattering in (0.3, 1].

TEST(Ggx, FresnelOneAlbedoIsKnownAndConserved) {
    for (double alpha : {0.2, 0.5, 1.0}) {
        Material m = with_model(Model::kGgx, alpha);
        m.f0 = Eigen::Vector3d::Ones();
        for (double tv : {0.0, 45.0, 80.0}) {
            const Albedo e = directional_albedo(m, dir(tv, 0), 0);
            if (alpha == 1.0) {
                const double mu = std::cos(tv * kPi / 180);
                EXPECT_NEAR(e.value, 1 - mu * std::log(1 + 1 / mu), e.error) << tv;
            } else {
                const Albedo gl = gl_albedo(m, dir(tv, 0));
                EXPECT_NEAR(e.value, gl.value, e.error + gl.error) << alpha << " " << tv;
                EXPECT_LT(gl.error, 1e-4) << "the check must stay sharp";
            }
            EXPECT_LE(e.value, 1.0 + e.error) << alpha << " " << tv;
            EXPECT_GT(e.value, 0.3) << alpha << " " << tv;  // single scattering loses < 70%
            // F = 1 on every channel: identical channels.
            const Eigen::Vector3d f = eval(m, dir(tv, 0), dir(30, 180));
            EXPECT_EQ(f[0], f[1]);
            EXPECT_TRUE(f.allFinite());
        }
    }
}

// Charlie has no closed-form albedo: the cubature against the GL product rule as above, and
// energy conservation.
TEST(Charlie, AlbedoAgreesAcrossRulesAndIsConserved) {
    for (double alpha : {0.1, 0.5, 1.0}) {
        const Material m = with_model(Model::kCharlie, alpha);
        for (double tv : {0.0, 45.0, 80.0}) {
            const Albedo e = directional_albedo(m, dir(tv, 0), 0);
            const Albedo gl = gl_albedo(m, dir(tv, 0));
            EXPECT_NEAR(e.value, gl.value, e.error + gl.error) << alpha << " " << tv;
            EXPECT_LT(gl.error, 1e-4) << "the check must stay sharp";
            EXPECT_LE(e.value, 1.0 + e.error) << alpha << " " << tv;
            EXPECT_GT(e.value, 0.0);
        }
    }
}

// Schlick 1994: f0 + (1 - f0)(1 - c)^5, exact values; cos is clamped to [0, 1].
TEST(Schlick, ClosedValues) {
    EXPECT_DOUBLE_EQ(schlick(0.04, 1.0), 0.04);
    EXPECT_DOUBLE_EQ(schlick(0.04, 0.0), 1.0);
    EXPECT_DOUBLE_EQ(schlick(0.04, 0.5), 0.04 + 0.96 / 32);
    EXPECT_DOUBLE_EQ(schlick(0.5, 0.75), 0.5 + 0.5 / 1024);
    EXPECT_DOUBLE_EQ(schlick(0.04, 1.5), 0.04);
    EXPECT_DOUBLE_EQ(schlick(0.04, -0.5), 1.0);
}

// Estevez and Kulla 2017, table 1 and eq. 3, evaluated outside this code (Python, from the
// paper's coefficients: L(x) = a/(1 + b x^c) + d x + e, interpolated by (1 - r)^2; Lambda = exp
// L(cos) below cos 0.5, exp(2 L(0.5) - L(1 - cos)) above). Relative rounding of exp/pow.
constexpr double kPinnedRelTol = 1e-12;

TEST(Charlie, LambdaMatchesThePapersFit) {
    const struct {
        double alpha, cos_theta, lambda;
    } kCases[] = {
        {1.0, 0.1, 5.873188816822575},   {1.0, 0.5, 0.710027789045483},
        {1.0, 0.9, 0.08583743464415955}, {0.5, 0.1, 7.419959426971326},
        {0.5, 0.5, 0.9438701928203119},  {0.5, 0.9, 0.12006682107401982},
        {0.1, 0.1, 13.136784265275022},  {0.1, 0.5, 1.8991019546991508},
        {0.1, 0.9, 0.2745411785345042},
    };
    for (const auto& c : kCases) {
        EXPECT_NEAR(charlie_lambda(c.alpha, c.cos_theta), c.lambda, kPinnedRelTol * c.lambda)
            << c.alpha << " " << c.cos_theta;
    }
}

// The report's Cook-Torrance (section 2.3) evaluated by hand from its formulas, N = +z:
// k = F G D / (4 (V.N)(N.L)), F = f + (1 - f)(1 - H.V)^5, G = min(1, 2(H.N)(V.N)/(V.H),
// 2(H.N)(L.N)/(V.H)), D = r^2 / (pi ((N.H)^2 r^2 + 1)^2). Case 1 by pencil: V = z, L at 60 deg:
// H.N = H.V = cos 30, G = min(1, 2, 1) = 1, F = 0.04 + 0.96 (1 - cos 30)^5, D = 0.09 / (pi
// 1.0675^2), k = F D / 2 = 5.0331e-4; the others (G < 1 from either term) in Python.
TEST(ReportCookTorrance, FullEvaluationMatchesHandComputedValues) {
    const struct {
        double f, r;
        Eigen::Vector3d v, l;
        double k;
    } kCases[] = {
        {0.04, 0.3, dir(0, 0), dir(60, 0), 0.0005033111177185836},
        {0.04, 0.3, dir(70, 0), dir(50, 90), 0.0006788761946372329},  // G = V term, 0.552
        {0.04, 0.3, dir(0, 0), dir(80, 30), 0.0005256106208162902},   // G = L term, 0.347
        {0.5, 1.0, dir(80, 0), dir(80, 180), 0.4569942516353306},
        {0.5, 1.0, dir(85, 0), dir(30, 200), 0.04805824724221078},
    };
    for (const auto& c : kCases) {
        Material m = with_model(Model::kCookTorranceReport);
        m.report_f = c.f;
        m.report_r = c.r;
        const Eigen::Vector3d k = eval_specular(m, c.v, c.l);
        EXPECT_NEAR(k[0], c.k, kPinnedRelTol * c.k) << c.v.transpose() << " / " << c.l.transpose();
        EXPECT_EQ(k[0], k[2]);
    }
    EXPECT_NEAR(schlick(0.04, std::cos(kPi / 6)), 0.04004143654313937, kPinnedRelTol);
    EXPECT_NEAR(report_d(0.3, std::cos(kPi / 6)), 0.025139513522514718, kPinnedRelTol);
}

TEST(Frame, OrthonormalEverywhere) {
    for (const Eigen::Vector3d& n : {Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(0, 0, -1),
                                     dir(179.9999, 10), dir(90, 33), dir(37, 251)}) {
        const Eigen::Matrix3d f = world_from_local(n);
        EXPECT_TRUE((f.transpose() * f).isApprox(Eigen::Matrix3d::Identity(), 1e-12));
        EXPECT_NEAR(f.determinant(), 1.0, 1e-12);
        EXPECT_TRUE(f.col(2).isApprox(n, 1e-15));
    }
}

// --- Sampling ---

// For each valid sample: the value is eval() and the pdf is pdf(), to rounding.
constexpr double kSampleConsistencyRelTol = 1e-12;

TEST(Sample, ValueAndPdfMatchEvalAndPdf) {
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> u(0, 1);
    for (Model model : kAllModels) {
        const Material m = with_model(model, 0.3);
        for (int k = 0; k < 5000; ++k) {
            const Eigen::Vector3d wo = dir(89.0 * u(rng), 360 * u(rng));
            const Sample s = sample(m, wo, Eigen::Vector2d(u(rng), u(rng)), u(rng));
            if (!s.valid) continue;
            ASSERT_NEAR(s.wi.norm(), 1.0, 1e-14);
            const double p = pdf(m, wo, s.wi);
            ASSERT_NEAR(s.pdf, p, kSampleConsistencyRelTol * p);
            ASSERT_TRUE(s.value.isApprox(eval(m, wo, s.wi), kSampleConsistencyRelTol));
        }
    }
}

// Histogram test (pbrt bsdfs_test.cpp style): samples binned on a cos(theta) x phi grid against
// the pdf integrated over each bin by 6x6 GL per bin. Pearson chi^2 over bins with expectation
// >= 5 (the rest pooled) must stay below dof + 6 sqrt(2 dof): about a 6-sigma normal
// approximation, so a correct sampler fails ~1e-9 of the time while a wrong pdf fails surely.
constexpr int kCosBins = 16, kPhiBins = 32;
constexpr int kHistSamples = 400000;
constexpr double kChi2Sigmas = 6.0;
// Integral of pdf over the hemisphere equals the fraction of valid samples within 5 standard
// errors of a binomial of kHistSamples (<= 5 * 0.5 / sqrt(4e5) = 0.004) plus bin quadrature.
constexpr double kValidFractionTol = 0.005;

void check_histogram(const Material& m, const Eigen::Vector3d& wo) {
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> u(0, 1);
    std::vector<double> observed(kCosBins * kPhiBins, 0);
    int valid = 0;
    for (int k = 0; k < kHistSamples; ++k) {
        const Sample s = sample(m, wo, Eigen::Vector2d(u(rng), u(rng)), u(rng));
        if (!s.valid) continue;
        ++valid;
        double phi = std::atan2(s.wi.y(), s.wi.x());
        if (phi < 0) phi += 2 * kPi;
        const int ic = std::min(kCosBins - 1, static_cast<int>(s.wi.z() * kCosBins));
        const int ip = std::min(kPhiBins - 1, static_cast<int>(phi / (2 * kPi) * kPhiBins));
        observed[ic * kPhiBins + ip] += 1;
    }
    std::vector<double> x, w;
    sh::gauss_legendre(6, x, w);
    std::vector<double> expected(observed.size(), 0);
    double total_pdf = 0;
    for (int ic = 0; ic < kCosBins; ++ic) {
        for (int ip = 0; ip < kPhiBins; ++ip) {
            double integral = 0;
            for (int a = 0; a < 6; ++a) {
                for (int b = 0; b < 6; ++b) {
                    const double c = (ic + 0.5 * (x[a] + 1)) / kCosBins;
                    const double phi = 2 * kPi * (ip + 0.5 * (x[b] + 1)) / kPhiBins;
                    const double sn = std::sqrt(1 - c * c);
                    const Eigen::Vector3d wi(sn * std::cos(phi), sn * std::sin(phi), c);
                    integral += 0.25 * w[a] * w[b] * pdf(m, wo, wi);
                }
            }
            integral *= (1.0 / kCosBins) * (2 * kPi / kPhiBins);
            total_pdf += integral;
            expected[ic * kPhiBins + ip] = integral * kHistSamples;
        }
    }
    EXPECT_NEAR(total_pdf, static_cast<double>(valid) / kHistSamples, kValidFractionTol)
        << to_string(m.specular);
    double chi2 = 0, pooled_o = 0, pooled_e = 0;
    int dof = -1;
    for (size_t i = 0; i < observed.size(); ++i) {
        if (expected[i] < 5) {
            pooled_o += observed[i];
            pooled_e += expected[i];
            continue;
        }
        chi2 += (observed[i] - expected[i]) * (observed[i] - expected[i]) / expected[i];
        ++dof;
    }
    if (pooled_e >= 5) {
        chi2 += (pooled_o - pooled_e) * (pooled_o - pooled_e) / pooled_e;
        ++dof;
    }
    ASSERT_GT(dof, 10);
    EXPECT_LT(chi2, dof + kChi2Sigmas * std::sqrt(2.0 * dof))
        << to_string(m.specular) << " wo " << wo.transpose() << " dof " << dof;
}

TEST(Sample, HistogramMatchesPdf) {
    for (Model model : kAllModels) {
        for (double alpha : {0.3, 0.8}) {
            Material m = with_model(model, alpha);
            for (double tv : {0.0, 50.0, 80.0}) check_histogram(m, dir(tv, 20));
        }
    }
}

TEST(Sample, PdfIntegratesToAtMostOne) {
    for (Model model : kAllModels) {
        const Material m = with_model(model, 0.5);
        const double total = hemisphere_integral(
            256, 256, [&](const Eigen::Vector3d& wi) { return pdf(m, dir(30, 0), wi); });
        EXPECT_LE(total, 1.0 + 1e-6) << to_string(model);
        EXPECT_GT(total, 0.5) << to_string(model);
    }
}

// --- Material files ---

TEST(Material, RoundTripsThroughToml) {
    Material m;
    m.specular = Model::kCharlie;
    m.albedo = Eigen::Vector3d(0.1, 0.2, 0.3);
    m.f0 = Eigen::Vector3d(0.9, 0.8, 0.7);
    m.alpha = 0.123;
    m.report_f = 0.5;
    m.report_r = 2.5;
    m.sheen_color = Eigen::Vector3d(1, 0.5, 0.25);
    m.specular_scale = 0.75;
    const Material r = parse_material(to_toml(m), "mem.toml");
    EXPECT_EQ(r.specular, m.specular);
    EXPECT_EQ(r.albedo, m.albedo);
    EXPECT_EQ(r.f0, m.f0);
    EXPECT_EQ(r.alpha, m.alpha);
    EXPECT_EQ(r.report_f, m.report_f);
    EXPECT_EQ(r.report_r, m.report_r);
    EXPECT_EQ(r.sheen_color, m.sheen_color);
    EXPECT_EQ(r.specular_scale, m.specular_scale);
}

std::string error_of(const std::string& text) {
    try {
        parse_material(text, "cloth.toml");
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

TEST(Material, ErrorsNameFileLineAndKey) {
    // The unknown-key message lists the keys that are known.
    EXPECT_NE(error_of("roughness = 0.3\n").find("(known: "), std::string::npos);
    const struct {
        const char* text;
        const char* expected;  // a part of the message: file, line and key
    } kCases[] = {
        {"alpha = 0.2\nroughness = 0.3\n", "cloth.toml:2: unknown key 'roughness'"},
        {"alpha = 2\n", "cloth.toml:1: alpha: 2 is outside [0, 1]"},
        {"report_r = 0\n", "cloth.toml:1: report_r: 0 is not > 0"},
        {"specular = \"phong\"\n", "cloth.toml:1: specular: unknown BRDF"},
        {"albedo = [1, 2]\n", "cloth.toml:1: albedo: expected an array of 3 numbers"},
        {"sheen_color = [0.5, 2, 0.5]\n", "cloth.toml:1: sheen_color: 2 is outside [0, 1]"},
        {"f0 = abc\n", "cloth.toml:1:6: TOML syntax error"},
        {"[material]\n", "cloth.toml:1: tables ([material]) are not supported"},
        {"alpha = 0.1\n\n[[layer]]\nf0 = 1\n", "cloth.toml:3: tables ([[layer]])"},
        {"alpha = 0.1\nalpha = 0.2\n", "cloth.toml:2:9: TOML syntax error: Error while parsing key-value pair: cannot redefine existing floating-point 'alpha'"},
        {"", "cloth.toml: specular: required key is missing"},
        {"alpha = 0.2\n", "cloth.toml: specular: required key is missing"},
    };
    for (const auto& c : kCases) {
        EXPECT_NE(error_of(c.text).find(c.expected), std::string::npos)
            << "text: " << c.text << "\nmessage: " << error_of(c.text)
            << "\nexpected to contain: " << c.expected;
    }
    EXPECT_EQ(error_of("# a comment\nspecular = \"ggx\"  # trailing\nf0 = 0.5\n"), "");
    try {
        load_material("/nonexistent/cloth.toml");
        FAIL();
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("/nonexistent/cloth.toml"), std::string::npos);
    }
}

}  // namespace
}  // namespace inlight::brdf
