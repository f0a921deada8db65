// Tests of envmap/lights.h: the cap's irradiance against an independent quadrature, and the
// extraction's hard cases (a sun 30,000x the sky, two suns, an overcast sky, a light at a pole and
// on the seam, a light at the rim of a fisheye's field, clipped pixels).
#include "envmap/lights.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/conventions.h"
#include "core/parallel.h"
#include "envmap/envmap_testing.h"
#include "envmap/project.h"
#include "envmap/validate.h"
#include "sh/quadrature.h"
#include "testing/testing.h"

namespace inlight::envmap {
namespace {

using testmaps::fisheye_frame;
using testmaps::latlong;

// Sums of up to 1e5 double terms of O(1): rounding only.
constexpr double kRoundingRel = 1e-10;

// Independent reference for the cap integral: rings at angle t from the cap's centre have the
// closed form integral over phi of max(0, A + B cos phi) (A = cos b cos t, B = sin b sin t),
// integrated over t by Gauss-Legendre, split where a ring first touches n's horizon.
double cap_reference(double beta, double alpha) {
    auto ring = [&](double t) {
        const double a = std::cos(beta) * std::cos(t), b = std::sin(beta) * std::sin(t);
        if (a >= b) return 2 * kPi * a;
        if (a <= -b) return 0.0;
        const double phi0 = std::acos(-a / b);
        return 2 * (a * phi0 + b * std::sin(phi0));
    };
    std::vector<double> x, w;
    sh::gauss_legendre(48, x, w);
    std::vector<double> cuts = {0.0};
    const double touch = std::abs(kPi / 2 - beta);
    if (touch > 0 && touch < alpha) cuts.push_back(touch);
    cuts.push_back(alpha);
    double sum = 0;
    for (size_t s = 0; s + 1 < cuts.size(); ++s) {
        const double lo = cuts[s], hi = cuts[s + 1];
        for (size_t k = 0; k < x.size(); ++k) {
            const double t = 0.5 * (lo + hi) + 0.5 * (hi - lo) * x[k];
            sum += 0.5 * (hi - lo) * w[k] * ring(t) * std::sin(t);
        }
    }
    return sum;
}

TEST(CapCosineIntegral, MatchesAnIndependentQuadratureOnEitherSideOfTheHorizon) {
    // 48-node Gauss-Legendre per segment; the integrand is smooth inside each segment and
    // behaves as (t - t*)^(3/2) at the split: the rule's error is below 1e-9 of pi sin^2(alpha).
    constexpr double kQuadratureRel = 1e-8;
    for (double alpha : {0.01, 0.1, 0.5, 1.2}) {
        const double full = kPi * std::sin(alpha) * std::sin(alpha);
        for (int i = 0; i <= 60; ++i) {
            const double beta = kPi * i / 60;
            EXPECT_NEAR(cap_cosine_integral(std::cos(beta), alpha), cap_reference(beta, alpha),
                        kQuadratureRel * full)
                << "alpha " << alpha << " beta " << beta;
        }
        // Centre on the horizon: half the cap above it, alpha - sin(alpha) cos(alpha) exactly.
        EXPECT_NEAR(cap_cosine_integral(0.0, alpha), alpha - std::sin(alpha) * std::cos(alpha),
                    1e-14);
    }
}

TEST(LightIrradiance, SmallCapTendsToAPointLightAndWideOneIsNormalised) {
    DirectionalLight l;
    l.direction = Eigen::Vector3d(1, 2, 2) / 3.0;
    l.flux = {2, 3, 4};
    for (const auto& n : validation_normals(40)) {
        l.angular_radius = 1e-6;  // the point limit
        const Eigen::Vector3d point = l.flux * std::max(0.0, n.dot(l.direction));
        EXPECT_LT((light_irradiance(l, n) - point).norm(), 1e-9);
        l.angular_radius = 2e-4;  // the cap formula just above the point branch
        EXPECT_LT((light_irradiance(l, n) - point).norm(), 1e-7 * l.flux.norm());
        // A wide cap wholly above the horizon: flux x mean cosine (1 + cos a) / 2 x n.d.
        l.angular_radius = 0.3;
        if (n.dot(l.direction) > std::sin(0.3)) {
            EXPECT_LT(
                (light_irradiance(l, n) - l.flux * 0.5 * (1 + std::cos(0.3)) * n.dot(l.direction))
                    .norm(),
                1e-12);
        }
    }
}

// The smooth cap's largest departure from the exact one in the horizon band, over pi sin^3(alpha),
// for radii up to 0.8 rad: the small-radius limit 0.0378 (docs/formats.md states it).
constexpr double kSmoothCapBandRel = 0.038;

TEST(SmoothCap, IsTheCapOutsideItsHorizonBandAndMeetsItWithValueAndSlope) {
    for (double alpha : {0.01, 0.1, 0.3, 0.8}) {
        const double s = std::sin(alpha), full = kPi * s * s;
        double worst = 0;
        for (int i = 0; i <= 400; ++i) {
            const double t = -1 + 2.0 * i / 400;
            const double smooth = full * smooth_cap_cosine(t, alpha);
            const double exact = cap_cosine_integral(t, alpha);
            if (t >= s || t <= -s) {
                EXPECT_NEAR(smooth, exact, 1e-15 * full) << alpha << " " << t;
            }
            worst = std::max(worst, std::abs(smooth - exact) / (full * s));
        }
        // In the band the two differ by at most this fraction of the band's scale pi sin^3(alpha)
        // (the limit shape as alpha -> 0 gives 0.0378; 0.032 at 0.3 rad, 0.009 at 0.8 rad).
        EXPECT_LT(worst, kSmoothCapBandRel) << "alpha " << alpha;
        // C1 at both ends of the band: one-sided differences of the quadratic (step h: error h/2
        // of the second derivative 1 / (2 s)).
        const double h = 1e-7 * s;
        EXPECT_NEAR(smooth_cap_cosine(s - h, alpha), s - h, h * h / (4 * s) + 1e-15);
        EXPECT_NEAR((smooth_cap_cosine(s, alpha) - smooth_cap_cosine(s - h, alpha)) / h, 1.0,
                    h / (4 * s) + 1e-8);
        EXPECT_NEAR(smooth_cap_cosine(-s + h, alpha) / h, 0.0, h / (4 * s) + 1e-8);
    }
    // Lights: kSmoothCap shades (1 + cos a) / 2 Phi n.d above the band, like the cap.
    DirectionalLight l;
    l.direction = Eigen::Vector3d(1, 2, 2) / 3.0;
    l.flux = {2, 3, 4};
    l.angular_radius = 0.3;
    for (const auto& n : validation_normals(40)) {
        DirectionalLight smooth = l;
        smooth.shading = LightShading::kSmoothCap;
        if (std::abs(n.dot(l.direction)) >= std::sin(0.3)) {
            EXPECT_LT((light_irradiance(smooth, n) - light_irradiance(l, n)).norm(), 1e-14);
        }
    }
}

// A lat-long map of `sky` (per direction) with discs of uniform radiance added.
struct Disc {
    Eigen::Vector3d centre;
    double radius;  // radians; pixels whose centre lies inside get `radiance`
    double radiance;
};

Environment sky_with_discs(int w, int h, const testmaps::Fn& sky, const std::vector<Disc>& discs) {
    return latlong(w, h, [&](const Eigen::Vector3d& d) -> Eigen::Vector3d {
        for (const auto& disc : discs)
            if (std::acos(std::clamp(d.dot(disc.centre.normalized()), -1.0, 1.0)) < disc.radius)
                return Eigen::Vector3d::Constant(disc.radiance);
        return sky(d);
    });
}

// What a disc over a uniform background should become: flux sum (L - b) Omega and its direction
// sum (L - b) Omega w, over the disc's pixels, computed here from the pixel grid.
struct Expected {
    Eigen::Vector3d flux = Eigen::Vector3d::Zero(), moment = Eigen::Vector3d::Zero();
    int64_t pixels = 0;
};
Expected expected_disc(int w, int h, const Disc& disc, double background) {
    Expected e;
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            const Eigen::Vector3d d = latlong_direction((x + 0.5) / w, (y + 0.5) / h);
            if (std::acos(std::clamp(d.dot(disc.centre.normalized()), -1.0, 1.0)) >= disc.radius)
                continue;
            const double excess = (disc.radiance - background) * latlong_pixel_solid_angle(y, w, h);
            e.flux += Eigen::Vector3d::Constant(excess);
            e.moment += excess * d;
            ++e.pixels;
        }
    }
    return e;
}

void expect_light(const DirectionalLight& l, const Expected& e, double background) {
    EXPECT_EQ(l.samples, e.pixels);
    EXPECT_NEAR(l.background[1], background, 1e-12);
    EXPECT_NEAR(l.flux[0], e.flux[0], kRoundingRel * e.flux[0]);
    EXPECT_LT((l.direction - e.moment.normalized()).norm(), kRoundingRel);
    // The cap with the region's mean cosine |V| / Phi = (1 + cos alpha) / 2 (acos near 1 loses
    // half the digits: 1e-7).
    EXPECT_NEAR(l.angular_radius, std::acos(2 * e.moment.norm() / e.flux[0] - 1), 1e-7);
    EXPECT_FALSE(l.flux_is_lower_bound);
}

testmaps::Fn grey(double v) {
    return [v](const Eigen::Vector3d&) { return Eigen::Vector3d::Constant(v); };
}

TEST(ExtractLights, SunThirtyThousandTimesTheSky) {
    const int w = 256, h = 128;
    const Disc sun{direction_from_spherical(50 * kPi / 180, 30 * kPi / 180), 1.5 * kPi / 180, 3e4};
    const Environment env = sky_with_discs(w, h, grey(1.0), {sun});
    const Extraction ex = extract_lights(env);
    ASSERT_EQ(ex.lights.size(), 1u);
    expect_light(ex.lights[0], expected_disc(w, h, sun, 1.0), 1.0);
    // Pixel centres within 1.5 deg, each 1.4 deg wide: the fitted cap is about the disc's size.
    EXPECT_NEAR(ex.lights[0].angular_radius, 1.5 * kPi / 180, 0.5 * kPi / 180);
    // The residual is the uniform sky: every pixel 1 exactly.
    const Environment res = residual_environment(env, ex, 1);
    EXPECT_EQ(*std::min_element(res.radiance.pixels.begin(), res.radiance.pixels.end()), 1.0f);
    EXPECT_EQ(*std::max_element(res.radiance.pixels.begin(), res.radiance.pixels.end()), 1.0f);
}

TEST(ExtractLights, TwoSunsComeOutStrongestFirst) {
    const int w = 256, h = 128;
    const Disc a{direction_from_spherical(40 * kPi / 180, -60 * kPi / 180), 1.5 * kPi / 180, 3e4};
    const Disc b{direction_from_spherical(70 * kPi / 180, 100 * kPi / 180), 2.5 * kPi / 180, 5e3};
    const Environment env = sky_with_discs(w, h, grey(1.0), {b, a});
    const Extraction ex = extract_lights(env);
    ASSERT_EQ(ex.lights.size(), 2u);
    expect_light(ex.lights[0], expected_disc(w, h, a, 1.0), 1.0);
    expect_light(ex.lights[1], expected_disc(w, h, b, 1.0), 1.0);
    // max_lights caps the count, keeping the strongest.
    ExtractOptions one;
    one.max_lights = 1;
    const Extraction ex1 = extract_lights(env, one);
    ASSERT_EQ(ex1.lights.size(), 1u);
    EXPECT_EQ(ex1.lights[0].samples, ex.lights[0].samples);
}

// The CIE standard overcast sky (Moon and Spencer 1942), L = Lz (1 + 2 cos theta) / 3, over
// ground of albedo 0.3 lit by it (E = 7 pi Lz / 9): no compact bright region anywhere.
Eigen::Vector3d overcast(const Eigen::Vector3d& d) {
    const double lz = 1.0;
    return Eigen::Vector3d::Constant(d.z() > 0 ? lz * (1 + 2 * d.z()) / 3 : 0.3 * 7 * lz / 9);
}

TEST(ExtractLights, OvercastSkyHasNoLight) {
    const Extraction ex = extract_lights(latlong(256, 128, overcast));
    EXPECT_TRUE(ex.lights.empty());
    EXPECT_GT(ex.regions_examined, 0);
}

TEST(ExtractLights, LightExactlyAtEitherPoleIsOneLightOnTheAxis) {
    const int w = 256, h = 128;
    for (double z : {1.0, -1.0}) {
        const Disc pole{{0, 0, z}, 3 * kPi / 180, 1e4};
        const Extraction ex = extract_lights(sky_with_discs(w, h, grey(0.5), {pole}));
        ASSERT_EQ(ex.lights.size(), 1u) << "pole z = " << z;
        expect_light(ex.lights[0], expected_disc(w, h, pole, 0.5), 0.5);
        // Every row of the cap is symmetric in phi: the direction is the axis to rounding.
        EXPECT_LT((ex.lights[0].direction - Eigen::Vector3d(0, 0, z)).norm(), kRoundingRel);
    }
}

TEST(ExtractLights, LightOnTheSeamIsOneLightNotTwo) {
    const int w = 256, h = 128;
    const Disc seam{{-1, 0, 0}, 2.5 * kPi / 180, 1e4};  // u = 0 and u = 1 both face -x
    const Environment env = sky_with_discs(w, h, grey(0.5), {seam});
    const Extraction ex = extract_lights(env);
    ASSERT_EQ(ex.lights.size(), 1u);
    const Expected e = expected_disc(w, h, seam, 0.5);
    expect_light(ex.lights[0], e, 0.5);
    // Its pixels lie in both the first and the last columns.
    bool left = false, right = false;
    for (int64_t px : ex.region_samples[0]) {
        left |= px % w == 0;
        right |= px % w == w - 1;
    }
    EXPECT_TRUE(left && right);
    EXPECT_LT((ex.lights[0].direction - Eigen::Vector3d(-1, 0, 0)).norm(), kRoundingRel);
}

TEST(ExtractLights, ResidualPlusLightsKeepsFluxAndIrradianceOfFullyVisibleNormals) {
    const int w = 256, h = 128;
    const Disc a{direction_from_spherical(35 * kPi / 180, 10 * kPi / 180), 2 * kPi / 180, 2e4};
    const Disc b{direction_from_spherical(60 * kPi / 180, -120 * kPi / 180), 1.5 * kPi / 180, 8e3};
    const Environment env = sky_with_discs(w, h, grey(1.0), {a, b});
    const Extraction ex = extract_lights(env);
    ASSERT_EQ(ex.lights.size(), 2u);
    const Environment res = residual_environment(env, ex, 2);
    ProjectOptions po;
    po.sh_bands = 1;
    const double flux_env = project(env, po).coeffs(0, 1) * 2 * std::sqrt(kPi);
    const double flux_res = project(res, po).coeffs(0, 1) * 2 * std::sqrt(kPi);
    EXPECT_NEAR(flux_res + ex.lights[0].flux[1] + ex.lights[1].flux[1], flux_env,
                kRoundingRel * flux_env);
    // Grey lights: V_c is parallel to d, and the cap's mean cosine is |V| / Phi, so for a normal
    // that sees a whole region E_light(n) = n . V: brute force of residual + lights = original.
    const auto normals = validation_normals(200);
    const Eigen::MatrixXd e_env = brute_force_irradiance(env, normals);
    const Eigen::MatrixXd e_res = brute_force_irradiance(res, normals);
    int checked = 0;
    for (size_t i = 0; i < normals.size(); ++i) {
        bool sees_all = true;
        for (const auto& l : ex.lights)
            sees_all &= std::abs(normals[i].dot(l.direction)) > std::sin(4 * kPi / 180);
        if (!sees_all) continue;
        ++checked;
        Eigen::Vector3d e = e_res.row(static_cast<Eigen::Index>(i)).transpose();
        for (const auto& l : ex.lights) e += light_irradiance(l, normals[i]);
        EXPECT_NEAR(e[1], e_env(static_cast<Eigen::Index>(i), 1), kRoundingRel * e_env.maxCoeff());
    }
    EXPECT_GT(checked, 150);
}

TEST(ExtractLights, ClippedPixelsMakeTheFluxALowerBound) {
    const int w = 256, h = 128;
    const Disc sun{direction_from_spherical(45 * kPi / 180, 0), 1.5 * kPi / 180, 300};
    const Environment env = sky_with_discs(w, h, grey(1.0), {sun});
    image::Image sat(w, h, 1, image::ColorSpace::kData);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) sat.at(x, y, 0) = env.radiance.at(x, y, 0) >= 300 ? 1.f : 0.f;
    const Extraction ex = extract_lights(env, {}, &sat);
    ASSERT_EQ(ex.lights.size(), 1u);
    const DirectionalLight& l = ex.lights[0];
    EXPECT_EQ(l.saturated_samples, l.samples);
    EXPECT_NEAR(l.saturated_flux_fraction, 1.0, kRoundingRel);
    EXPECT_TRUE(l.flux_is_lower_bound);
    EXPECT_FALSE(l.at_field_edge);
    // The flux is what the clipped pixels show (the lower bound), not more.
    EXPECT_NEAR(l.flux[0], expected_disc(w, h, sun, 1.0).flux[0], kRoundingRel * l.flux[0]);
}

TEST(ExtractLights, LampAtTheRimOfAFisheyeFieldIsALowerBound) {
    // 165-degree equidistant fisheye looking along +z; a lamp of radius 4 deg centred at 81 deg
    // (the field ends at 82.5 deg) is cut by the rim; one at 40 deg is seen whole.
    const double theta_max = 82.5 * kPi / 180, radius = 4 * kPi / 180, lamp = 2e3;
    auto frame = [&](double theta_deg) {
        const Eigen::Vector3d c = direction_from_spherical(theta_deg * kPi / 180, 0.7);
        return fisheye_frame(240, theta_max, [&](const Eigen::Vector3d& d) -> Eigen::Vector3d {
            return Eigen::Vector3d::Constant(d.dot(c) > std::cos(radius) ? lamp : 1.0);
        });
    };
    const double full_flux = (lamp - 1) * 2 * kPi * (1 - std::cos(radius));
    const Extraction inside = extract_lights(frame(40));
    ASSERT_EQ(inside.lights.size(), 1u);
    EXPECT_FALSE(inside.lights[0].at_field_edge);
    EXPECT_FALSE(inside.lights[0].flux_is_lower_bound);
    // Pixelated disc: the pixels inside cover its area to ~1 pixel ring (5% at 240 px).
    EXPECT_NEAR(inside.lights[0].flux[0], full_flux, 0.05 * full_flux);
    const Extraction rim = extract_lights(frame(81));
    ASSERT_EQ(rim.lights.size(), 1u);
    const DirectionalLight& l = rim.lights[0];
    EXPECT_TRUE(l.at_field_edge);
    EXPECT_TRUE(l.flux_is_lower_bound);
    EXPECT_LT(l.flux[0], 0.8 * full_flux);  // the cap beyond 82.5 deg is ~1/3 of it
    EXPECT_GT(l.flux[0], 0.3 * full_flux);
    double theta, phi;
    spherical_from_direction(l.direction, theta, phi);
    EXPECT_LT(theta, 81 * kPi / 180);  // the seen part lies inward of the lamp's centre
}

TEST(ExtractLights, NoLightsAskedIsPureSh) {
    ExtractOptions none;
    none.max_lights = 0;
    const Disc sun{{0, 0.6, 0.8}, 2 * kPi / 180, 3e4};
    EXPECT_TRUE(extract_lights(sky_with_discs(128, 64, grey(1.0), {sun}), none).lights.empty());
    ExtractOptions bad;
    bad.grow_contrast = 50;  // above min_peak_contrast
    EXPECT_THROW(extract_lights(sky_with_discs(128, 64, grey(1.0), {sun}), bad), UsageError);
}

TEST(DirectionalLight, JsonRoundTripAndBadValues) {
    DirectionalLight l;
    l.direction = Eigen::Vector3d(0.36, 0.48, 0.8);
    l.flux = {1.5, 2, 0.25};
    l.angular_radius = 0.01;
    const DirectionalLight r = light_from_json(to_json(l), "x.json");
    EXPECT_LT((r.direction - l.direction).norm(), 1e-15);
    EXPECT_LT((r.flux - l.flux).norm(), 1e-15);
    EXPECT_NEAR(r.angular_radius, l.angular_radius, 1e-15);
    EXPECT_EQ(r.shading, LightShading::kCap);
    nlohmann::json j = to_json(l);
    // The shading: written and read; absent (files before it) is the exact cap; else an error.
    l.shading = LightShading::kSmoothCap;
    EXPECT_EQ(to_json(l)["irradiance"], "smooth-cap");
    EXPECT_EQ(light_from_json(to_json(l), "x.json").shading, LightShading::kSmoothCap);
    j.erase("irradiance");
    EXPECT_EQ(light_from_json(j, "x.json").shading, LightShading::kCap);
    j["irradiance"] = "disc";
    EXPECT_EQ(inlight::testing::error_of([&] { light_from_json(j, "x.json"); }),
              "x.json: unknown light irradiance 'disc' (expected cap or smooth-cap)");
    // An option value names the option's subject and is a usage error.
    EXPECT_EQ(to_string(light_shading_from_string("smooth-cap")), "smooth-cap");
    EXPECT_THROW(light_shading_from_string("disc"), UsageError);
    j["flux"][1] = std::nan("");
    EXPECT_EQ(inlight::testing::error_of([&] { light_from_json(j, "x.json: lights[0]"); }),
              "x.json: lights[0]: light flux is not finite");
    j = to_json(l);
    j["direction"] = {0, 0, 2};
    EXPECT_EQ(inlight::testing::error_of([&] { light_from_json(j, "x.json"); }),
              "x.json: light direction must be a unit vector");
}

TEST(ExtractLights, IdenticalForAnyThreadCount) {
    const Disc a{direction_from_spherical(40 * kPi / 180, -60 * kPi / 180), 1.5 * kPi / 180, 3e4};
    const Environment env = sky_with_discs(256, 128, overcast, {a});
    parallel::set_thread_count(1);
    const Extraction one = extract_lights(env);
    parallel::set_thread_count(2);
    const Extraction two = extract_lights(env);
    parallel::set_thread_count(0);
    ASSERT_EQ(one.lights.size(), 1u);
    ASSERT_EQ(two.lights.size(), 1u);
    EXPECT_EQ(one.lights[0].flux, two.lights[0].flux);
    EXPECT_EQ(one.lights[0].direction, two.lights[0].direction);
}

}  // namespace
}  // namespace inlight::envmap
