// Tests of lib/envmap: exact quadratures, conventions at poles and seam, partial-sphere fit,
// hard inputs, and real HDRIs against brute-force irradiance.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <random>

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>

#include "core/conventions.h"
#include "core/error.h"
#include "core/parallel.h"
#include "envmap/environment.h"
#include "envmap/envmap_testing.h"
#include "envmap/project.h"
#include "envmap/validate.h"
#include "sh/quadrature.h"
#include "sh/sh.h"
#include "testing/testing.h"

namespace inlight::envmap {
namespace {

// Exact quadratures: only double rounding over up to 1e6 terms of O(1) values.
constexpr double kExactRel = 1e-11;

using testmaps::Fn;
using testmaps::constant;
using testmaps::fisheye_frame;
using testmaps::latlong;
using testmaps::cube;
using testmaps::angular;

// A smooth, positive, not band-limited test environment.
Eigen::Vector3d smooth(const Eigen::Vector3d& d) {
    const double a = std::exp(1.5 * d.dot(Eigen::Vector3d(0.48, 0.6, 0.64)));
    return {a, 0.5 * a + 0.2 * d.z(), 1.0 + 0.3 * d.x()};
}

// The float path's derived bound per coefficient (project.h): |L_lm(float) - L_lm| <=
// kFloatRowSumBound sqrt(2l + 1) L_00(|map|), plus the double path's own rounding (kExactRel).
Eigen::MatrixXd float_path_bound(const image::Image& img, int bands) {
    image::Image abs_img = img;
    for (float& p : abs_img.pixels) p = std::abs(p);
    const Eigen::MatrixXd abs00 = project_latlong(abs_img, 1, LatlongPrecision::kDouble);
    Eigen::MatrixXd bound(sh::count(bands), 3);
    for (int l = 0; l < bands; ++l)
        for (int m = -l; m <= l; ++m)
            for (int c = 0; c < 3; ++c)
                bound(sh::index(l, m), c) =
                    (kFloatRowSumBound * std::sqrt(2.0 * l + 1) + kExactRel) * abs00(0, c);
    return bound;
}

TEST(ProjectLatLong, ConstantMapIsExactAtAnyResolution) {
    const double value = 0.75;  // exact in float32, the pixel type
    for (int h : {1, 2, 3, 32, 256}) {
        const Environment env = latlong(2 * h, h, constant(value));
        ProjectOptions opt;
        opt.sh_bands = 9;
        opt.latlong_precision = LatlongPrecision::kDouble;
        const ProjectResult r = project(env, opt);
        EXPECT_NEAR(r.coeffs(0, 0), 2 * std::sqrt(kPi) * value, kExactRel) << "h=" << h;
        for (int k = 1; k < sh::count(9); ++k) EXPECT_NEAR(r.coeffs(k, 1), 0.0, kExactRel);
        for (const auto& n : validation_normals(16)) {
            const Eigen::MatrixXd e = sh_irradiance(r.coeffs, 9, {n});
            EXPECT_NEAR(e(0, 2), kPi * value, kExactRel);
        }
        // The float path (the default) within its bound; L_00 within kExactRel, since its m = 0
        // weights are exactly 1 and sums of 0.75 are exact in float.
        opt.sh_bands = kMaxFloatBands;
        opt.latlong_precision = LatlongPrecision::kFloatRowSums;
        const Eigen::MatrixXd f = project(env, opt).coeffs;
        const Eigen::MatrixXd bound = float_path_bound(env.radiance, 8);
        EXPECT_NEAR(f(0, 0), 2 * std::sqrt(kPi) * value, kExactRel) << "h=" << h;
        for (int k = 1; k < sh::count(8); ++k)
            EXPECT_NEAR(f(k, 1), 0.0, bound(k, 1)) << "h=" << h << " k=" << k;
    }
}

TEST(ProjectLatLong, SeparableSchemeEqualsPerPixelBoxIntegral) {
    // Reference: integrate Y_lm sin(theta) over each pixel's exact area by 2D Gauss-Legendre in
    // (theta, phi), 16 x 16 nodes: the integrand is analytic over a pi/8 pixel, so the rule
    // converges to rounding (~1e-15); times the pixel's value.
    const int w = 16, h = 8, bands = 5, n = sh::count(bands);
    std::mt19937_64 rng(1);
    std::uniform_real_distribution<double> u(-0.2, 3);
    Environment env = latlong(w, h, constant(0));
    for (float& p : env.radiance.pixels) p = static_cast<float>(u(rng));
    const Eigen::MatrixXd fast = project_latlong(env.radiance, bands, LatlongPrecision::kDouble);
    std::vector<double> gx, gw;
    sh::gauss_legendre(16, gx, gw);
    Eigen::MatrixXd ref = Eigen::MatrixXd::Zero(n, 3);
    std::vector<double> y(static_cast<size_t>(n));
    for (int row = 0; row < h; ++row) {
        const double t0 = kPi * row / h, t1 = kPi * (row + 1) / h;
        for (int col = 0; col < w; ++col) {
            // Cycles: u = col/W .. (col+1)/W maps to phi = pi(1-2u), decreasing.
            const double p0 = kPi * (1 - 2.0 * col / w), p1 = kPi * (1 - 2.0 * (col + 1) / w);
            for (size_t a = 0; a < gx.size(); ++a) {
                for (size_t b = 0; b < gx.size(); ++b) {
                    const double t = 0.5 * (t0 + t1) + 0.5 * (t1 - t0) * gx[a];
                    const double phi = 0.5 * (p0 + p1) + 0.5 * (p0 - p1) * gx[b];
                    const double s = std::sin(t);
                    sh::eval(bands, {s * std::cos(phi), s * std::sin(phi), std::cos(t)}, y.data());
                    const double wgt = 0.25 * (t1 - t0) * (p0 - p1) * gw[a] * gw[b] * s;
                    for (int k = 0; k < n; ++k)
                        for (int c = 0; c < 3; ++c)
                            ref(k, c) += wgt * y[size_t(k)] * env.radiance.at(col, row, c);
                }
            }
        }
    }
    EXPECT_LT((fast - ref).cwiseAbs().maxCoeff(), 1e-12);
    // The float path against the same reference, within its derived bound.
    const Eigen::MatrixXd f = project_latlong(env.radiance, bands, LatlongPrecision::kFloatRowSums);
    const Eigen::MatrixXd bound = float_path_bound(env.radiance, bands);
    for (int k = 0; k < n; ++k)
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(f(k, c), ref(k, c), bound(k, c)) << k << " " << c;
}

/// Maps that stress the float row sums, w x w/2: smooth random values in [-0.01, 2], and a 1e5
/// sun (12 x 12 pixels at 4096 wide, at (1000, 600) scaled to w) on a 0.1 sky with slightly
/// negative pixels, as the blender-data EXRs have.
std::vector<std::pair<std::string, image::Image>> float_stress_maps(int w, uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(-0.01, 2);
    const int h = w / 2;
    const double scale = w / 4096.0;
    image::Image smooth(w, h, 3), hdr(w, h, 3);
    for (float& p : smooth.pixels) p = static_cast<float>(u(rng));
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            const bool sun = std::abs(x - 1000 * scale) < 6 * scale &&
                             std::abs(y - 600 * scale) < 6 * scale;
            for (int c = 0; c < 3; ++c)
                hdr.at(x, y, c) = sun ? 1e5f : static_cast<float>(0.1 * u(rng));
        }
    }
    std::vector<std::pair<std::string, image::Image>> maps;
    maps.emplace_back("smooth random", std::move(smooth));
    maps.emplace_back("sun on sky", std::move(hdr));
    return maps;
}

TEST(ProjectLatLong, FloatRowSumsMatchDouble) {
    // The float path against the double reference, on maps that stress it: smooth random
    // values, a high-dynamic-range map (a 1e5 sun on a 1e-1 sky, with slightly negative pixels
    // as the blender-data EXRs have) and, when installed, city.exr; 1..8 bands, 4096 columns
    // (64 float blocks per row). Required: the 1e-6 of the largest coefficient.
    constexpr double kFloatRel = 1e-6;
    std::vector<std::pair<std::string, image::Image>> maps = float_stress_maps(4096, 3);
    const std::string dir = testing::blender_hdri_dir();
    if (!dir.empty()) maps.emplace_back("city.exr", image::read_image(dir + "/city.exr"));
    for (const auto& [name, img] : maps) {
        for (int bands : {1, 3, 5, 8}) {
            const Eigen::MatrixXd ref = project_latlong(img, bands, LatlongPrecision::kDouble);
            const Eigen::MatrixXd fast =
                project_latlong(img, bands, LatlongPrecision::kFloatRowSums);
            const double err = (fast - ref).cwiseAbs().maxCoeff() / ref.cwiseAbs().maxCoeff();
            EXPECT_LT(err, kFloatRel) << name << ", " << bands << " bands";
            EXPECT_GT(err, 0.0) << name << ": the float path did not run";
            const Eigen::MatrixXd bound = float_path_bound(img, bands);
            EXPECT_TRUE(((fast - ref).cwiseAbs().array() <= bound.array()).all())
                << name << ", " << bands << " bands: outside the derived bound";
            std::printf("%-14s %d bands: float path error %.2e of the largest coefficient\n",
                        name.c_str(), bands, err);
        }
    }
}

TEST(ProjectLatLong, BaselineIsaRowSumsMatchDouble) {
    // The fallback for CPUs without AVX2 + FMA (the baseline build, SSE2 on x86-64: separate
    // multiply and add, 4-lane registers), forced with FloatRowSumIsa::kBaseline, against the
    // double reference within the same derived bound, kFloatRowSumBound (its error analysis is
    // the same length-16 float inner product; without FMA each term rounds twice, which the
    // bound's gamma_16 already covers). 1024 columns (64 float blocks per row), both paddings
    // (K = 8 up to 4 bands, 16 above), maps like the smooth and the HDR map of the test above.
    for (const auto& [name, img] : float_stress_maps(1024, 5)) {
        for (int bands : {2, 3, 5, 8}) {
            const Eigen::MatrixXd ref = project_latlong(img, bands, LatlongPrecision::kDouble);
            const Eigen::MatrixXd base = project_latlong(
                img, bands, LatlongPrecision::kFloatRowSums, FloatRowSumIsa::kBaseline);
            const Eigen::MatrixXd bound = float_path_bound(img, bands);
            const Eigen::MatrixXd err = (base - ref).cwiseAbs();
            EXPECT_TRUE((err.array() <= bound.array()).all())
                << name << ", " << bands << " bands: the baseline float path is outside the "
                << "derived bound; worst " << (err.array() / bound.array()).maxCoeff() << " of it";
            EXPECT_GT(err.maxCoeff(), 0.0) << "the float path did not run";
            if (float_row_sums_use_avx2()) {
                // The default ran the AVX2 + FMA code: FMA's single rounding per term makes the
                // two differ, so equal results would mean the override did not take effect.
                const Eigen::MatrixXd best = project_latlong(img, bands);
                EXPECT_GT((best - base).cwiseAbs().maxCoeff(), 0.0)
                    << bands << " bands: kBaseline gave the AVX2 result";
            }
            std::printf("%-14s %d bands: baseline (SSE2) float path error %.2e of the largest "
                        "coefficient, %.2e of the derived bound\n",
                        name.c_str(), bands, err.maxCoeff() / ref.cwiseAbs().maxCoeff(),
                        (err.array() / bound.array()).maxCoeff());
        }
    }
}

TEST(ProjectLatLong, HotPixelsFollowCyclesConventionAtPolesAndSeam) {
    const int w = 64, h = 32;
    auto hot = [&](int x, int y) {
        Environment env = latlong(w, h, constant(0));
        for (int c = 0; c < 3; ++c) env.radiance.at(x, y, c) = 1;
        ProjectOptions opt;
        opt.sh_bands = 2;
        return project(env, opt).coeffs;
    };
    // Y_1,-1 ~ y, Y_1,0 ~ z, Y_1,1 ~ x: the first-band vector points at the hot pixel.
    auto dir = [](const Eigen::MatrixXd& c) { return Eigen::Vector3d(c(3, 0), c(1, 0), c(2, 0)); };
    EXPECT_GT(dir(hot(w / 2, h / 2)).normalized().x(), 0.99);      // centre faces +x
    EXPECT_GT(dir(hot(w / 4, h / 2)).normalized().y(), 0.99);      // u = 1/4 faces +y
    EXPECT_GT(dir(hot(3 * w / 4, h / 2)).normalized().y(), -1.0);  // finite
    EXPECT_LT(dir(hot(3 * w / 4, h / 2)).normalized().y(), -0.99); // u = 3/4 faces -y
    EXPECT_GT(dir(hot(5, 0)).normalized().z(), 0.99);              // top row: +z pole
    EXPECT_LT(dir(hot(5, h - 1)).normalized().z(), -0.99);         // bottom row: -z pole
    // Seam: the first and last columns both face -x, mirrored in y.
    const Eigen::Vector3d left = dir(hot(0, h / 2)), right = dir(hot(w - 1, h / 2));
    EXPECT_LT(left.normalized().x(), -0.99);
    EXPECT_GT(left.y(), 0.0);
    EXPECT_NEAR(left.y(), -right.y(), 1e-15);
    EXPECT_NEAR(left.x(), right.x(), 1e-15);
}

TEST(ProjectLatLong, RotationMovesTheLight) {
    const int w = 64, h = 32;
    Environment env = latlong(w, h, constant(0));
    for (int c = 0; c < 3; ++c) env.radiance.at(w / 2, h / 2, c) = 1;  // +x
    env.world_from_input = parse_rotation("z=90");
    ProjectOptions opt;
    opt.sh_bands = 4;
    const Eigen::MatrixXd c = project(env, opt).coeffs;
    EXPECT_GT(Eigen::Vector3d(c(3, 0), c(1, 0), c(2, 0)).normalized().y(), 0.99);  // now +y
}

TEST(ProjectLatLong, IdenticalForAnyThreadCount) {
    const Environment env = latlong(512, 256, smooth);
    parallel::set_thread_count(1);
    const Eigen::MatrixXd one = project_latlong(env.radiance, 9);
    parallel::set_thread_count(2);
    const Eigen::MatrixXd two = project_latlong(env.radiance, 9);
    parallel::set_thread_count(0);
    EXPECT_EQ((one - two).cwiseAbs().maxCoeff(), 0.0);
    parallel::set_thread_count(1);
    const Eigen::MatrixXd one_f = project_latlong(env.radiance, 3, LatlongPrecision::kFloatRowSums);
    parallel::set_thread_count(2);
    const Eigen::MatrixXd two_f = project_latlong(env.radiance, 3, LatlongPrecision::kFloatRowSums);
    parallel::set_thread_count(0);
    EXPECT_EQ((one_f - two_f).cwiseAbs().maxCoeff(), 0.0);
}

TEST(Layouts, CubeAndAngularAgreeWithLatLong) {
    // The same smooth function sampled at pixel centres of three layouts. Midpoint quadrature
    // error is O(h^2 |f''|) with h ~ pixel angle (pi/256 here): ~1e-4 of the coefficient scale;
    // the angular map's rim and the pixel supersampling add O(1e-4). Tolerance 2e-3 of L_00.
    ProjectOptions opt;
    opt.sh_bands = 4;
    const Eigen::MatrixXd ll = project(latlong(1024, 512, smooth), opt).coeffs;
    const Eigen::MatrixXd cb = project(cube(256, smooth), opt).coeffs;
    const Eigen::MatrixXd an = project(angular(512, smooth), opt).coeffs;
    const double scale = std::abs(ll(0, 0));
    EXPECT_LT((cb - ll).cwiseAbs().maxCoeff(), 2e-3 * scale);
    EXPECT_LT((an - ll).cwiseAbs().maxCoeff(), 2e-3 * scale);
}

// Rounding of a handful of double operations on O(1) values.
constexpr double kDirectionTol = 1e-14;

TEST(Layouts, CubeTexelsFollowTheOpenGlFaceTable) {
    // testmaps::kCubePins: texel -> direction from the OpenGL ES cube-map table, by hand. Checked
    // on cube_direction and on the strip decoding (face order, row = t) of the sample set.
    for (const auto& p : testmaps::kCubePins) {
        const Eigen::Vector3d want = Eigen::Vector3d(p.x, p.y, p.z).normalized();
        const Eigen::Vector3d got = cube_direction(p.face, (p.i + 0.5) / 2, (p.j + 0.5) / 2);
        EXPECT_LT((got - want).norm(), kDirectionTol) << p.face << " " << p.i << " " << p.j;
    }
    Environment env;
    env.layout = Layout::kCube;
    env.radiance = image::Image(12, 2, 3);
    for (int x = 0; x < 12; ++x) {
        for (int y = 0; y < 2; ++y) env.radiance.at(x, y, 0) = float(y * 12 + x);  // texel id
    }
    const auto samples = make_sample_set(env);
    ASSERT_EQ(samples->size(), 24);
    int checked = 0;
    for (int64_t k = 0; k < samples->size(); ++k) {
        Eigen::Vector3d d;
        double w, v[3];
        ASSERT_TRUE(samples->sample(k, d, w, v));
        for (const auto& p : testmaps::kCubePins) {
            if (int(v[0]) != p.j * 12 + p.face * 2 + p.i) continue;
            EXPECT_LT((d - Eigen::Vector3d(p.x, p.y, p.z).normalized()).norm(), kDirectionTol)
                << "texel (" << p.face * 2 + p.i << ", " << p.j << ")";
            ++checked;
        }
    }
    EXPECT_EQ(checked, 24);
}

TEST(Layouts, AngularPixelsFollowDebevecsDefinition) {
    // testmaps::kAngularPins and debevec_angular_uv: Debevec's (u, v) = (Dx r, Dy r) with
    // r = acos(Dz) / (pi sqrt(Dx^2 + Dy^2)), written out independently of angular_direction.
    for (const auto& p : testmaps::kAngularPins) {
        const Eigen::Vector3d want(p.x, p.y, p.z);
        EXPECT_LT((angular_direction(p.u, p.v) - want).norm(), kDirectionTol) << p.u << " " << p.v;
    }
    // Every pixel of a 16 x 16 map through the sample set: Debevec's forward map of its direction
    // lands on the pixel centre (u = -1 + 2 (x + 0.5) / n, v = 1 - 2 (y + 0.5) / n). acos turns
    // a rounding error dz into dz / sin(theta), sin(theta) >= 0.27 at the innermost centres: 1e-12.
    const int n = 16;
    Environment env;
    env.layout = Layout::kAngular;
    env.radiance = image::Image(n, n, 3);
    for (int y = 0; y < n; ++y) {
        for (int x = 0; x < n; ++x) env.radiance.at(x, y, 0) = float(y * n + x);
    }
    const auto samples = make_sample_set(env);
    int checked = 0;
    for (int64_t k = 0; k < samples->size(); ++k) {
        Eigen::Vector3d d;
        double w, v[3];
        if (!samples->sample(k, d, w, v)) continue;
        const int x = int(v[0]) % n, y = int(v[0]) / n;
        const Eigen::Vector2d centre(-1 + 2.0 * (x + 0.5) / n, 1 - 2.0 * (y + 0.5) / n);
        if (centre.norm() > 1) continue;  // pixels straddling the rim take the rim's direction
        EXPECT_LT((testmaps::debevec_angular_uv(d) - centre).norm(), 1e-12) << x << " " << y;
        ++checked;
    }
    EXPECT_EQ(checked, 208);  // pixel centres inside the unit disc of a 16 x 16 grid
}

TEST(Layouts, ConstantCubeAndAngularSolidAngles) {
    ProjectOptions opt;
    opt.sh_bands = 3;
    const ProjectResult c = project(cube(7, constant(1)), opt);
    EXPECT_NEAR(c.covered_solid_angle_sr, 4 * kPi, 1e-12);  // exact texel solid angles
    EXPECT_NEAR(c.coeffs(0, 0), 2 * std::sqrt(kPi), 1e-12);
    // Octahedral symmetry of the cube cancels bands 1..3 exactly: irradiance is pi exactly.
    for (const auto& n : validation_normals(20))
        EXPECT_NEAR(sh_irradiance(c.coeffs, 3, {n})(0, 0), kPi, 1e-12);
    // Angular: 4x4 sub-sampled Jacobian; rim coverage error O(delta^2), delta = 1/(2 n): 1e-3.
    const ProjectResult a = project(angular(128, constant(1)), opt);
    EXPECT_NEAR(a.covered_solid_angle_sr, 4 * kPi, 1e-3 * 4 * kPi);
}


// The exact SH coefficients (3 bands) of a function of degree <= 2 in x, y, z: Gauss-Legendre
// in cos(theta) (4 nodes, exact to degree 7) times 8 equal steps in phi (exact for trigonometric
// degree < 8); the integrands Y_k f have degree <= 4.
Eigen::MatrixXd exact_coefficients_degree2(const Fn& f) {
    std::vector<double> z, wz;
    sh::gauss_legendre(4, z, wz);
    Eigen::MatrixXd c = Eigen::MatrixXd::Zero(9, 3);
    double y[9];
    for (size_t a = 0; a < z.size(); ++a) {
        for (int b = 0; b < 8; ++b) {
            const double phi = 2 * kPi * b / 8, s = std::sqrt(1 - z[a] * z[a]);
            const Eigen::Vector3d d(s * std::cos(phi), s * std::sin(phi), z[a]);
            sh::eval(3, d, y);
            const Eigen::Vector3d v = f(d);
            for (int k = 0; k < 9; ++k) c.row(k) += (wz[a] * 2 * kPi / 8 * y[k]) * v.transpose();
        }
    }
    return c;
}

TEST(Partial, FisheyeFitBeatsZeroFillOnAFrameCutFromAKnownEnvironment) {
    // Synthetic equidistant fisheye, 165 degree field of view, looking along +z, cut from an
    // environment of SH degree 2 (exactly 3 bands); direction and solid-angle maps as calibrate
    // writes them.
    const double theta_max = 82.5 * kPi / 180;
    auto env_fn = [](const Eigen::Vector3d& d) {
        const double v = 1.0 + 0.6 * d.x() + 0.3 * d.z() - 0.2 * d.y() + 0.25 * d.x() * d.z();
        return Eigen::Vector3d(v, 0.8 * v, 0.6 * v);
    };
    const Environment fe = fisheye_frame(200, theta_max, env_fn);
    check_layout(fe);
    ProjectOptions fit_opt;
    fit_opt.sh_bands = 3;
    fit_opt.fit_lambda = 0;
    ProjectOptions zero_opt = fit_opt;
    zero_opt.partial = PartialMethod::kZeroFill;
    const ProjectResult fit = project(fe, fit_opt);
    const ProjectResult zero = project(fe, zero_opt);
    const Eigen::MatrixXd truth = exact_coefficients_degree2(env_fn);
    EXPECT_TRUE(fit.fitted);
    // Covered solid angle: 2 pi (1 - cos 82.5 deg) up to the pixelated rim (1 pixel ring).
    EXPECT_NEAR(fit.covered_solid_angle_sr, 2 * kPi * (1 - std::cos(theta_max)), 0.05);

    // A function inside the fitted span is recovered exactly by an unregularised least-squares
    // fit, whatever the pixel quadrature: the only error is the float32 storage of the frame.
    // Its size: each value rounds by 2^-24 |f|, each stored direction by 2^-24 per component,
    // moving f by at most 2^-24 sqrt(3) |grad f| (|grad f| <= 0.6 + 0.3 + 0.2 + 0.25 = 1.35 on
    // the sphere, per unit of the first channel). The weighted fit turns a perturbation df into
    // dc with |dc| <= |W^1/2 df| / sqrt(lambda_min(G)), G = B^T W B over the observed pixels;
    // the irradiance error at n is then at most |dc| |(A_l Y_k(n))_k|.
    const auto samples = make_sample_set(fe);
    Eigen::MatrixXd gram = Eigen::MatrixXd::Zero(9, 9);
    double df2 = 0, y[9];
    for (int64_t i = 0; i < samples->size(); ++i) {
        Eigen::Vector3d d;
        double w, v[3];
        if (!samples->sample(i, d, w, v)) continue;
        sh::eval(3, d, y);
        const Eigen::Map<const Eigen::Matrix<double, 9, 1>> b(y);
        gram += w * b * b.transpose();
        const double df = 0x1p-24 * (std::abs(v[0]) + std::sqrt(3.0) * 1.35);
        df2 += w * df * df;
    }
    const double lambda_min = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(gram).eigenvalues()[0];
    const double dc_bound = std::sqrt(df2 / lambda_min);
    const auto normals = validation_normals(200, kPi / 3);  // the screen's normals: within 60 deg
    const Eigen::MatrixXd e_true = sh_irradiance(truth, 3, normals);
    const Eigen::MatrixXd e_fit = sh_irradiance(fit.coeffs, 3, normals);
    for (size_t i = 0; i < normals.size(); ++i) {
        sh::eval(3, normals[i], y);
        double kernel2 = 0;
        for (int k = 0; k < 9; ++k) {
            const int l = k < 1 ? 0 : k < 4 ? 1 : 2;
            kernel2 += std::pow(sh::cosine_zonal(l) * y[k], 2);
        }
        // Channel 0 (the others are scaled copies with smaller errors).
        EXPECT_LE(std::abs(e_fit(i, 0) - e_true(i, 0)), dc_bound * std::sqrt(kernel2)) << i;
    }
    const IrradianceError fit_err = irradiance_error(e_fit, e_true);
    const IrradianceError zero_err = irradiance_error(sh_irradiance(zero.coeffs, 3, normals), e_true);
    std::printf("165-deg fisheye: Gram condition %.0f, coefficient error bound %.1e; irradiance "
                "error fit mean %.2e max %.2e, zero-fill mean %.3f max %.3f\n",
                fit.fit.gram_condition, dc_bound, fit_err.mean_rel, fit_err.max_rel,
                zero_err.mean_rel, zero_err.max_rel);
    // Zero-fill loses the light from behind the 165-degree cone, well over 10% for these normals.
    EXPECT_GT(zero_err.mean_rel, 0.1);
}

TEST(Partial, AutomaticLambdaKeepsExactFitsAndTamesWildOnes) {
    // A smooth band-limited positive environment: the unregularised fit is already plausible,
    // so the rule picks lambda = 0 and keeps the exact recovery.
    auto smooth_fn = [](const Eigen::Vector3d& d) {
        const double v = 1.0 + 0.6 * d.x() + 0.3 * d.z() - 0.2 * d.y();
        return Eigen::Vector3d(v, v, v);
    };
    ProjectOptions opt;
    opt.sh_bands = 3;
    const ProjectResult smooth = project(fisheye_frame(160, kPi / 2, smooth_fn), opt);
    EXPECT_TRUE(smooth.fit_lambda_auto);
    EXPECT_EQ(smooth.fit.lambda, 0.0);
    EXPECT_TRUE(smooth.fit_plausible);
    // A lamp near the edge of a hemispherical view: the unregularised fit extrapolates into
    // the unseen hemisphere with irradiance no non-negative light can give; the rule raises
    // lambda until it can, and says so.
    auto lamp_fn = [](const Eigen::Vector3d& d) {
        const double lamp = d.dot(Eigen::Vector3d(0.9, 0, 0.436).normalized()) > 0.99 ? 200.0 : 0.0;
        return Eigen::Vector3d::Constant(0.2 + lamp);
    };
    const Environment lamp = fisheye_frame(160, kPi / 2, lamp_fn);
    ProjectOptions raw = opt;
    raw.fit_lambda = 0;
    EXPECT_FALSE(irradiance_is_plausible(project(lamp, raw).coeffs, 3));
    const ProjectResult tamed = project(lamp, opt);
    EXPECT_GT(tamed.fit.lambda, 0.0);
    EXPECT_TRUE(tamed.fit_plausible);
    EXPECT_TRUE(irradiance_is_plausible(tamed.coeffs, 3));
    std::printf("lamp at the edge of a 180-degree view: automatic lambda %.0e\n", tamed.fit.lambda);
}

TEST(Input, NonFinitePixelsRejectedWithPositionOrReplacedAndCounted) {
    image::Image img(8, 4, 3);
    img.at(3, 2, 1) = std::nanf("");
    img.at(5, 1, 0) = INFINITY;
    img.at(0, 0, 0) = -0.01f;
    image::Image copy = img;
    try {
        scan_pixels(img, NonFinitePolicy::kReject, "sky.exr");
        FAIL() << "expected an error";
    } catch (const Error& e) {
        const std::string msg = e.what();
        EXPECT_NE(msg.find("sky.exr: pixel (x=5, y=1) channel 0 is Inf"), std::string::npos) << msg;
        EXPECT_NE(msg.find("2 non-finite"), std::string::npos) << msg;
    }
    const InputStats s = scan_pixels(copy, NonFinitePolicy::kZero, "sky.exr");
    EXPECT_EQ(s.nonfinite_values, 2);
    EXPECT_EQ(s.negative_values, 1);
    EXPECT_EQ(copy.at(3, 2, 1), 0.0f);
    EXPECT_FLOAT_EQ(float(s.min_value), -0.01f);
}

TEST(Input, ParallelScanEqualsASerialScan) {
    // 1024 x 512 x 3 values span two of the scan's 2^20-value chunks: min, max and counts
    // against a plain serial loop; -Inf and NaN in either chunk neither count as negative nor
    // reach min/max, and the error names the first one in memory order.
    image::Image img(1024, 512, 3);
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<float> u(-0.5f, 900.0f);
    for (float& p : img.pixels) p = u(rng);
    img.pixels[1200000] = -INFINITY;  // second chunk
    img.pixels[700001] = std::nanf("");  // first chunk: named first
    double lo = INFINITY, hi = -INFINITY;
    int64_t negative = 0;
    for (float v : img.pixels) {
        if (!std::isfinite(v)) continue;
        lo = std::min(lo, double(v));
        hi = std::max(hi, double(v));
        negative += v < 0;
    }
    image::Image copy = img;
    const InputStats s = scan_pixels(copy, NonFinitePolicy::kZero, "big.exr");
    EXPECT_EQ(s.nonfinite_values, 2);
    EXPECT_EQ(s.negative_values, negative);
    EXPECT_EQ(s.min_value, lo);
    EXPECT_EQ(s.max_value, hi);
    EXPECT_EQ(copy.pixels[1200000], 0.0f);
    EXPECT_EQ(copy.pixels[700001], 0.0f);
    try {
        scan_pixels(img, NonFinitePolicy::kReject, "big.exr");
        FAIL() << "expected an error";
    } catch (const Error& e) {
        // value 700001 = pixel 233333 (x = 885, y = 227), channel 2
        const std::string msg = e.what();
        EXPECT_NE(msg.find("big.exr: pixel (x=885, y=227) channel 2 is NaN"), std::string::npos)
            << msg;
    }
}

TEST(Input, WrongAspectNamesTheFileAndSize) {
    Environment env;
    env.source = "sky.exr";
    env.radiance = image::Image(1024, 1000, 3);
    try {
        check_layout(env);
        FAIL();
    } catch (const Error& e) {
        EXPECT_STREQ(e.what(), "sky.exr: expected a 2:1 lat-long map, got 1024x1000");
    }
    env.layout = Layout::kCube;
    EXPECT_THROW(check_layout(env), Error);
    env.layout = Layout::kFisheye;
    EXPECT_THROW(check_layout(env), Error);  // no direction map
}

TEST(Input, NegativePixelsProjectLinearly) {
    // Slightly negative pixels (present in the blender-data EXRs) are kept: projection is linear.
    Environment env = latlong(64, 32, constant(-1.0 / 1024));  // exact in float32
    ProjectOptions opt;
    EXPECT_NEAR(project(env, opt).coeffs(0, 0), -2 * std::sqrt(kPi) / 1024, 1e-15);
}

// The clamped-cosine kernel truncated to B bands, K_B(t) = sum_{l<B} A_l (2l+1)/(4 pi) P_l(t):
// SH irradiance is E_B(n) = integral L(w) K_B(n.w) dw where the truth has max(n.w, 0).
double truncated_kernel(int bands, double t) {
    double p0 = 1, p1 = t, k = 0;
    for (int l = 0; l < bands; ++l) {
        const double pl = l == 0 ? 1 : l == 1 ? t : ((2.0 * l - 1) * t * p1 - (l - 1.0) * p0) / l;
        if (l >= 2) p0 = p1, p1 = pl;
        k += sh::cosine_zonal(l) * (2 * l + 1) / (4 * kPi) * pl;
    }
    return k;
}

// sup over t of |K_B(t) - max(t, 0)|: for non-negative lighting |E_B(n) - E(n)| <= this *
// integral L dw.
double kernel_error_bound(int bands) {
    double worst = 0;
    for (int i = 0; i <= 20000; ++i) {
        const double t = -1 + 2.0 * i / 20000;
        worst = std::max(worst, std::abs(truncated_kernel(bands, t) - std::max(t, 0.0)));
    }
    return worst;
}

TEST(HardCases, SunThirtyThousandTimesTheSky) {
    const int w = 512, h = 256;
    Environment env = latlong(w, h, constant(1.0));
    for (int c = 0; c < 3; ++c) env.radiance.at(100, 60, c) = 3e4f;
    ProjectOptions opt;
    opt.sh_bands = 9;
    const ProjectResult r = project(env, opt);
    const double sun_sr = latlong_pixel_solid_angle(60, w, h);
    const Eigen::Vector3d sun_dir = latlong_direction(100.5 / w, 60.5 / h);
    const double flux = 4 * kPi + (3e4 - 1) * sun_sr;
    EXPECT_NEAR(r.coeffs(0, 0), flux / (2 * std::sqrt(kPi)), kExactRel * flux);
    const auto normals = validation_normals(128);
    const Eigen::MatrixXd ref = brute_force_irradiance(env, normals);
    for (int bands : {2, 3, 5, 9}) {
        const Eigen::MatrixXd est = sh_irradiance(r.coeffs, bands, normals);
        // The error is the truncated kernel's: the sky (constant, all in band 0) has none, and
        // the sun adds its flux times K_B(n.s) - max(n.s, 0) at its pixel centre s. What is left
        // is the pixel quadrature: pixel-centre brute force against the box-filtered projection,
        // O((pi/h)^2) of the flux (the horizon's kink in max(n.w, 0) for the sky).
        const double slack = 1e-3 * flux;
        double worst_pred = 0;
        for (size_t i = 0; i < normals.size(); ++i) {
            const double t = normals[i].dot(sun_dir);
            const double predicted =
                (3e4 - 1) * sun_sr * (truncated_kernel(bands, t) - std::max(t, 0.0));
            worst_pred = std::max(worst_pred, std::abs(predicted));
            EXPECT_NEAR(est(i, 0) - ref(i, 0), predicted, slack) << bands << " bands, normal " << i;
        }
        const IrradianceError e = irradiance_error(est, ref);
        std::printf("sun 3e4 over sky 1: %d bands mean rel %.3f max rel %.3f; largest predicted "
                    "error %.3f of the flux\n",
                    bands, e.mean_rel, e.max_rel, worst_pred / flux);
    }
}

struct RealMap {
    std::string name, path;
    Layout layout;
};

std::vector<RealMap> real_maps() {
    std::vector<RealMap> maps;
    const std::string blender = inlight::testing::blender_hdri_dir();
    if (!blender.empty()) {
        for (const char* n : inlight::testing::kBlenderHdris)
            maps.push_back({n, blender + "/" + n + ".exr", Layout::kLatLong});
    }
    const std::string probes = inlight::testing::shared_data("probes-latlong");
    if (!probes.empty()) {
        for (const char* n : {"ennis", "grace", "pisa", "uffizi", "wells"})
            maps.push_back({n, probes + "/" + n + ".hdr", Layout::kLatLong});
    }
    return maps;
}

TEST(RealData, ShIrradianceAgainstBruteForceOnEveryHdri) {
    const auto maps = real_maps();
    if (maps.empty()) GTEST_SKIP() << "no blender-data HDRIs and no ../shared/data/probes-latlong";
    const auto normals = validation_normals(128);
    std::printf("%-10s %9s | mean/max relative irradiance error, RMS/mean, for 2, 3, 5, 9 bands\n",
                "map", "peak");
    for (const auto& m : maps) {
        LoadOptions lo;
        lo.layout = m.layout;
        InputStats stats;
        const Environment env = load_environment(m.path, lo, &stats);
        ProjectOptions opt;
        opt.sh_bands = 9;
        const ProjectResult r = project(env, opt);
        const Eigen::MatrixXd ref = brute_force_irradiance(env, normals);
        double abs_flux = 0;  // integral of |L| (luminance), for the bound
        {
            const auto samples = make_sample_set(env);
            Eigen::Vector3d d;
            double w, v[3];
            for (int64_t i = 0; i < samples->size(); ++i) {
                samples->sample(i, d, w, v);
                abs_flux += w * std::abs(luminance(v[0], v[1], v[2]));
            }
        }
        std::printf("%-10s %9.0f |", m.name.c_str(), stats.max_value);
        double prev_rms_abs = INFINITY;
        for (int bands : {3, 5, 9}) {
            const Eigen::MatrixXd est = sh_irradiance(r.coeffs, bands, normals);
            double max_abs = 0, rms_abs = 0;
            for (int i = 0; i < est.rows(); ++i) {
                const double d = luminance(est(i, 0), est(i, 1), est(i, 2)) -
                                 luminance(ref(i, 0), ref(i, 1), ref(i, 2));
                max_abs = std::max(max_abs, std::abs(d));
                rms_abs += d * d;
            }
            rms_abs = std::sqrt(rms_abs / double(est.rows()));
            // Kernel bound plus the O((pi/h)^2) pixel-centre vs box-filter difference.
            EXPECT_LE(max_abs, (kernel_error_bound(bands) + 2e-3) * abs_flux) << m.name << " " << bands;
            // The L2 error over the sphere of normals is a tail sum over bands: it falls.
            EXPECT_LE(rms_abs, prev_rms_abs * 1.0001) << m.name << " " << bands;
            prev_rms_abs = rms_abs;
        }
        for (int bands : {2, 3, 5, 9}) {
            const IrradianceError e = irradiance_error(sh_irradiance(r.coeffs, bands, normals), ref);
            std::printf("  %.4f/%.4f/%.4f", e.mean_rel, e.max_rel, e.rms_over_mean);
        }
        std::printf("\n");
    }
}

}  // namespace
}  // namespace inlight::envmap
