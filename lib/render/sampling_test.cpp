// Tests of the sampling building blocks: the chi-square machinery against published quantiles,
// the environment's importance sampling (real map, synthetic gradient, one-hot pixels at the
// seam and the poles) and lib/brdf's BSDF sampling as the path tracer uses it.
#include "render/sampling.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <set>

#include "brdf/brdf.h"
#include "core/conventions.h"
#include "core/error.h"
#include "envmap/envmap_testing.h"
#include "envmap/project.h"
#include "render/environment.h"
#include "sh/sh.h"
#include "testing/testing.h"

namespace inlight::render {
namespace {

/// Significance of each chi-square test: a correct sampler fails one test with probability
/// 1e-3; over the ~15 chi-square tests here the chance of any false alarm is < 2% (and, seeds
/// being fixed, a passing run stays passing).
constexpr double kChi2Significance = 1e-3;

TEST(Chi2, SurvivalMatchesPublishedQuantiles) {
    // Upper-tail quantiles from NIST/SEMATECH e-Handbook table 1.3.6.7.4.
    constexpr double kTol = 1e-4;  // the table has 3 decimals on values ~10-30: relative ~1e-4
    EXPECT_NEAR(chi2_survival(3.841, 1), 0.05, kTol);
    EXPECT_NEAR(chi2_survival(18.307, 10), 0.05, kTol);
    EXPECT_NEAR(chi2_survival(29.588, 10), 0.001, kTol);
    EXPECT_NEAR(chi2_survival(124.342, 100), 0.05, kTol);
    EXPECT_NEAR(chi2_survival(149.449, 100), 0.001, kTol);
    // dof = 2: survival is exp(-x/2) exactly.
    EXPECT_NEAR(chi2_survival(5.0, 2), std::exp(-2.5), 1e-14);
}

TEST(Chi2, DetectsAWrongDistribution) {
    // 10 bins, expected uniform, observed skewed by 10%: with 10^5 samples this is obvious.
    std::vector<double> exp(10, 1e4), obs(10, 1e4);
    obs[0] = 1.1e4;
    obs[9] = 0.9e4;
    EXPECT_LT(chi2_test(obs, exp).p_value, 1e-10);
    EXPECT_GT(chi2_test(exp, exp).p_value, 0.99);
}

TEST(Rng, StreamsAreDeterministicAndDistinct) {
    Rng a(7, 123, 4), b(7, 123, 4), c(7, 123, 5), d(7, 124, 4);
    const uint32_t x = a.next_u32();
    EXPECT_EQ(x, b.next_u32());
    EXPECT_NE(x, c.next_u32());
    EXPECT_NE(x, d.next_u32());
    // Uniformity of the first draw across many streams (what the renderer relies on): chi2 over
    // 64 bins.
    std::vector<double> obs(64, 0), exp(64, 1e5 / 64.0);
    for (uint64_t s = 0; s < 100000; ++s) {
        Rng r(1, s % 997, s / 997);
        obs[static_cast<size_t>(r.uniform() * 64)] += 1;
    }
    EXPECT_GT(chi2_test(obs, exp).p_value, kChi2Significance);
}

TEST(Distribution1D, SkipsZeroBinsAndRemaps) {
    const Distribution1D d({0.0, 1.0, 0.0, 3.0, 0.0});
    EXPECT_DOUBLE_EQ(d.pmf(1), 0.25);
    EXPECT_DOUBLE_EQ(d.pmf(3), 0.75);
    double r = 0;
    EXPECT_EQ(d.sample(0.0, &r), 1);
    EXPECT_DOUBLE_EQ(r, 0.0);
    EXPECT_EQ(d.sample(0.125, &r), 1);
    EXPECT_DOUBLE_EQ(r, 0.5);
    EXPECT_EQ(d.sample(0.25, &r), 3);
    EXPECT_EQ(d.sample(std::nextafter(1.0, 0.0), &r), 3);
}

// --- Environment sampling --------------------------------------------------------------------

/// Draws n samples from `light`, bins them by the pixel their direction falls in (computed
/// independently of the light: R^T dir -> latlong_uv -> pixel, coarsened by `bin`), and tests
/// against the light's pixel probabilities. Also checks that every sample's pdf equals pdf(dir).
Chi2Result env_chi2(const EnvironmentLight& light, const Eigen::Matrix3d& world_from_env, int bin,
                    int n, uint64_t seed) {
    const int bw = light.width() / bin, bh = light.height() / bin;
    std::vector<double> obs(static_cast<size_t>(bw) * bh, 0.0), exp(obs.size(), 0.0);
    for (int row = 0; row < light.height(); ++row) {
        for (int col = 0; col < light.width(); ++col) {
            exp[static_cast<size_t>(row / bin) * bw + col / bin] +=
                n * light.pixel_probability(col, row);
        }
    }
    int pdf_mismatches = 0;
    for (int i = 0; i < n; ++i) {
        Rng rng(seed, 0, static_cast<uint64_t>(i));
        const EnvironmentLight::Sample s = light.sample(rng.uniform2());
        EXPECT_NEAR(s.dir.norm(), 1.0, 1e-12);
        const Eigen::Vector2d uv = latlong_uv(world_from_env.transpose() * s.dir);
        const int col = std::min(static_cast<int>(uv[0] * light.width()), light.width() - 1);
        const int row = std::min(static_cast<int>(uv[1] * light.height()), light.height() - 1);
        obs[static_cast<size_t>(row / bin) * bw + col / bin] += 1;
        if (std::abs(s.pdf - light.pdf(s.dir)) > 1e-9 * s.pdf) ++pdf_mismatches;
    }
    EXPECT_EQ(pdf_mismatches, 0);
    return chi2_test(obs, exp);
}

TEST(EnvironmentSampling, RealHdriChi2) {
    const std::string dir = testing::blender_hdri_dir();
    INLIGHT_SKIP_IF_MISSING(dir, "blender-data HDRIs");
    const image::Image img = load_latlong(dir + "/city.exr");
    const Eigen::Matrix3d r = parse_rotation("z=30,x=-20");
    const EnvironmentLight light(img, r, 1.0, "city.exr");
    // 1024x512 pixels in 16x16 bins: 64x32 bins; the sun makes many bins tiny (pooled).
    const Chi2Result c = env_chi2(light, r, 16, 400000, 11);
    EXPECT_GT(c.p_value, kChi2Significance) << "chi2 " << c.statistic << " dof " << c.dof;
    EXPECT_GT(c.dof, 100);  // the test must have real resolution, not pool everything
}

TEST(EnvironmentSampling, SyntheticGradientChi2PerPixel) {
    image::Image img(64, 32, 3);
    for (int row = 0; row < 32; ++row) {
        for (int col = 0; col < 64; ++col) {
            const float v = static_cast<float>((col + 1) * (row + 1));
            img.at(col, row, 0) = v;
            img.at(col, row, 1) = 0.5f * v;
            img.at(col, row, 2) = -0.1f * v;  // negative values are sampled by |value|
        }
    }
    const EnvironmentLight light(img, Eigen::Matrix3d::Identity(), 2.0, "gradient");
    const Chi2Result c = env_chi2(light, Eigen::Matrix3d::Identity(), 1, 300000, 12);
    EXPECT_GT(c.p_value, kChi2Significance) << "chi2 " << c.statistic << " dof " << c.dof;
    // The pixel probabilities follow luminance(|rgb|) x exact solid angle.
    double total = 0;
    for (int row = 0; row < 32; ++row) {
        for (int col = 0; col < 64; ++col) total += light.pixel_probability(col, row);
    }
    EXPECT_NEAR(total, 1.0, 1e-12);
    const double w00 =
        (0.2126 + 0.7152 * 0.5 + 0.0722 * 0.1) * latlong_pixel_solid_angle(0, 64, 32);
    const double w35 =
        (0.2126 + 0.7152 * 0.5 + 0.0722 * 0.1) * 4 * 6 * latlong_pixel_solid_angle(5, 64, 32);
    // The map stores float radiance (-0.1f * v is rounded): relative agreement to float epsilon.
    constexpr double kFloatRel = 1e-7;
    EXPECT_NEAR(light.pixel_probability(3, 5) / light.pixel_probability(0, 0), w35 / w00,
                kFloatRel * w35 / w00);
}

TEST(EnvironmentSampling, Chi2RejectsSamplingWithoutSolidAngle) {
    // Power check: the same gradient map, but expected counts from luminance alone (the
    // mistake of forgetting sin(theta)); the test above would have to catch it.
    image::Image img(64, 32, 3);
    for (int row = 0; row < 32; ++row) {
        for (int col = 0; col < 64; ++col) {
            for (int c = 0; c < 3; ++c) img.at(col, row, c) = static_cast<float>(col + row + 1);
        }
    }
    const EnvironmentLight light(img, Eigen::Matrix3d::Identity(), 1.0, "gradient");
    const int n = 100000;
    std::vector<double> obs(64 * 32, 0.0), exp(64 * 32, 0.0);
    double total = 0;
    for (int i = 0; i < 64 * 32; ++i) total += (i % 64) + (i / 64) + 1;
    for (int i = 0; i < 64 * 32; ++i)
        exp[static_cast<size_t>(i)] = n * ((i % 64) + (i / 64) + 1) / total;
    for (int i = 0; i < n; ++i) {
        Rng rng(13, 0, static_cast<uint64_t>(i));
        const Eigen::Vector2i p = light.pixel_of(light.sample(rng.uniform2()).dir);
        obs[static_cast<size_t>(p[1] * 64 + p[0])] += 1;
    }
    EXPECT_LT(chi2_test(obs, exp).p_value, 1e-9);
}

/// A map that is black except one pixel: every sample must land in that pixel, with pdf
/// 1 / Omega_pixel, uniformly in solid angle inside it (chi2 over 4x4 equal-solid-angle cells).
void check_one_hot(int hot_col, int hot_row) {
    const int w = 32, h = 16;
    image::Image img(w, h, 3);
    img.at(hot_col, hot_row, 0) = 5.0f;
    img.at(hot_col, hot_row, 1) = 2.0f;
    const Eigen::Matrix3d r = parse_rotation("y=40");
    const EnvironmentLight light(img, r, 1.0, "one-hot");
    const double omega = latlong_pixel_solid_angle(hot_row, w, h);
    const double z0 = std::cos(kPi * hot_row / h), z1 = std::cos(kPi * (hot_row + 1) / h);
    const int n = 100000, sub = 4;
    std::vector<double> obs(sub * sub, 0.0), exp(sub * sub, static_cast<double>(n) / (sub * sub));
    int outside = 0;
    for (int i = 0; i < n; ++i) {
        Rng rng(5, static_cast<uint64_t>(hot_col), static_cast<uint64_t>(i));
        const EnvironmentLight::Sample s = light.sample(rng.uniform2());
        ASSERT_NEAR(s.pdf, 1.0 / omega, 1e-9 / omega);
        const Eigen::Vector3d d = r.transpose() * s.dir;
        const Eigen::Vector2d uv = latlong_uv(d);
        const int col = std::min(static_cast<int>(uv[0] * w), w - 1);
        const int row = std::min(static_cast<int>(uv[1] * h), h - 1);
        if (col != hot_col || row != hot_row) {
            ++outside;
            continue;
        }
        // Position inside the pixel: column fraction, and the fraction of the row's cos range.
        const double fu = uv[0] * w - col;
        const double fz = (z0 - d.z()) / (z0 - z1);
        const int bu = std::clamp(static_cast<int>(fu * sub), 0, sub - 1);
        const int bz = std::clamp(static_cast<int>(fz * sub), 0, sub - 1);
        obs[static_cast<size_t>(bz * sub + bu)] += 1;
    }
    EXPECT_EQ(outside, 0) << "pixel (" << hot_col << ", " << hot_row << ")";
    const Chi2Result c = chi2_test(obs, exp);
    EXPECT_GT(c.p_value, kChi2Significance)
        << "pixel (" << hot_col << ", " << hot_row << ") chi2 " << c.statistic;
    // Directions elsewhere have zero density; the hot pixel's radiance is returned.
    EXPECT_EQ(light.pdf(r * latlong_direction((hot_col + 10.5) / w, 0.5)), 0.0);
    EXPECT_NEAR(light.eval(r * latlong_direction((hot_col + 0.5) / w, (hot_row + 0.5) / h))[0], 5.0,
                0.0);
}

TEST(EnvironmentSampling, OneHotInside) { check_one_hot(11, 6); }
TEST(EnvironmentSampling, OneHotAtSeamColumns) {
    check_one_hot(0, 7);
    check_one_hot(31, 8);
}
TEST(EnvironmentSampling, OneHotAtPoleRows) {
    check_one_hot(5, 0);
    check_one_hot(20, 15);
}

TEST(EnvironmentSampling, ConstantMapIsUniformOnTheSphere) {
    const EnvironmentLight light = EnvironmentLight::constant({2, 2, 2});
    for (int i = 0; i < 100; ++i) {
        Rng rng(3, 0, static_cast<uint64_t>(i));
        const auto s = light.sample(rng.uniform2());
        EXPECT_NEAR(s.pdf, 1.0 / (4 * kPi), 1e-12);
        EXPECT_EQ(s.radiance, Eigen::Vector3d(2, 2, 2));
    }
    EXPECT_NEAR(light.mean_radiance()[1], 2.0, 1e-12);
}

TEST(EnvironmentSampling, RejectsBadMaps) {
    image::Image square(16, 16, 3);
    EXPECT_THROW(EnvironmentLight(square, Eigen::Matrix3d::Identity(), 1, "sq"), Error);
    image::Image nan(8, 4, 3);
    nan.at(1, 1, 1) = std::nanf("");
    try {
        const EnvironmentLight bad(nan, Eigen::Matrix3d::Identity(), 1, "nan.exr");
        FAIL() << "expected Error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("nan.exr: non-finite radiance at pixel (1, 1)"),
                  std::string::npos)
            << e.what();
    }
}

// --- BSDF sampling (lib/brdf, as the path tracer calls it) ---------------------------------

/// Bins sample() over (cos theta, phi) and compares with pdf() integrated over each bin by the
/// midpoint rule on an 8x8 sub-grid (dw = dcos dphi); the mass pdf() does not cover (invalid
/// samples) is an extra bin.
void check_bsdf_chi2(const brdf::Material& m, double theta_o_deg, uint64_t seed) {
    const int nc = 16, np = 32, sub = 8, n = 200000;
    const double to = theta_o_deg * kPi / 180;
    const Eigen::Vector3d wo(std::sin(to), 0, std::cos(to));
    std::vector<double> obs(nc * np + 1, 0.0), exp(nc * np + 1, 0.0);
    double covered = 0;
    for (int ic = 0; ic < nc; ++ic) {
        for (int ip = 0; ip < np; ++ip) {
            double mass = 0;
            for (int a = 0; a < sub; ++a) {
                for (int b = 0; b < sub; ++b) {
                    const double c = (ic + (a + 0.5) / sub) / nc;
                    const double phi = 2 * kPi * (ip + (b + 0.5) / sub) / np;
                    const double s = std::sqrt(std::max(0.0, 1 - c * c));
                    mass += brdf::pdf(m, wo, {s * std::cos(phi), s * std::sin(phi), c});
                }
            }
            mass *= (1.0 / nc) * (2 * kPi / np) / (sub * sub);
            exp[static_cast<size_t>(ic * np + ip)] = n * mass;
            covered += mass;
        }
    }
    exp.back() = n * std::max(0.0, 1.0 - covered);
    for (int i = 0; i < n; ++i) {
        Rng rng(seed, 1, static_cast<uint64_t>(i));
        const Eigen::Vector2d u = rng.uniform2();
        const brdf::Sample s = brdf::sample(m, wo, u, rng.uniform());
        if (!s.valid) {
            obs.back() += 1;
            continue;
        }
        double phi = std::atan2(s.wi.y(), s.wi.x());
        if (phi < 0) phi += 2 * kPi;
        const int ic = std::min(static_cast<int>(s.wi.z() * nc), nc - 1);
        const int ip = std::min(static_cast<int>(phi / (2 * kPi) * np), np - 1);
        obs[static_cast<size_t>(ic * np + ip)] += 1;
    }
    const Chi2Result c = chi2_test(obs, exp);
    EXPECT_GT(c.p_value, kChi2Significance)
        << brdf::to_string(m.specular) << " theta_o " << theta_o_deg << " chi2 " << c.statistic
        << " dof " << c.dof << " covered " << covered;
}

TEST(BsdfSampling, LambertChi2) {
    brdf::Material m;
    m.specular = brdf::Model::kLambert;
    m.albedo = {0.8, 0.6, 0.4};
    check_bsdf_chi2(m, 30, 21);
}

TEST(BsdfSampling, GgxChi2) {
    brdf::Material m;
    m.specular = brdf::Model::kGgx;
    m.alpha = 0.3;
    m.albedo = {0.3, 0.3, 0.3};
    check_bsdf_chi2(m, 20, 22);
    check_bsdf_chi2(m, 65, 23);
}

TEST(BsdfSampling, ReportCookTorranceChi2) {
    brdf::Material m;
    m.specular = brdf::Model::kCookTorranceReport;
    m.report_r = 0.3;
    m.report_f = 0.5;
    check_bsdf_chi2(m, 40, 24);
}

TEST(BsdfSampling, CharlieChi2) {
    brdf::Material m;
    m.specular = brdf::Model::kCharlie;
    m.alpha = 0.5;
    m.albedo = {0.2, 0.2, 0.2};
    check_bsdf_chi2(m, 50, 25);
}

}  // namespace
}  // namespace inlight::render

// --- Environment layouts (resampling of cube and angular maps) -------------------------------

namespace inlight::render {
namespace {

/// Writes a map whose every pixel's first channel is its index, loads it with lib/envmap, and
/// checks that each pixel's own direction (envmap's sample set) maps back to that pixel.
void check_inverse_mapping(envmap::Layout layout, int w, int h) {
    image::Image img(w, h, 3);
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) img.at(x, y, 0) = static_cast<float>(y * w + x);
    }
    const std::string path = testing::temp_dir("env_layout") + "/map.exr";
    image::write_image(path, img);
    envmap::LoadOptions lo;
    lo.layout = layout;
    const envmap::Environment env = envmap::load_environment(path, lo);
    const auto samples = envmap::make_sample_set(env);
    int checked = 0, wrong = 0;
    for (int64_t i = 0; i < samples->size(); ++i) {
        Eigen::Vector3d d;
        double weight, v[3];
        if (!samples->sample(i, d, weight, v)) continue;
        const int x = static_cast<int>(i % w), y = static_cast<int>(i / w);
        if (layout == envmap::Layout::kAngular) {
            const double u = -1 + 2.0 * (x + 0.5) / w, vv = 1 - 2.0 * (y + 0.5) / h;
            if (u * u + vv * vv > 0.98 * 0.98) continue;  // rim pixels take the rim direction
        }
        ++checked;
        if (environment_texel(layout, d, w, h) != Eigen::Vector2i(x, y)) ++wrong;
    }
    EXPECT_GT(checked, w * h / 2);
    EXPECT_EQ(wrong, 0) << envmap::to_string(layout);
}

TEST(EnvironmentLayouts, CubeAndAngularInvertEnvmapDirections) {
    check_inverse_mapping(envmap::Layout::kCube, 6 * 8, 8);
    check_inverse_mapping(envmap::Layout::kAngular, 32, 32);
    check_inverse_mapping(envmap::Layout::kLatLong, 32, 16);
}

TEST(EnvironmentLayouts, LookupsFollowTheOpenGlCubeTableAndDebevecsAngularMap) {
    // The pins of envmap_testing.h (from the OpenGL ES cube-map table and Debevec's definition,
    // written out by hand): the path tracer's texel lookup must find the pinned texel.
    for (const auto& p : envmap::testmaps::kCubePins) {
        EXPECT_EQ(environment_texel(envmap::Layout::kCube, Eigen::Vector3d(p.x, p.y, p.z), 12, 2),
                  Eigen::Vector2i(p.face * 2 + p.i, p.j))
            << p.face << " " << p.i << " " << p.j;
    }
    // An odd size keeps every pin off the pixel borders: pixel x covers
    // u in [-1 + 2x/n, -1 + 2(x+1)/n], row y covers v in [1 - 2(y+1)/n, 1 - 2y/n].
    const int n = 7;
    for (const auto& p : envmap::testmaps::kAngularPins) {
        const Eigen::Vector2i want(int(std::floor((p.u + 1) / 2 * n)),
                                   int(std::floor((1 - p.v) / 2 * n)));
        EXPECT_EQ(environment_texel(envmap::Layout::kAngular, Eigen::Vector3d(p.x, p.y, p.z), n, n),
                  want)
            << p.u << " " << p.v;
    }
}

TEST(EnvironmentLayouts, ResampledCubeKeepsTheLighting) {
    // A smooth environment sampled on a cube strip, resampled to lat-long: its SH projection
    // (power and the low bands the real-time model uses) must match the cube's own.
    const int n = 32;
    image::Image cube(6 * n, n, 3);
    const Eigen::Vector3d key = Eigen::Vector3d(0.3, -0.5, 0.8).normalized();
    for (int y = 0; y < n; ++y) {
        for (int x = 0; x < 6 * n; ++x) {
            const Eigen::Vector3d d =
                envmap::cube_direction(x / n, (x % n + 0.5) / n, (y + 0.5) / n);
            const double v = 1.0 + 4.0 * std::exp(4.0 * (d.dot(key) - 1.0));
            for (int c = 0; c < 3; ++c) cube.at(x, y, c) = static_cast<float>(v * (1 + 0.2 * c));
        }
    }
    const std::string path = testing::temp_dir("env_cube") + "/cube.exr";
    image::write_image(path, cube);
    const image::Image ll = load_environment_latlong(path, "cube");
    EXPECT_EQ(ll.height, 2 * n);
    EXPECT_EQ(ll.width, 4 * n);
    envmap::LoadOptions lo;
    lo.layout = envmap::Layout::kCube;
    const Eigen::MatrixXd from_cube =
        envmap::project(envmap::load_environment(path, lo), {}).coeffs;
    const Eigen::MatrixXd from_ll = envmap::project_latlong(ll, 3);
    // Noise source: nearest-texel lookup returns f at the texel centre, not at the direction
    // asked for: a displacement u within one texel (angular size a <= 2 / n), uniform, so the
    // value is off by grad f . u with variance |grad f|^2 a^2 / 6 (two axes of a^2 / 12).
    // Taking each lat-long pixel's error as one such draw (its 4x4 lookups mostly hit one
    // texel: no averaging credited), coefficient k is off by a sum of independent terms
    // Omega_p Y_k(d_p) e_p: sigma_k^2 = sum_p (Omega_p Y_k(d_p))^2 |grad f(d_p)|^2 a^2 / 6.
    // |grad f| = 16 exp(4 (d.key - 1)) sqrt(1 - (d.key)^2) per unit of channel 0. Allowed:
    // 4 sigma_k, plus the two quadratures' own O(a^2) midpoint error (1e-4 of L00).
    const double a = 2.0 / n;
    Eigen::VectorXd var = Eigen::VectorXd::Zero(9);
    double y[9];
    for (int row = 0; row < ll.height; ++row) {
        const double omega = latlong_pixel_solid_angle(row, ll.width, ll.height);
        for (int col = 0; col < ll.width; ++col) {
            const Eigen::Vector3d d =
                latlong_direction((col + 0.5) / ll.width, (row + 0.5) / ll.height);
            const double t = d.dot(key);
            const double grad = 16 * std::exp(4 * (t - 1)) * std::sqrt(std::max(0.0, 1 - t * t));
            sh::eval(3, d, y);
            for (int k = 0; k < 9; ++k) var[k] += std::pow(omega * y[k] * grad * a, 2) / 6;
        }
    }
    double worst_in_sigmas = 0;
    for (int c = 0; c < 3; ++c) {
        const double scale = 1 + 0.2 * c;
        for (int k = 0; k < 9; ++k) {
            const double sigma = scale * std::sqrt(var[k]);
            EXPECT_NEAR(from_ll(k, c), from_cube(k, c), 4 * sigma + 1e-4 * from_cube(0, c))
                << k << "," << c;
            worst_in_sigmas = std::max(worst_in_sigmas, std::abs(from_ll(k, c) - from_cube(k, c)) / sigma);
        }
    }
    std::printf("cube -> lat-long resampling: largest coefficient difference %.2f sigma "
                "(sigma_00 = %.1e of L00)\n",
                worst_in_sigmas, std::sqrt(var[0]) / from_cube(0, 0));
}

}  // namespace
}  // namespace inlight::render
