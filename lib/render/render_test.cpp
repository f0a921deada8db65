// Tests of the path tracer against analytic results: the white furnace, a Lambert sphere under
// a real HDRI against brute-force irradiance / pi, agreement of the three light-transport
// estimators, 1/sqrt(N) convergence, determinism over threads and pass schedules, and an OBJ
// quad against the analytic patch.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>

#include "core/conventions.h"
#include "core/parallel.h"
#include "render/path_tracer.h"
#include "render/reference.h"
#include "render/render_testing.h"
#include "testing/testing.h"

namespace inlight::render {
namespace {

/// Per-pixel acceptance |mean - exact| <= kSigmas * se (independent sampler: with the Sobol
/// sampler's few scramble groups se has G - 1 dof and per-pixel tails are too heavy; see
/// expect_noise_predicts_error). With the sample standard error of n >= 64 samples the statistic
/// is ~Student-t; over ~2000 pixel-channels per image a Bonferroni
/// family-wise false-alarm rate of 1e-3 needs a two-sided per-test level of 5e-7, i.e. about 5.0
/// normal sigmas and 5.8 for t with 63 dof; 6 covers both.
constexpr double kSigmas = 6.0;
/// Image-average acceptance: one z-score per channel (3 tests), 1e-3 family-wise -> 3.6 sigmas;
/// 4 is used.
constexpr double kAggregateSigmas = 4.0;

using testscenes::base_scene;

SurfaceMaterial lambert(const std::string& name, const Eigen::Vector3d& albedo) {
    SurfaceMaterial m;
    m.name = name;
    m.brdf.specular = brdf::Model::kLambert;
    m.brdf.albedo = albedo;
    return m;
}

ObjectSpec object(ShapeKind kind, const std::string& material) {
    ObjectSpec o;
    o.shape.kind = kind;
    o.material = material;
    return o;
}

/// A smooth synthetic lat-long map (no file needed): a bright warm spot plus a sky gradient.
image::Image synthetic_sky(int w, int h) {
    image::Image img(w, h, 3);
    const Eigen::Vector3d sun = Eigen::Vector3d(0.3, 0.5, 0.8).normalized();
    for (int row = 0; row < h; ++row) {
        for (int col = 0; col < w; ++col) {
            const Eigen::Vector3d d = latlong_direction((col + 0.5) / w, (row + 0.5) / h);
            const double s = std::pow(std::max(0.0, d.dot(sun)), 20.0) * 30.0;
            const double sky = 0.2 + 0.8 * std::max(0.0, d.z());
            img.at(col, row, 0) = static_cast<float>(sky * 0.6 + s);
            img.at(col, row, 1) = static_cast<float>(sky * 0.8 + 0.8 * s);
            img.at(col, row, 2) = static_cast<float>(sky * 1.0 + 0.5 * s);
        }
    }
    return img;
}

/// Checks every pixel-channel against `exact` within kSigmas standard errors (plus `abs_tol`
/// for quadrature/float error), and the image average within kAggregateSigmas. `mask` selects
/// pixels (empty = all).
void expect_within_noise(const RenderResult& r, const std::vector<Eigen::Vector3d>& exact,
                         const std::vector<bool>& mask, double rel_tol, const std::string& what) {
    int bad = 0, used = 0;
    Eigen::Vector3d sum_diff = Eigen::Vector3d::Zero(), sum_var = Eigen::Vector3d::Zero();
    for (size_t i = 0; i < exact.size(); ++i) {
        if (!mask.empty() && !mask[i]) continue;
        ++used;
        for (int c = 0; c < 3; ++c) {
            const double mean = r.radiance.pixels[i * 3 + static_cast<size_t>(c)];
            const double se = r.std_error.pixels[i * 3 + static_cast<size_t>(c)];
            const double diff = mean - exact[i][c];
            sum_diff[c] += diff;
            sum_var[c] += se * se;
            if (std::abs(diff) > kSigmas * se + rel_tol * std::abs(exact[i][c]) + 1e-6) {
                if (++bad <= 5) {
                    ADD_FAILURE() << what << ": pixel " << i << " channel " << c << ": " << mean
                                  << " vs exact " << exact[i][c] << " (se " << se << ")";
                }
            }
        }
    }
    EXPECT_EQ(bad, 0) << what;
    ASSERT_GT(used, 0);
    for (int c = 0; c < 3; ++c) {
        EXPECT_LE(std::abs(sum_diff[c]), kAggregateSigmas * std::sqrt(sum_var[c]) + 1e-6 * used)
            << what << ": image-average bias in channel " << c << ": mean diff "
            << sum_diff[c] / used << ", se of the mean " << std::sqrt(sum_var[c]) / used;
    }
}

/// Standard deviations of the derived spread (noise_map_log_band) that the noise map's
/// actual / predicted ratio may stray. Over 20 seeds each (white furnace and Lambert sphere
/// below, 2 and 4 scramble groups) the measured sd of log(ratio) was 0.70-1.21x the derived one
/// (20 seeds: +-16%): pixels of one Morton block share a Sobol sequence, which the derivation
/// ignores. 5 derived sd are >= 4.1 measured ones: <= 4e-5 two-sided per check.
constexpr double kNoiseMapSigmas = 5.0;

/// How far the noise map's prediction may stray from the actual error: the half-width of the
/// accepted band for log(RMS error / RMS predicted), kNoiseMapSigmas standard deviations of it.
/// Derivation (Gaussian pixel means; each pixel's three channels come from the same paths, so a
/// pixel is one unit): pixel i's squared error summed over channels has mean S_i (the sum of its
/// channel variances) and variance <= 2 S_i^2, so the image's MSE has relative variance
/// <= 2 / N_eff with N_eff = (sum S_i)^2 / sum S_i^2 (Kish's effective count: a few bright pixels
/// dominate a sum of unequal variances). The map's variance is the spread of G independent
/// group means (dof = G - 1; the Welford variance of n samples, dof = n - 1, with one group),
/// s_i = S_i chi2_dof / dof, so its sum has relative variance <= 2 / (dof N_eff), independent of
/// the error (the mean and the spread of Gaussian group means are independent). Hence
/// sd(log ratio) <= 0.5 sqrt(2 / N_eff (1 + 1 / dof)). N_eff is taken from the map itself:
/// E[s_i^2] <= (1 + 2 / dof) S_i^2, so sum s_i^2 / (1 + 2 / dof) estimates sum S_i^2 without
/// under-stating it when the channels are fully correlated and by less than the channel-wise
/// count would need when they are not.
double noise_map_log_band(const std::vector<double>& pixel_var, int dof) {
    double sum = 0, sum2 = 0;
    for (double s : pixel_var) {
        sum += s;
        sum2 += s * s;
    }
    const double n_eff = sum * sum / (sum2 / (1.0 + 2.0 / dof));
    return kNoiseMapSigmas * 0.5 * std::sqrt(2.0 / n_eff * (1.0 + 1.0 / dof));
}

/// Sobol sampler: the image average is unbiased within its noise (the sum of per-pixel
/// variances; pixels of one Morton block are negatively correlated, so this is conservative),
/// and the noise map predicts the error: RMS(mean - exact) / sqrt(mean se^2) is 1 within
/// noise_map_log_band. `groups` is the render's scramble groups.
void expect_noise_predicts_error(const RenderResult& r, const std::vector<Eigen::Vector3d>& exact,
                                 const std::vector<bool>& mask, int groups,
                                 const std::string& what) {
    double mse = 0, var = 0;
    int used = 0;
    std::vector<double> pixel_var;
    Eigen::Vector3d sum_diff = Eigen::Vector3d::Zero(), sum_var = Eigen::Vector3d::Zero();
    for (size_t i = 0; i < exact.size(); ++i) {
        if (!mask.empty() && !mask[i]) continue;
        ++used;
        pixel_var.push_back(0.0);
        for (int c = 0; c < 3; ++c) {
            const double diff = r.radiance.pixels[i * 3 + static_cast<size_t>(c)] - exact[i][c];
            const double se = r.std_error.pixels[i * 3 + static_cast<size_t>(c)];
            mse += diff * diff;
            var += se * se;
            pixel_var.back() += se * se;
            sum_diff[c] += diff;
            sum_var[c] += se * se;
        }
    }
    ASSERT_GT(used, 100);
    for (int c = 0; c < 3; ++c) {
        EXPECT_LE(std::abs(sum_diff[c]), kAggregateSigmas * std::sqrt(sum_var[c]) + 1e-6 * used)
            << what << ": image-average bias in channel " << c;
    }
    const double band = noise_map_log_band(pixel_var, groups - 1);
    const double ratio = std::sqrt(mse / var);
    std::printf("%s: actual / predicted RMS %.3f, accepted [%.3f, %.3f]\n", what.c_str(), ratio,
                std::exp(-band), std::exp(band));
    EXPECT_GT(ratio, std::exp(-band)) << what << ": the noise map over-states the error";
    EXPECT_LT(ratio, std::exp(band)) << what << ": the noise map under-states the error";
}

TEST(PathTracer, WhiteFurnaceMis) {
    // An albedo-1 Lambert sphere in a constant environment L reflects exactly L everywhere
    // (every path escapes with throughput 1): the image must equal L within its own noise.
    const Eigen::Vector3d l(0.5, 1.0, 2.0);
    SceneDesc d = base_scene(24);
    d.environment.radiance = l;
    d.materials.push_back(lambert("white", {1, 1, 1}));
    d.objects.push_back(object(ShapeKind::kSphere, "white"));
    const Scene scene(d);
    RenderOptions o;
    o.spp = 64;
    const std::vector<Eigen::Vector3d> exact(24 * 24, l);
    o.sampler = SamplerKind::kIndependent;
    const RenderResult r = render(scene, o);
    expect_within_noise(r, exact, {}, 0.0, "white furnace (mis, independent)");
    EXPECT_EQ(r.nonfinite_samples, 0);
    EXPECT_GT(r.std_error.pixels[(12 * 24 + 12) * 3], 0.0f);  // MIS is not trivially exact
    o.sampler = SamplerKind::kSobol;
    expect_noise_predicts_error(render(scene, o), exact, {}, o.scramble_groups,
                                "white furnace (mis, sobol)");
}

TEST(PathTracer, WhiteFurnaceBsdfSamplingIsExact) {
    // With cosine sampling of an albedo-1 Lambert BRDF every path carries exactly L.
    const Eigen::Vector3d l(0.5, 1.0, 2.0);
    SceneDesc d = base_scene(16);
    d.environment.radiance = l;
    d.materials.push_back(lambert("white", {1, 1, 1}));
    d.objects.push_back(object(ShapeKind::kSphere, "white"));
    RenderOptions o;
    o.spp = 16;
    o.strategy = Strategy::kBsdf;
    const RenderResult r = render(Scene(d), o);
    constexpr double kFloatRel = 1e-6;  // float storage and double accumulation of equal values
    for (size_t i = 0; i < r.radiance.pixels.size(); ++i) {
        EXPECT_NEAR(r.radiance.pixels[i], l[static_cast<int>(i % 3)], kFloatRel * 2.0) << i;
    }
}

/// Box-filters a lat-long map by an integer factor (the test's own environment).
image::Image downsample(const image::Image& img, int f) {
    image::Image out(img.width / f, img.height / f, 3);
    for (int y = 0; y < out.height; ++y) {
        for (int x = 0; x < out.width; ++x) {
            for (int c = 0; c < 3; ++c) {
                double s = 0;
                for (int j = 0; j < f; ++j) {
                    for (int i = 0; i < f; ++i) s += img.at(x * f + i, y * f + j, c);
                }
                out.at(x, y, c) = static_cast<float>(s / (f * f));
            }
        }
    }
    return out;
}

TEST(PathTracer, LambertSphereUnderHdriEqualsBruteForceIrradiance) {
    const std::string dir = testing::blender_hdri_dir();
    INLIGHT_SKIP_IF_MISSING(dir, "blender-data HDRIs");
    // city.exr (with its sun, ~34,000) box-filtered 1024x512 -> 64x32; rotated so that no axis
    // is special. A convex sphere has no interreflection: L = albedo / pi * E(n).
    SceneDesc d = base_scene(24);
    d.environment.image = downsample(load_latlong(dir + "/city.exr"), 16);
    d.environment.rotation = "z=70,x=-25";
    const Eigen::Vector3d albedo(0.8, 0.5, 0.3);
    d.materials.push_back(lambert("grey", albedo));
    d.objects.push_back(object(ShapeKind::kSphere, "grey"));
    const Scene scene(d);
    RenderOptions o;
    o.spp = 256;
    o.jitter = false;  // one normal per pixel, so the brute force is a single integral

    // The exact image at pixel centres (render/reference.h: each 5.6-degree pixel of the
    // 64 x 32 map split into 8 x 8 cells of 0.7 degrees, kMaxCellDeg).
    const ConvergenceReference ref = irradiance_reference(scene);
    std::vector<Eigen::Vector3d> exact(24 * 24);
    std::vector<bool> on_sphere(24 * 24, false);
    for (size_t i = 0; i < exact.size(); ++i) {
        on_sphere[i] = ref.object_mask[i] != 0;
        for (int c = 0; c < 3; ++c) exact[i][c] = ref.radiance.pixels[i * 3 + static_cast<size_t>(c)];
    }
    // The clamped cosine's kink at the horizon, midpoint rule on 0.7-degree cells (kMaxCellDeg).
    constexpr double kQuadratureRel = 1e-4;
    o.sampler = SamplerKind::kIndependent;
    expect_within_noise(render(scene, o), exact, on_sphere, kQuadratureRel,
                        "Lambert sphere under city.exr (independent)");
    o.sampler = SamplerKind::kSobol;
    const RenderResult sobol = render(scene, o);
    expect_noise_predicts_error(sobol, exact, on_sphere, o.scramble_groups,
                                "Lambert sphere under city.exr (sobol)");
}

TEST(PathTracer, EstimatorsAgreeWithInterreflection) {
    // A GGX sphere resting on a Lambert patch, seen in perspective: paths bounce between them.
    // MIS, BSDF-only and light-only are three unbiased estimators of the same image; their
    // image averages must agree within their noise (a wrong MIS weight shows up as a bias).
    SceneDesc d = base_scene(20);
    d.camera.projection = Projection::kPerspective;
    d.camera.position = {0, -1.6, 1.4};
    d.camera.look_at = {0, 0, 0.2};
    d.camera.up = {0, 0, 1};
    d.camera.fov_deg = 45;
    d.environment.image = synthetic_sky(64, 32);
    SurfaceMaterial ggx;
    ggx.name = "ggx";
    ggx.brdf.specular = brdf::Model::kGgx;
    ggx.brdf.alpha = 0.3;
    ggx.brdf.f0 = {0.9, 0.7, 0.5};
    ggx.brdf.albedo = {0.2, 0.3, 0.4};
    d.materials.push_back(ggx);
    d.materials.push_back(lambert("floor", {0.7, 0.7, 0.7}));
    ObjectSpec sphere = object(ShapeKind::kSphere, "ggx");
    sphere.shape.center = {0, 0, 0.4};
    sphere.shape.radius = 0.4;
    ObjectSpec floor = object(ShapeKind::kPatch, "floor");
    floor.shape.size = {3, 3};
    d.objects = {sphere, floor};
    const Scene scene(d);
    RenderOptions o;
    o.spp = 128;
    Eigen::Vector3d mean[3], se[3];
    const Strategy strategies[3] = {Strategy::kMis, Strategy::kBsdf, Strategy::kLight};
    for (int k = 0; k < 3; ++k) {
        o.strategy = strategies[k];
        o.seed = 100 + static_cast<uint64_t>(k);
        const RenderResult r = render(scene, o);
        mean[k].setZero();
        Eigen::Vector3d var = Eigen::Vector3d::Zero();
        const size_t n = r.radiance.pixel_count();
        for (size_t i = 0; i < n; ++i) {
            for (int c = 0; c < 3; ++c) {
                mean[k][c] += r.radiance.pixels[i * 3 + static_cast<size_t>(c)];
                const double s = r.std_error.pixels[i * 3 + static_cast<size_t>(c)];
                var[c] += s * s;
            }
        }
        mean[k] /= static_cast<double>(n);
        se[k] = var.cwiseSqrt() / static_cast<double>(n);
    }
    for (int k = 1; k < 3; ++k) {
        for (int c = 0; c < 3; ++c) {
            const double tol = kAggregateSigmas * std::hypot(se[0][c], se[k][c]);
            EXPECT_NEAR(mean[k][c], mean[0][c], tol) << "strategy " << k << " channel " << c;
        }
    }
    // MIS must beat the worse of the two single strategies on this scene (its purpose).
    EXPECT_LT(se[0].sum(), std::max(se[1].sum(), se[2].sum()));
}

SceneDesc small_mixed_scene() {
    SceneDesc d = base_scene(20);
    d.camera.projection = Projection::kPerspective;
    d.camera.position = {0.3, -1.2, 1.5};
    d.camera.look_at = {0, 0, 0.2};
    d.camera.up = {0, 0, 1};
    d.environment.image = synthetic_sky(32, 16);
    SurfaceMaterial sheen;
    sheen.name = "sheen";
    sheen.brdf.specular = brdf::Model::kCharlie;
    sheen.brdf.alpha = 0.4;
    d.materials.push_back(sheen);
    d.materials.push_back(lambert("floor", {0.6, 0.5, 0.4}));
    ObjectSpec sphere = object(ShapeKind::kSphere, "sheen");
    sphere.shape.center = {0, 0, 0.3};
    sphere.shape.radius = 0.3;
    ObjectSpec floor = object(ShapeKind::kPatch, "floor");
    floor.shape.size = {2, 2};
    d.objects = {sphere, floor};
    return d;
}

TEST(PathTracer, BitIdenticalForAnyThreadCountAndPassSchedule) {
    const Scene scene(small_mixed_scene());
    RenderOptions o;
    o.spp = 12;
    o.tile_px = 8;
    parallel::set_thread_count(1);
    const RenderResult a = render(scene, o);
    parallel::set_thread_count(2);
    const RenderResult b = render(scene, o);
    o.snapshot_spp = {1, 2, 3, 4, 5};  // another pass schedule: 1, 1, 1, 1, 1, 7 samples
    const RenderResult c = render(scene, o);
    parallel::set_thread_count(0);
    EXPECT_EQ(a.radiance.pixels, b.radiance.pixels);
    EXPECT_EQ(a.std_error.pixels, b.std_error.pixels);
    EXPECT_EQ(a.rays, b.rays);
    EXPECT_EQ(a.radiance.pixels, c.radiance.pixels);
    EXPECT_EQ(c.snapshots.size(), 5u);
    EXPECT_NE(a.passes, c.passes);
}

TEST(PathTracer, ErrorFallsAsInverseSqrtOfSamples) {
    const Scene scene(small_mixed_scene());
    RenderOptions o;
    o.seed = 9;
    o.sampler = SamplerKind::kIndependent;
    const ConvergenceResult c = convergence_study(scene, o, 1024, {4, 16, 64});
    ASSERT_EQ(c.points.size(), 3u);
    // Slope of log RMSE (reference noise removed) against log N: -0.5 for an unbiased
    // estimator. The MSE of 1200 pixel-channels is itself noisy (~sqrt(2/1200) = 4% relative,
    // 0.02 in log) and the reference's noise correction adds a few %: 0.1 bounds both.
    constexpr double kSlopeTol = 0.1;
    EXPECT_NEAR(c.slope, -0.5, kSlopeTol);
    EXPECT_GT(c.points[0].rel_rmse_corrected, c.points[2].rel_rmse_corrected);
}

TEST(PathTracer, SobolErrorFallsFasterThanInverseSqrtOnDirectLighting) {
    // A Lambert sphere under a smooth sky, pixel-filtered: the integrand is smooth in the light
    // and BSDF dimensions and has one edge (the silhouette) in the pixel dimension, where
    // scrambled nets converge as N^-0.75; the independent sampler stays at -0.5.
    SceneDesc d = base_scene(24);
    d.environment.image = synthetic_sky(64, 32);
    d.materials.push_back(lambert("grey", {0.8, 0.8, 0.8}));
    d.objects.push_back(object(ShapeKind::kSphere, "grey"));
    const Scene scene(d);
    RenderOptions o;
    o.seed = 3;
    const ConvergenceResult c = convergence_study(scene, o, 2048, {16, 64, 256});
    ASSERT_EQ(c.points.size(), 3u);
    // The 3-point slope of ~1700 pixel-channels' RMSE is good to ~0.03 (see the test above);
    // -0.6 leaves 0.1 to the expected ~-0.7 and sits 3 such errors below -0.5.
    constexpr double kSlopeMax = -0.6;
    EXPECT_LT(c.slope, kSlopeMax);
}

/// Relative RMSE of `img` against `ref` and the RMSE its noise map predicts, both / mean(ref),
/// and the accepted band of their log ratio (noise_map_log_band; the reference's own variance,
/// from `ref_groups` groups at many more samples, is added to each pixel's).
struct ErrorAndPrediction {
    double error, predicted, log_band;
};
ErrorAndPrediction error_and_prediction(const RenderResult& r, const RenderResult& ref,
                                        int groups) {
    double mse = 0, var = 0, mean = 0;
    const size_t n = r.radiance.pixels.size();
    std::vector<double> pixel_var(n / 3, 0.0);
    for (size_t i = 0; i < n; ++i) {
        const double d = static_cast<double>(r.radiance.pixels[i]) - ref.radiance.pixels[i];
        const double se = r.std_error.pixels[i], se_ref = ref.std_error.pixels[i];
        mse += d * d;
        var += se * se + se_ref * se_ref;
        pixel_var[i / 3] += se * se + se_ref * se_ref;
        mean += ref.radiance.pixels[i];
    }
    return {std::sqrt(mse / n) / (mean / n), std::sqrt(var / n) / (mean / n),
            noise_map_log_band(pixel_var, groups - 1)};
}

/// The accepted band of log(RMS error / RMS predicted) pooled over K renders of different seeds
/// against one shared reference: `render_var[k][i]` is pixel i's map (channel-summed se^2) of
/// render k, `ref_var[i]` the reference's; both maps have `dof` degrees of freedom. As
/// noise_map_log_band, a pixel is one unit with fully correlated channels (the worst case), but
/// the reference's error r_i is common to the K errors e_ki + r_i: with a_ki, b_i their
/// variances, the pooled squared error D has variance 2 sum_i (sum_k a_ki^2 + 2 b_i sum_k a_ki +
/// K^2 b_i^2) (2 tr(M^2), M = diag(a_i) + b_i 1 1^T), the pooled prediction
/// P = sum_i (sum_k s_ki + K s_ref_i) has variance 2 / dof sum_i (sum_k a_ki^2 + K^2 b_i^2), and
/// sd(log sqrt(D / P)) = 0.5 sqrt(Var D + Var P) / E[P]. Squares are estimated from the maps as
/// in noise_map_log_band (s^2 / (1 + 2 / dof)), cross terms by products of independent maps.
double pooled_noise_map_log_band(const std::vector<std::vector<double>>& render_var,
                                 const std::vector<double>& ref_var, int dof) {
    const double k = static_cast<double>(render_var.size()), sq = 1.0 + 2.0 / dof;
    double var_d = 0, var_p = 0, p = 0;
    for (size_t i = 0; i < ref_var.size(); ++i) {
        const double b = ref_var[i];
        double sum_a = 0, sum_a2 = 0;
        for (const auto& a : render_var) {
            sum_a += a[i];
            sum_a2 += a[i] * a[i] / sq;
        }
        var_d += 2 * (sum_a2 + 2 * b * sum_a + k * k * b * b / sq);
        var_p += 2.0 / dof * (sum_a2 + k * k * b * b / sq);
        p += sum_a + k * b;
    }
    return kNoiseMapSigmas * 0.5 * std::sqrt(var_d + var_p) / p;
}

TEST(PathTracer, AdaptiveSamplingLowersTheErrorAtEqualSamplesAndStaysHonest) {
    // A small Lambert sphere in perspective under a sky with a sun: the noise sits on the
    // sphere (the background is the sky seen directly, nearly noise-free), so spending the same
    // mean spp where v / rays is largest must lower the image's error against a reference, and
    // the noise map must still predict that error.
    SceneDesc d = base_scene(24);
    d.camera.projection = Projection::kPerspective;
    d.camera.position = {0, -3, 0.5};
    d.camera.up = {0, 0, 1};
    d.camera.fov_deg = 30;
    d.environment.image = synthetic_sky(64, 32);
    d.materials.push_back(lambert("grey", {0.8, 0.8, 0.8}));
    ObjectSpec sphere = object(ShapeKind::kSphere, "grey");
    sphere.shape.radius = 0.5;
    d.objects.push_back(sphere);
    const Scene scene(d);
    RenderOptions o;
    o.spp = 2048;
    o.seed = 77;
    const RenderResult ref = render(scene, o);
    o.seed = 5;
    o.spp = 64;
    const RenderResult uniform = render(scene, o);
    o.adaptive = true;
    parallel::set_thread_count(1);
    const RenderResult adaptive = render(scene, o);
    parallel::set_thread_count(2);
    const RenderResult adaptive2 = render(scene, o);
    parallel::set_thread_count(0);
    EXPECT_EQ(adaptive.radiance.pixels, adaptive2.radiance.pixels);  // any thread count
    EXPECT_NEAR(adaptive.mean_spp, 64.0, 1.0);  // the budget: the last pass is clipped to it
    EXPECT_GT(adaptive.max_pixel_spp, 2 * 64);          // it did move samples
    const ErrorAndPrediction uni = error_and_prediction(uniform, ref, o.scramble_groups);
    const ErrorAndPrediction ad = error_and_prediction(adaptive, ref, o.scramble_groups);
    // Equal samples: the error halves here (0.029 against 0.057 when written); each error is
    // good to a few % (576 pixels), so asking for 0.8 cannot pass by luck nor fail by noise.
    constexpr double kMinGain = 0.8;
    EXPECT_LT(ad.error, kMinGain * uni.error);
    // Honest map, as expect_noise_predicts_error. One render cannot be held tighter than
    // [0.46, 2.2] here: the noise sits on a few sphere pixels (the map's effective pixel count
    // is ~40 of 576) and 2 scramble groups give each pixel's variance 1 dof, so the derived sd
    // of log(actual / predicted) is 0.16 (measured 0.12 over 128 seeds). Pooling K renders of
    // other seeds against the same reference divides the renders' part of that variance by K:
    // with K = 8 the derived sd is 0.04-0.055 (measured 0.035 over 16 sets of 8) and 5 of them
    // give [0.76, 1.32] for these seeds. The pooled ratio sat at exp(0.055 +- 0.009) over those
    // 16 sets (~1.2 derived sd, inside the band): the map under-states the error a little as
    // the pixels the sampler chose by their own estimate keep the under-estimates (predicted /
    // actual 0.91-0.92 for adaptive and 0.99 for plain sobol in render-convergence agree).
    constexpr int kPooledRenders = 8;
    std::vector<std::vector<double>> render_var;
    std::vector<double> ref_var(ref.radiance.pixels.size() / 3, 0.0);
    double d2 = 0, p2 = 0;
    for (int k = 0; k < kPooledRenders; ++k) {
        o.seed = 5 + k;  // seed 5 is `adaptive` above
        const RenderResult r = k == 0 ? adaptive : render(scene, o);
        render_var.emplace_back(ref_var.size(), 0.0);
        for (size_t i = 0; i < r.radiance.pixels.size(); ++i) {
            const double diff = static_cast<double>(r.radiance.pixels[i]) - ref.radiance.pixels[i];
            const double se = r.std_error.pixels[i], se_ref = ref.std_error.pixels[i];
            d2 += diff * diff;
            p2 += se * se + se_ref * se_ref;
            render_var.back()[i / 3] += se * se;
            if (k == 0) ref_var[i / 3] += se_ref * se_ref;
        }
    }
    const double ratio = std::sqrt(d2 / p2);
    const double band = pooled_noise_map_log_band(render_var, ref_var, o.scramble_groups - 1);
    std::printf("adaptive, %d seeds pooled: actual / predicted RMS %.3f, accepted [%.3f, %.3f] "
                "(one render: %.3f in [%.3f, %.3f])\n",
                kPooledRenders, ratio, std::exp(-band), std::exp(band), ad.error / ad.predicted,
                std::exp(-ad.log_band), std::exp(ad.log_band));
    EXPECT_GT(ratio, std::exp(-band)) << "the adaptive noise map over-states the error";
    EXPECT_LT(ratio, std::exp(band)) << "the adaptive noise map under-states the error";
}

TEST(PathTracer, StopsAtTargetRelativeError) {
    const Scene scene(small_mixed_scene());
    RenderOptions o;
    o.spp = 4096;
    o.target_rel_error = 0.05;
    const RenderResult r = render(scene, o);
    EXPECT_EQ(r.stop_reason, "target_rel_error");
    EXPECT_LE(r.rel_error, 0.05);
    EXPECT_LT(r.spp, 4096);
}

TEST(PathTracer, ObjQuadRendersLikeTheAnalyticPatch) {
    // The same 1x1 fabric patch, once analytic and once as a two-triangle OBJ with uvs, under
    // a checker albedo texture: geometry, normals and uv conventions must match.
    const std::string tmp = testing::temp_dir("render_quad");
    {
        std::ofstream obj(tmp + "/quad.obj");
        obj << "v -0.5 -0.5 0\nv 0.5 -0.5 0\nv 0.5 0.5 0\nv -0.5 0.5 0\n"
               "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nf 1/1 2/2 3/3 4/4\n";
    }
    image::Image checker(4, 4, 3);
    for (int y = 0; y < 4; ++y) {
        for (int x = 0; x < 4; ++x) {
            const float v = ((x + y) % 2) ? 0.9f : 0.1f;
            checker.at(x, y, 0) = v;
            checker.at(x, y, 1) = y == 0 ? 0.9f : v;  // row 0 tinted: catches a v flip
            checker.at(x, y, 2) = v;
        }
    }
    image::write_image(tmp + "/checker.exr", checker);

    auto make = [&](bool mesh) {
        SceneDesc d = base_scene(24);
        d.camera.ortho_height = 0.9;  // inside the patch: no edge pixels
        d.environment.image = synthetic_sky(32, 16);
        SurfaceMaterial m = lambert("cloth", {1, 1, 1});
        m.albedo_texture_path = tmp + "/checker.exr";
        d.materials.push_back(m);
        ObjectSpec o = object(mesh ? ShapeKind::kMesh : ShapeKind::kPatch, "cloth");
        o.mesh_path = tmp + "/quad.obj";
        d.objects.push_back(o);
        return d;
    };
    RenderOptions o;
    o.spp = 32;
    const RenderResult patch = render(Scene(make(false)), o);
    const RenderResult mesh = render(Scene(make(true)), o);
    // Same seed, same paths: only float (Embree) versus double intersection positions differ,
    // by ~1e-7, which moves a bilinear texture lookup by far less than 1e-4 of its range.
    constexpr double kGeomRel = 1e-4;
    for (size_t i = 0; i < patch.radiance.pixels.size(); ++i) {
        EXPECT_NEAR(mesh.radiance.pixels[i], patch.radiance.pixels[i],
                    kGeomRel * (1 + std::abs(patch.radiance.pixels[i])))
            << "pixel " << i / 3 << " channel " << i % 3;
    }
}

}  // namespace
}  // namespace inlight::render
