// Tests of envmap/budget.h: the cost model's counts, the choice of bands and lights on maps
// whose answer is known, the two metrics, the radiance check, and the trade-off on real HDRIs.
#include "envmap/budget.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

#include "brdf/bake.h"
#include "brdf/grid.h"
#include "core/conventions.h"
#include "envmap/envmap_testing.h"
#include "envmap/light_fit.h"
#include "envmap/validate.h"
#include "sh/sh.h"
#include "testing/testing.h"

namespace inlight::envmap {
namespace {

using testmaps::fisheye_frame;
using testmaps::latlong;

TEST(ShaderCost, CountsEveryTermOfTheShader) {
    const CostModel diffuse_only;
    // 3 bands: basis 3 x 9 + irradiance 3 x 9 (A_l != 0 for l = 0, 1, 2).
    EXPECT_EQ(shader_cost(3, 0, diffuse_only).operations, 54);
    // 4 bands: the basis grows to 16 coefficients, the sum does not (A_3 = 0).
    EXPECT_EQ(shader_cost(4, 0, diffuse_only).operations, 3 * 16 + 3 * 9);
    // 1 band: the constant Y_00 needs no basis.
    EXPECT_EQ(shader_cost(1, 0, diffuse_only).operations, 3);
    EXPECT_EQ(shader_cost(3, 2, diffuse_only).operations,
              54 + 2 * (kLightIrradianceOps + kLightDiffuseOps));
    EXPECT_EQ(shader_cost(3, 2, diffuse_only).lighting_floats, 27 + 14);
    // Smooth caps: 15 operations a light's irradiance instead of 45, the same 7 uniforms.
    const CostModel smooth{0, 1, LightShading::kSmoothCap};
    EXPECT_EQ(shader_cost(3, 2, smooth).operations, 54 + 2 * (15 + kLightDiffuseOps));
    EXPECT_EQ(shader_cost(3, 2, smooth).lighting_floats, 27 + 14);
    // With a 1-channel 5-band table: specular at min(3, 5) = 3 bands, 3 texels per corner.
    CostModel table{5, 1};
    const ShaderCost c = shader_cost(3, 1, table);
    EXPECT_EQ(c.specular_bands, 3);
    EXPECT_EQ(c.texture_fetches, 4 * 3);
    EXPECT_EQ(c.operations, 54 + kTableCoordOps + 10 * 9 + 3 * 9 + kLightIrradianceOps +
                                kLightDiffuseOps + kLightSpecularOps);
    // A 3-band table caps the specular bands (and their cost) whatever the lighting's bands.
    EXPECT_EQ(shader_cost(7, 0, CostModel{3, 3}).specular_bands, 3);
    EXPECT_EQ(shader_cost(7, 0, CostModel{3, 3}).texture_fetches, 4 * 3 * 3);
}

// A map whose SH has l <= 2 only: 3 bands are exact.
Eigen::Vector3d band_limited(const Eigen::Vector3d& d) {
    const double v = 1.0 + 0.4 * d.z() + 0.2 * d.x() + 0.3 * (d.x() * d.x() - d.y() * d.y());
    return {v, 0.9 * v, 0.8 * v};
}

TEST(PlanBudget, BandLimitedMapNeedsThreeBandsAndNoLight) {
    BudgetOptions o;
    o.max_error = 1e-3;  // the pixel-centre reference resolves ~1e-4 at 256 x 128
    o.validate_normals = 64;
    const BudgetPlan p = plan_budget(latlong(256, 128, band_limited), o);
    EXPECT_TRUE(p.met);
    EXPECT_EQ(p.lights, 0);
    EXPECT_EQ(p.sh_bands, 3);
    EXPECT_TRUE(p.extraction.lights.empty());
    EXPECT_EQ(p.candidates.size(), 9u);  // no light found: pure SH only
}

TEST(PlanBudget, SunThirtyThousandTimesTheSkyIsOneLightOverOneBand) {
    const Eigen::Vector3d sun = direction_from_spherical(50 * kPi / 180, 30 * kPi / 180);
    const Environment env = latlong(256, 128, [&](const Eigen::Vector3d& d) {
        return Eigen::Vector3d::Constant(d.dot(sun) > std::cos(1.5 * kPi / 180) ? 3e4 : 1.0);
    });
    BudgetOptions o;
    o.max_error = 1e-3;
    o.validate_normals = 64;
    const BudgetPlan p = plan_budget(env, o);
    // The residual is the uniform sky (1 band exact) and the light's model is exact for every
    // normal that sees the whole sun: only normals within its radius of the terminator differ.
    ASSERT_TRUE(p.met);
    EXPECT_EQ(p.lights, 1);
    EXPECT_EQ(p.sh_bands, 1);
    EXPECT_LT(p.candidates[static_cast<size_t>(p.chosen)].irradiance.abs_over_mean, 1e-4);
    // Pure SH cannot meet it at 9 bands: the sun's clamped cosine rings.
    EXPECT_GT(p.candidates[8].irradiance.abs_over_mean, 1e-2);
    EXPECT_LT(p.candidates[static_cast<size_t>(p.chosen)].cost.operations,
              shader_cost(3, 0, {}).operations);
}

TEST(HoldoutNormals, AreUnitAndNoneIsAScoringOrFitNormal) {
    const auto held = holdout_normals(2000);
    ASSERT_EQ(held.size(), 2000u);  // no axes, nothing dropped on the full sphere
    std::vector<Eigen::Vector3d> seen = validation_normals(kDefaultBudgetNormals);
    for (const auto& n : fit_normals(512)) seen.push_back(n);
    double closest = 2;  // least distance between a held-out and a scored or fitted normal
    for (const auto& h : held) {
        EXPECT_NEAR(h.norm(), 1.0, 1e-12);  // a rotation of unit vectors, double rounding
        for (const auto& n : seen) closest = std::min(closest, (h - n).norm());
    }
    // Within 1e-9 rad of another normal would be the same normal. For two unrelated sets of
    // 2000 and 1548 points the closest pair lies about sqrt(4 / (2000 x 1548)) = 1.1e-3 apart
    // (measured 1.08e-3 on 2026-11-28), six orders above that.
    EXPECT_GT(closest, 1e-9);
    // A fisheye frame keeps only the held-out normals within 60 deg of +z.
    for (const auto& h : holdout_normals(500, kPi / 3)) EXPECT_GE(h.z(), 0.5 - 1e-12);
}

TEST(PlanBudget, HoldoutScoresTheChosenModelOffItsNormalsWithoutChangingTheChoice) {
    // A sun on a sky with a gradient: the choice needs a light and a few bands.
    const Eigen::Vector3d sun = direction_from_spherical(70 * kPi / 180, 200 * kPi / 180);
    const Environment env = latlong(256, 128, [&](const Eigen::Vector3d& d) {
        return Eigen::Vector3d::Constant(d.dot(sun) > std::cos(2.0 * kPi / 180) ? 2e3
                                                                               : 1.0 + 0.5 * d.z());
    });
    BudgetOptions o;
    o.max_error = 3e-3;
    o.validate_normals = 200;
    const BudgetPlan plain = plan_budget(env, o);
    o.holdout_normals = 700;
    const BudgetPlan p = plan_budget(env, o);
    // The check only reads the choice.
    ASSERT_EQ(p.chosen, plain.chosen);
    EXPECT_EQ(p.candidates[static_cast<size_t>(p.chosen)].error,
              plain.candidates[static_cast<size_t>(plain.chosen)].error);
    EXPECT_EQ(plain.holdout_count, 0);
    ASSERT_EQ(p.holdout_count, 700);
    // It scores what ships (the chosen lights and the written coefficients), recomputed here
    // from the model's definition: SH irradiance of the residual + every light's cap.
    const auto held = holdout_normals(700);
    Eigen::MatrixXd model = sh_irradiance(p.projection.coeffs, p.sh_bands, held);
    for (size_t i = 0; i < held.size(); ++i)
        for (const auto& l : p.chosen_lights)
            model.row(static_cast<Eigen::Index>(i)) += light_irradiance(l, held[i]).transpose();
    const double expected =
        metric_value(irradiance_error(model, brute_force_irradiance(env, held)), o.metric);
    EXPECT_NEAR(p.holdout_error, expected, 1e-12 * expected);  // same sums, summed in another order
    EXPECT_GT(p.lights, 0);
}

TEST(PlanBudget, MarginRefusesACandidateJustUnderTheBudget) {
    // Pure SH of a gradient sky with a soft blob: the error falls with every odd band count.
    const Eigen::Vector3d blob = direction_from_spherical(40 * kPi / 180, 100 * kPi / 180);
    const Environment env = latlong(128, 64, [&](const Eigen::Vector3d& d) {
        return Eigen::Vector3d::Constant(1.0 + 0.5 * d.z() + 4 * std::pow(std::max(0.0, d.dot(blob)), 8));
    });
    BudgetOptions o;
    o.extract.max_lights = 0;
    o.validate_normals = 128;
    o.max_error = 1.0;
    o.scoring_margin = 0;
    const BudgetPlan all = plan_budget(env, o);
    // A budget equal to the 3-band candidate's error: met by it without a margin, and by a
    // costlier candidate (or none) with one.
    o.max_error = all.candidates[2].error;
    ASSERT_GT(all.candidates[1].error, o.max_error);  // 2 bands miss it: 3 is the cheapest
    const BudgetPlan exact = plan_budget(env, o);
    ASSERT_TRUE(exact.met);
    EXPECT_EQ(exact.sh_bands, 3);
    o.scoring_margin = kDefaultBudgetMargin;
    const BudgetPlan margin = plan_budget(env, o);
    EXPECT_GT(margin.sh_bands, 3);
    if (margin.met)
        EXPECT_LE(margin.candidates[static_cast<size_t>(margin.chosen)].error,
                  o.max_error * (1 - kDefaultBudgetMargin));
}

TEST(PlanBudget, TwoSunsAreTwoLightsOverOneBand) {
    // Two suns on a uniform sky: the residual is uniform (1 band exact) once both are lights;
    // one light leaves the other sun in the SH, which 9 bands cannot hold to 1e-3.
    const Eigen::Vector3d a = direction_from_spherical(40 * kPi / 180, -60 * kPi / 180);
    const Eigen::Vector3d b = direction_from_spherical(70 * kPi / 180, 100 * kPi / 180);
    const Environment env = latlong(256, 128, [&](const Eigen::Vector3d& d) {
        if (d.dot(a) > std::cos(1.5 * kPi / 180)) return Eigen::Vector3d::Constant(3e4);
        if (d.dot(b) > std::cos(2.5 * kPi / 180)) return Eigen::Vector3d::Constant(5e3);
        return Eigen::Vector3d::Constant(1.0);
    });
    BudgetOptions o;
    o.max_error = 1e-3;
    o.validate_normals = 64;
    const BudgetPlan p = plan_budget(env, o);
    ASSERT_EQ(p.extraction.lights.size(), 2u);
    ASSERT_TRUE(p.met);
    EXPECT_EQ(p.lights, 2);
    EXPECT_EQ(p.sh_bands, 1);
    for (const auto& c : p.candidates) {
        if (c.lights == 1) {
            EXPECT_FALSE(c.meets) << c.sh_bands << " bands";
        }
    }
}

TEST(PlanBudget, LightAtAPoleOrOnTheSeamIsOneFittedLightOverOneBand) {
    // A 3-degree disc 2e4 times the sky at either pole and on the lat-long seam (u = 0 and 1
    // both face -x): the region is one light (not one per side of the seam, not a ring of
    // phi), the fit keeps it on its axis, and the uniform residual needs one band.
    const int w = 256, h = 128;
    const double pitch = kPi / h;  // a pixel's angular size in theta
    for (const Eigen::Vector3d& axis :
         {Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(0, 0, -1), Eigen::Vector3d(-1, 0, 0)}) {
        const Environment env = latlong(w, h, [&](const Eigen::Vector3d& d) {
            return Eigen::Vector3d::Constant(d.dot(axis) > std::cos(3 * kPi / 180) ? 2e4 : 1.0);
        });
        BudgetOptions o;
        o.max_error = 1e-3;
        o.validate_normals = 64;
        const BudgetPlan p = plan_budget(env, o);
        ASSERT_EQ(p.extraction.lights.size(), 1u) << axis.transpose();
        ASSERT_TRUE(p.met) << axis.transpose();
        EXPECT_EQ(p.lights, 1);
        EXPECT_EQ(p.sh_bands, 1);
        ASSERT_EQ(p.chosen_lights.size(), 1u);
        EXPECT_TRUE(p.chosen_lights[0].fitted);
        // The disc is rasterised at pixel centres, symmetric about its axis to a pixel: the
        // fitted direction stays within half a pitch of it.
        EXPECT_LT(std::acos(std::min(1.0, p.chosen_lights[0].direction.dot(axis))), pitch / 2)
            << axis.transpose();
    }
}

TEST(PlanBudget, LampCutByTheFisheyeRimIsShadedWithItsFluxStatedAsALowerBound) {
    // A 165-degree frame, a lamp of radius 4 deg centred at 81 deg (the field ends at 82.5):
    // the extraction sees part of it; the plan reports the bound and still checks the model
    // on the directions the camera saw.
    const Eigen::Vector3d lamp = direction_from_spherical(81 * kPi / 180, 0.7);
    const Environment fe = fisheye_frame(200, 82.5 * kPi / 180, [&](const Eigen::Vector3d& d) {
        return Eigen::Vector3d::Constant(d.dot(lamp) > std::cos(4 * kPi / 180) ? 2e3 : 0.5);
    });
    BudgetOptions o;
    o.max_error = 0.01;
    o.max_bands = 5;
    o.validate_normals = 128;
    const BudgetPlan p = plan_budget(fe, o);
    ASSERT_EQ(p.extraction.lights.size(), 1u);
    EXPECT_TRUE(p.extraction.lights[0].at_field_edge);
    EXPECT_TRUE(p.extraction.lights[0].flux_is_lower_bound);
    const nlohmann::json j = to_json(p, o);
    EXPECT_TRUE(j["lights_found"][0]["flux_is_lower_bound"].get<bool>());
    EXPECT_TRUE(j["lights_found"][0]["at_field_edge"].get<bool>());
    // Against what the camera saw, the lamp as a light beats the lamp in a 3-band fit.
    const auto& pure3 = p.candidates[2];
    const auto& lit3 = p.candidates[static_cast<size_t>(o.max_bands + 2)];
    ASSERT_EQ(lit3.lights, 1);
    EXPECT_LT(lit3.irradiance.abs_over_mean, pure3.irradiance.abs_over_mean);
}

// The CIE standard overcast sky over albedo-0.3 ground (as in lights_test.cpp).
Eigen::Vector3d overcast(const Eigen::Vector3d& d) {
    return Eigen::Vector3d::Constant(d.z() > 0 ? (1 + 2 * d.z()) / 3 : 0.3 * 7 / 9.0);
}

TEST(PlanBudget, OvercastSkyFindsNoLightAndPaysForNone) {
    BudgetOptions o;
    o.max_error = 0.01;
    o.validate_normals = 64;
    // Also with the metric fit, whose start pool takes regions down to 0.3% of the flux.
    for (const ShFit fit : {ShFit::kProjection, ShFit::kMetric}) {
        o.sh_fit = fit;
        const BudgetPlan p = plan_budget(latlong(256, 128, overcast), o);
        EXPECT_TRUE(p.extraction.lights.empty()) << to_string(fit);
        EXPECT_EQ(p.lights, 0);
        for (const auto& c : p.candidates) EXPECT_EQ(c.lights, 0);
        EXPECT_EQ(p.candidates[static_cast<size_t>(p.chosen)].cost.operations,
                  shader_cost(p.sh_bands, 0, {}).operations);
    }
}

TEST(PlanBudget, MeanRelativeErrorExplodesOnDarkNormals) {
    // A sky with a bright 10-degree patch over ground of radiance g. As the ground darkens, the
    // normals facing it receive less light while the patch's SH ringing stays the same in
    // absolute terms: their relative errors, and mean_rel, grow; abs_over_mean hardly moves.
    const Eigen::Vector3d patch = direction_from_spherical(0.6, 0.3);
    BudgetOptions o;
    o.max_error = 0.01;
    o.extract.max_lights = 0;
    o.validate_normals = 128;
    std::map<double, IrradianceError> at3;
    std::map<double, int> bands;
    for (double g : {0.3, 1e-3}) {
        const Environment env = latlong(256, 128, [&](const Eigen::Vector3d& d) {
            if (d.z() <= 0) return Eigen::Vector3d::Constant(g);
            return Eigen::Vector3d::Constant(d.dot(patch) > std::cos(0.17) ? 20.0 : 1.0);
        });
        o.metric = ErrorMetric::kAbsOverMean;
        at3[g] = plan_budget(env, o).candidates[2].irradiance;
        o.metric = ErrorMetric::kMeanRel;
        bands[g] = plan_budget(env, o).sh_bands;
        std::printf(
            "ground %.0e, 3 bands: mean_rel %.4f, abs_over_mean %.4f; mean-rel budget "
            "needs %d bands\n",
            g, at3[g].mean_rel, at3[g].abs_over_mean, bands[g]);
    }
    EXPECT_GT(at3[1e-3].mean_rel, 3 * at3[0.3].mean_rel);
    EXPECT_NEAR(at3[1e-3].abs_over_mean, at3[0.3].abs_over_mean, 0.3 * at3[0.3].abs_over_mean);
    EXPECT_GT(bands[1e-3], bands[0.3]);
}

TEST(FitShToMetric, RecoversAnExactModelFromAPerturbedStartInEitherMetric) {
    // The reference is exactly 4 bands of SH plus one smooth-cap light: the fit's unknowns (the
    // coefficients with A_l != 0 and the flux) can reproduce it, so the fitted metric is
    // rounding: the least-squares solve's condition (~1e3 for these columns) x 1e-16.
    constexpr double kRounding = 1e-10;
    const auto normals = fit_normals(256);
    Eigen::MatrixXd truth(sh::count(4), 3);
    for (int i = 0; i < truth.rows(); ++i)
        truth.row(i) << 0.3 / (1 + i), 0.2 / (2 + i), 0.25 * std::cos(i);
    truth.row(0) << 2.0, 1.8, 1.6;
    const DirectionalLight light = testmaps::smooth_light(direction_from_spherical(0.7, 1.1), 0.1,
                                                          Eigen::Vector3d(5, 4, 3));
    const Eigen::MatrixXd e_ref = testmaps::sh_and_lights_irradiance(truth, 4, {light}, normals);
    for (const ErrorMetric metric : {ErrorMetric::kAbsOverMean, ErrorMetric::kMeanRel}) {
        Eigen::MatrixXd c = truth;
        c.row(1) *= 1.5;
        c.row(6) *= -1;
        c.row(sh::index(3, 1)) << 7, 7, 7;  // A_3 = 0: invisible to irradiance, so kept
        std::vector<DirectionalLight> lights{light};
        lights[0].flux *= 0.5;
        const Eigen::MatrixXd start_irr = testmaps::sh_and_lights_irradiance(c, 4, lights, normals);
        const double start = metric_value(irradiance_error(start_irr, e_ref), metric);
        const double fitted = fit_sh_to_metric(c, 4, lights, normals, e_ref, metric);
        EXPECT_GT(start, 0.01);
        EXPECT_LT(fitted, kRounding) << to_string(metric);
        EXPECT_LT((lights[0].flux - light.flux).norm(), kRounding * 1e3);
        EXPECT_EQ(c(sh::index(3, 1), 0), 7.0);
        for (int l : {0, 1, 2})
            for (int m = -l; m <= l; ++m)
                EXPECT_NEAR(c(sh::index(l, m), 2), truth(sh::index(l, m), 2), kRounding * 1e3);
    }
    EXPECT_EQ(sh_fit_from_string("metric"), ShFit::kMetric);
    EXPECT_EQ(to_string(ShFit::kProjection), "projection");
    EXPECT_THROW(sh_fit_from_string("fit"), UsageError);
}

TEST(PlanBudget, MetricFitLowersMeanRelOnNormalsItDidNotSee) {
    // The dark-ground map of the test above: the projection spreads the patch's ringing evenly,
    // so the dark normals carry large relative errors. The mean-rel fit (at the fit normals)
    // moves the error to the bright normals; measured at the validation normals, which are
    // not fit normals (fit_normals turns them off the lattice) and are 4x denser here.
    const Eigen::Vector3d patch = direction_from_spherical(0.6, 0.3);
    const Environment env = latlong(256, 128, [&](const Eigen::Vector3d& d) {
        if (d.z() <= 0) return Eigen::Vector3d::Constant(1e-3);
        return Eigen::Vector3d::Constant(d.dot(patch) > std::cos(0.17) ? 20.0 : 1.0);
    });
    BudgetOptions o;
    o.max_error = 0.01;
    o.metric = ErrorMetric::kMeanRel;
    o.extract.max_lights = 0;
    o.fit_normals = 256;
    o.validate_normals = 1024;
    o.max_bands = 5;
    const BudgetPlan proj = plan_budget(env, o);
    o.sh_fit = ShFit::kMetric;
    const BudgetPlan fit = plan_budget(env, o);
    for (int b : {3, 5}) {
        const auto& p = proj.candidates[static_cast<size_t>(b - 1)];
        const auto& f = fit.candidates[static_cast<size_t>(b - 1)];
        std::printf("%d bands: mean_rel projection %.4f, metric fit %.4f; abs_over_mean %.4f, %.4f\n",
                    b, p.irradiance.mean_rel, f.irradiance.mean_rel, p.irradiance.abs_over_mean,
                    f.irradiance.abs_over_mean);
        EXPECT_TRUE(f.sh_fitted);
        EXPECT_FALSE(p.sh_fitted);
        // The claim is a real gain, not rounding: at least a fifth off (measured: 27% at 3
        // bands, 52% at 5).
        EXPECT_LT(f.irradiance.mean_rel, 0.8 * p.irradiance.mean_rel) << b << " bands";
    }
}

TEST(PlanBudget, UnreachableBudgetKeepsTheLeastError) {
    BudgetOptions o;
    o.max_error = 1e-9;
    o.max_bands = 4;
    o.validate_normals = 32;
    const BudgetPlan p = plan_budget(latlong(128, 64, overcast), o);
    EXPECT_FALSE(p.met);
    for (const auto& c : p.candidates)
        EXPECT_GE(c.error, p.candidates[static_cast<size_t>(p.chosen)].error);
    o.max_error = std::nan("");
    EXPECT_THROW(plan_budget(latlong(128, 64, overcast), o), UsageError);
}

TEST(PlanBudget, FisheyeFrameFitsEveryBandCountAndExtractsTheLamp) {
    // A 165-degree frame of a room with a lamp at 35 deg: the fit of the residual per band
    // count, the lamp shaded analytically, checked on the screen's normals (within 60 deg).
    const Eigen::Vector3d lamp = direction_from_spherical(35 * kPi / 180, 2.0);
    const Environment fe = fisheye_frame(200, 82.5 * kPi / 180, [&](const Eigen::Vector3d& d) {
        const double l = d.dot(lamp) > std::cos(2 * kPi / 180) ? 3e3 : 0.0;
        return Eigen::Vector3d(0.5 + 0.2 * d.x() + l, 0.5 + l, 0.4 + l);
    });
    BudgetOptions o;
    o.max_error = 0.01;
    o.max_bands = 5;
    o.validate_normals = 128;
    const BudgetPlan p = plan_budget(fe, o);
    for (const auto& c : p.candidates)
        std::printf("fisheye: %d lights %d bands: abs_over_mean %.4f mean_rel %.4f\n", c.lights,
                    c.sh_bands, c.irradiance.abs_over_mean, c.irradiance.mean_rel);
    ASSERT_EQ(p.extraction.lights.size(), 1u);
    EXPECT_FALSE(p.extraction.lights[0].at_field_edge);
    EXPECT_TRUE(p.met);
    EXPECT_EQ(p.lights, 1);
    EXPECT_TRUE(p.projection.fitted);
    // At 3 bands the lamp as a light beats the lamp in the fit by far.
    const auto& pure3 = p.candidates[2];
    const auto& lit3 = p.candidates[static_cast<size_t>(o.max_bands + 2)];
    ASSERT_EQ(lit3.lights, 1);
    EXPECT_LT(lit3.irradiance.abs_over_mean, 0.2 * pure3.irradiance.abs_over_mean);
}

TEST(BruteForceRadiance, LambertUnderAConstantSkyIsTheAlbedo) {
    RadianceCheck check;
    check.material.specular = brdf::Model::kLambert;
    check.material.albedo = {0.2, 0.5, 0.8};
    check.table.view = {0, 0, 1};
    const Environment env = latlong(256, 128, testmaps::constant(1.0));
    std::vector<Eigen::Vector3d> normals;
    for (const auto& n : validation_normals(40))
        if (n.z() > 0) normals.push_back(n);
    const Eigen::MatrixXd l = brute_force_radiance(env, check, normals);
    // The pixel-centre rule's own error on the cosine lobe (brute_force_self_error).
    const double self = brute_force_self_error(env, normals);
    for (size_t i = 0; i < normals.size(); ++i)
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(l(static_cast<Eigen::Index>(i), c), check.material.albedo[c], self + 1e-12);
}

TEST(ModelRadiance, SunLightsSpecularMatchesTheBruteForceLobe) {
    // A small sun on a black sky, GGX: the model's radiance is the light alone (the residual is
    // black); it differs from the per-pixel sum by the lobe's curvature over the sun's pixels,
    // second order in (pixel 0.7 deg / lobe width ~alpha rad): (0.012 / 0.25)^2 = 2.3e-3.
    constexpr double kCurvatureRel = 1e-2;
    const Eigen::Vector3d sun = direction_from_spherical(30 * kPi / 180, 1.0);
    const Environment env = latlong(512, 256, [&](const Eigen::Vector3d& d) {
        return Eigen::Vector3d::Constant(d.dot(sun) > std::cos(0.8 * kPi / 180) ? 1e4 : 0.0);
    });
    RadianceCheck check;
    check.material.specular = brdf::Model::kGgx;
    check.material.alpha = 0.25;
    check.material.albedo = {0.3, 0.3, 0.3};
    check.table.sh_bands = 1;
    check.table.grid = brdf::parse_grid("octa:5");
    check.table.view = {0, 0, 1};
    check.table.resize();
    const Extraction ex = extract_lights(env);
    ASSERT_EQ(ex.lights.size(), 1u);
    std::vector<Eigen::Vector3d> normals;  // around the mirror direction of the sun
    for (const auto& n : validation_normals(400))
        if (n.dot((sun + check.table.view).normalized()) > std::cos(0.3)) normals.push_back(n);
    ASSERT_GT(normals.size(), 5u);
    const Eigen::MatrixXd ref = brute_force_radiance(env, check, normals);
    const Eigen::MatrixXd model =
        model_radiance(Eigen::MatrixXd::Zero(1, 3), 1, ex.lights, check, normals);
    for (size_t i = 0; i < normals.size(); ++i)
        EXPECT_NEAR(model(static_cast<Eigen::Index>(i), 1), ref(static_cast<Eigen::Index>(i), 1),
                    kCurvatureRel * ref(static_cast<Eigen::Index>(i), 1));
}

}  // namespace
}  // namespace inlight::envmap
