#include "btf/lighting.h"
#include "btf/sh_lighting.h"

#include <cmath>
#include <limits>

#include <Eigen/Geometry>

#include <gtest/gtest.h>

#include "core/conventions.h"
#include "testing/testing.h"

namespace inlight::btf {
namespace {

constexpr double kDeg = kPi / 180;
/// Sums of ~1e5 positive doubles: relative rounding well below 1e-12.
constexpr double kSumRelTol = 1e-12;

image::Image constant_map(int h, const Eigen::Vector3d& l) {
    image::Image img(2 * h, h, 3);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < 2 * h; ++x)
            for (int c = 0; c < 3; ++c) img.at(x, y, c) = static_cast<float>(l[c]);
    return img;
}

DomeLightingOptions constant_rule() {
    DomeLightingOptions opt;
    opt.rule = CellRule::kConstant;
    return opt;
}

TEST(DomeLighting, ConstantEnvironmentSplitsTheHemisphereExactly) {
    // The equator is a row boundary of an even-height map, so every subsample falls cleanly on
    // one side: the cells' solid angles sum to 2 pi and, under the constant rule, the weights to
    // 2 pi L.
    const Eigen::Vector3d l(0.5, 1.0, 2.0);
    const DomeLighting d = integrate_dome_cells(constant_map(32, l), ubo2003_dome(), constant_rule());
    ASSERT_EQ(d.weight.size(), 81u);
    double omega = 0;
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (size_t k = 0; k < 81; ++k) {
        EXPECT_GT(d.solid_angle_sr[k], 0) << k;
        omega += d.solid_angle_sr[k];
        sum += d.weight[k];
    }
    EXPECT_NEAR(omega, 2 * kPi, 2 * kPi * kSumRelTol);
    for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(sum[c], 2 * kPi * l[c], 2 * kPi * l[c] * kSumRelTol);
        EXPECT_NEAR(d.below_horizon[c], 2 * kPi * l[c], 2 * kPi * l[c] * kSumRelTol);
    }
}

/// Solid angle of the pole's Voronoi cell on the UBO2003 dome, independently: its boundary is
/// the bisector of the pole and the nearest 15-degree direction at each azimuth,
/// tan(theta_b) = (1 - cos 15) / (sin 15 cos(phi - phi_k)), and the area is the integral of
/// 1 - cos(theta_b(phi)) over phi (1-D midpoint rule with 1e5 steps: error < 1e-9 sr).
double pole_cell_solid_angle() {
    const int n = 100000;
    double area = 0;
    for (int i = 0; i < n; ++i) {
        const double phi = 2 * kPi * (i + 0.5) / n;
        double theta_b = kPi / 2;
        for (int k = 0; k < 6; ++k) {
            const double c = std::cos(phi - k * kPi / 3);
            if (c <= 0) continue;
            theta_b = std::min(
                theta_b, std::atan((1 - std::cos(15 * kDeg)) / (std::sin(15 * kDeg) * c)));
        }
        area += (1 - std::cos(theta_b)) * 2 * kPi / n;
    }
    return area;
}

TEST(DomeLighting, PoleCellMatchesItsBisectorBoundary) {
    const int h = 64, s = 16;
    DomeLightingOptions opt;
    opt.subsamples = s;
    const DomeLighting d = integrate_dome_cells(constant_map(h, {1, 1, 1}), ubo2003_dome(), opt);
    const double truth = pole_cell_solid_angle();
    // Only subsamples whose pixel part straddles the boundary can be misassigned: at most the
    // boundary's length (6 sides of the hexagon, 2 tan(7.5 deg) tan(30 deg)... < 0.95 rad)
    // times a subsample's diagonal (theta side pi / (h s); the phi side is shorter near the pole).
    const double perimeter = 0.95, diagonal = std::sqrt(2.0) * kPi / (h * s);
    EXPECT_NEAR(d.solid_angle_sr[0], truth, perimeter * diagonal);
    EXPECT_NEAR(truth, 0.0594, 0.001);  // a regular hexagon of inradius 7.5 deg: 2 sqrt(3) r^2
}

TEST(DomeLighting, OnePixelLightsTheDirectionItFacesInTheSampleFrame) {
    // A 64 x 32 map, black but for the pixel holding (theta 42.2, phi 42.2 deg): the pixel spans
    // theta 39.4..45 and phi 39.4..45 deg, every part nearer to the dome's (45, 40) than to any
    // other direction (the next, (30, 30), is >= 10 deg away).
    const int h = 32, w = 64;
    const Eigen::Vector3d l(3, 2, 1);
    image::Image img(w, h, 3);
    const int col = 24, row = 7;
    for (int c = 0; c < 3; ++c) img.at(col, row, c) = static_cast<float>(l[c]);
    const double omega = latlong_pixel_solid_angle(row, w, h);

    // Under the cosine rule the pixel's weight is its integral of L cos(theta) (in closed form,
    // 2 pi / w (z0^2 - z1^2) / 2, which the subsamples' midpoint rule in z sums exactly) over
    // cos 45 deg.
    const double z0 = std::cos(kPi * row / h), z1 = std::cos(kPi * (row + 1) / h);
    const double cos_omega = 2 * kPi / w * (z0 * z0 - z1 * z1) / 2;
    const auto check = [&](const DomeLighting& d, Direction expected, double scale) {
        const int k = find_direction(ubo2003_dome(), expected).value();
        for (size_t j = 0; j < 81; ++j) {
            for (int c = 0; c < 3; ++c) {
                const double want = static_cast<int>(j) == k ? l[c] * scale : 0.0;
                EXPECT_NEAR(d.weight[j][c], want, l[c] * scale * kSumRelTol) << j;
            }
        }
    };
    check(integrate_dome_cells(img, ubo2003_dome(), constant_rule()), {45, 40}, omega);
    check(integrate_dome_cells(img, ubo2003_dome()), {45, 40}, cos_omega / std::cos(45 * kDeg));
    // Turned by -40 deg about z into the sample frame, the pixel spans phi -0.6..5 deg: (45, 0).
    DomeLightingOptions opt = constant_rule();
    opt.sample_from_env = parse_rotation("z=-40");
    check(integrate_dome_cells(img, ubo2003_dome(), opt), {45, 0}, omega);
}

TEST(DomeLighting, LambertianBtfUnderAConstantSkyFollowsTheRingModel) {
    // A Lambertian BTF, btf = rho cos(theta_l) / pi, under a constant sky L reflects rho L; the
    // dome's sampling gives rho L sum_k cos(theta_k) Omega_k / pi instead. Taking each ring's
    // cells as the band between the mid-angles (7.5, 22.5, ..., 67.5, 90 deg) predicts
    // sum_rings cos(theta_r) 2 (cos a_r - cos b_r) = 1.0589: the dome overestimates a uniform
    // sky by ~6%, because the 75-degree ring's cells reach the horizon. The Voronoi boundary
    // between two rings deviates from their mid-angle by < 1 deg; moving all five by 1 deg
    // changes the sum by sum 2 sin(b) (cos theta_in - cos theta_out) * 0.0175 = 0.018: the bound.
    const DomeLighting d =
        integrate_dome_cells(constant_map(64, {1, 1, 1}), ubo2003_dome(), constant_rule());
    double sum = 0;
    for (size_t k = 0; k < 81; ++k)
        sum += std::cos(ubo2003_dome()[k].theta_deg * kDeg) * d.solid_angle_sr[k] / kPi;
    double ring_model = 0;
    for (int r = 0; r < 6; ++r) {
        const double a = r == 0 ? 0.0 : (15.0 * r - 7.5) * kDeg;
        const double b = r == 5 ? 90.0 * kDeg : (15.0 * r + 7.5) * kDeg;
        ring_model += std::cos(15.0 * r * kDeg) * 2 * (std::cos(a) - std::cos(b));
    }
    EXPECT_NEAR(ring_model, 1.0589, 1e-4);
    EXPECT_NEAR(sum, ring_model, 0.018);
}

/// sum_k cos(theta_k) W_k: what a Lambertian BTF of albedo pi (btf = cos theta_l) reflects.
Eigen::Vector3d lambertian_shading(const DomeLighting& d, const std::vector<Direction>& lights) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (size_t k = 0; k < lights.size(); ++k)
        sum += std::cos(lights[k].theta_deg * kDeg) * d.weight[k];
    return sum;
}

/// A room lit from near the horizon: a uniform sky of 1, a window band at theta 80-88 deg of 50
/// and a sun pixel of 3e4 at theta 86 deg (90 rows), with what a Lambertian BTF (btf = cos)
/// reflects under it computed independently: the integral of L cos(theta) over the upper
/// hemisphere, per map pixel in closed form (2 pi / w (z0^2 - z1^2) / 2).
struct RoomMap {
    image::Image map = constant_map(90, {1, 1, 1});
    double lambertian_truth = 0;
    RoomMap() {
        const int h = map.height, w = map.width;
        for (int row = 40; row < 44; ++row)
            for (int col = 20; col < 60; ++col)
                for (int c = 0; c < 3; ++c) map.at(col, row, c) = 50;
        for (int c = 0; c < 3; ++c) map.at(100, 43, c) = 3e4f;
        for (int row = 0; row < h / 2; ++row) {
            const double z0 = std::cos(kPi * row / h), z1 = std::cos(kPi * (row + 1) / h);
            for (int col = 0; col < w; ++col)
                lambertian_truth += map.at(col, row, 0) * 2 * kPi / w * (z0 * z0 - z1 * z1) / 2;
        }
    }
};

TEST(DomeLighting, CosineRuleShadesALambertianBtfExactlyUnderAnyEnvironment) {
    // RoomMap: the room light the constant rule gets most wrong, and its closed-form truth.
    const RoomMap room;
    const image::Image& img = room.map;
    const double truth = room.lambertian_truth;
    const Eigen::Vector3d cosine = lambertian_shading(integrate_dome_cells(img, ubo2003_dome()), ubo2003_dome());
    const Eigen::Vector3d constant =
        lambertian_shading(integrate_dome_cells(img, ubo2003_dome(), constant_rule()), ubo2003_dome());
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(cosine[c], truth, truth * 1e-12) << c;
    // The constant rule, for contrast: the window and the sun at 80-88 deg get cos 75 deg.
    EXPECT_GT(constant[0] / truth, 1.5);
    // And under a uniform sky the cosine rule gives pi exactly, where the constant rule's ring
    // model gives 1.0589 pi (the test above).
    const Eigen::Vector3d sky =
        lambertian_shading(integrate_dome_cells(constant_map(64, {1, 1, 1}), ubo2003_dome()), ubo2003_dome());
    EXPECT_NEAR(sky[0], kPi, kPi * 1e-12);
}

TEST(DomeLighting, CosineRuleGivesAHorizonLightNoCell) {
    // A light at theta 90 deg (its image is black) owns no cell under the cosine rule, so no
    // division by its zero cosine; its neighbour at 60 deg takes the light it would have had.
    std::vector<Direction> lights = {{0, 0}, {60, 0}, {90, 0}};
    const DomeLighting d = integrate_dome_cells(constant_map(32, {1, 1, 1}), lights);
    EXPECT_EQ(d.solid_angle_sr[2], 0.0);
    EXPECT_EQ(d.weight[2], Eigen::Vector3d::Zero());
    for (const auto& wk : d.weight) EXPECT_TRUE(wk.allFinite());
    EXPECT_NEAR(lambertian_shading(d, lights)[0], kPi, kPi * 1e-12);
    EXPECT_NE(testing::error_of([] { integrate_dome_cells(constant_map(4, {1, 1, 1}), {{90, 0}}); })
                  .find("horizon"),
              std::string::npos);
}

TEST(DomeLighting, BarycentricRuleInterpolatesTheCosineToTheHorizon) {
    // Under the barycentric rule a Lambertian BTF (btf = cos theta_l) is the cosine linearly
    // interpolated over flat triangles of directions whose edges are at most ~21 deg (the
    // dome's 15-degree rings and their diagonals) and black at the horizon: under a uniform
    // sky it reflects pi within the chord error of cos over such an edge, 1 - cos(10.6 deg) =
    // 1.7%: far closer than the constant rule's 5.9%, but not exact like the cosine rule.
    DomeLightingOptions opt;
    opt.rule = CellRule::kBarycentric;
    const DomeLighting d = integrate_dome_cells(constant_map(64, {1, 1, 1}), ubo2003_dome(), opt);
    const double reflected = lambertian_shading(d, ubo2003_dome())[0] / kPi;
    EXPECT_NEAR(reflected, 1.0, 1 - std::cos(10.6 * kDeg));
    RecordProperty("barycentric_uniform_sky", std::to_string(reflected));
    // Every weight is a share of the sky: they sum to the upper hemisphere less the horizon
    // points' share, which only triangles touching the horizon have, all in the band theta
    // 75-90 deg (2 pi cos 75 sr), where it is at most each direction's whole weight.
    double sum = 0;
    for (const auto& wk : d.weight) sum += wk[0];
    EXPECT_LT(sum, 2 * kPi);
    EXPECT_GT(sum, 2 * kPi - 2 * kPi * std::cos(75 * kDeg));
}

TEST(DomeLighting, ExtrapolatedRuleFollowsARatioLinearInThetaBeyondTheLastRing) {
    // A BTF whose btf / cos is rho(theta) = 1 + theta (radians), the same at every azimuth:
    // btf_k = cos(theta_k) rho(theta_k). Lit only by a window band at theta 80-88 deg (beyond the
    // dome's last ring at 75), it reflects 2 pi x the integral of cos rho sin over the band
    // (computed here by Simpson's rule, 2e4 steps: error < 1e-12). The extrapolated rule
    // continues rho linearly from the ring pair 60/75 deg at the same azimuth, so it is exact up
    // to its own midpoint quadrature (16 x 16 subsamples of 1-degree pixels: < 1e-6); the
    // cosine rule holds rho(75 deg) there, 6% low.
    const int h = 180;
    image::Image img = constant_map(h, {0, 0, 0});
    for (int row = 80; row < 88; ++row)
        for (int col = 0; col < 2 * h; ++col)
            for (int c = 0; c < 3; ++c) img.at(col, row, c) = 1;
    auto rho = [](double theta) { return 1 + theta; };
    const int n = 20000;
    const double a = 80 * kDeg, b = 88 * kDeg, step = (b - a) / n;
    double truth = 0;
    for (int i = 0; i <= n; ++i) {
        const double t = a + i * step;
        const double f = std::cos(t) * std::sin(t) * rho(t);
        truth += f * (i == 0 || i == n ? 1 : (i % 2 ? 4 : 2));
    }
    truth *= 2 * kPi * step / 3;
    auto shaded = [&](CellRule rule, bool lambertian) {
        DomeLightingOptions opt;
        opt.rule = rule;
        opt.subsamples = 16;
        const DomeLighting d = integrate_dome_cells(img, ubo2003_dome(), opt);
        double sum = 0;
        for (size_t k = 0; k < d.weight.size(); ++k) {
            const double th = ubo2003_dome()[k].theta_deg * kDeg;
            sum += d.weight[k][0] * std::cos(th) * (lambertian ? 1.0 : rho(th));
        }
        return sum;
    };
    const double extrapolated = shaded(CellRule::kExtrapolated, false);
    const double cosine = shaded(CellRule::kCosine, false);
    EXPECT_NEAR(extrapolated / truth, 1.0, 1e-6);
    EXPECT_LT(cosine / truth, 0.96);
    // A Lambertian BTF (rho constant) stays exact: the partner's negative share cancels.
    double lambert_truth = 0;
    for (int i = 0; i <= n; ++i) {
        const double t = a + i * step;
        lambert_truth += std::cos(t) * std::sin(t) * (i == 0 || i == n ? 1 : (i % 2 ? 4 : 2));
    }
    lambert_truth *= 2 * kPi * step / 3;
    EXPECT_NEAR(shaded(CellRule::kExtrapolated, true) / lambert_truth, 1.0, 1e-6);
    // A light beyond the last ring as a delta: the same continuation.
    const Direction sun{84, 7};
    const DomeLighting d = directional_light_weights(ubo2003_dome(), sun.vector(), {1, 1, 1},
                                                     [] { DomeLightingOptions o; o.rule = CellRule::kExtrapolated; return o; }());
    double reflected = 0;
    for (size_t k = 0; k < d.weight.size(); ++k) {
        const double th = ubo2003_dome()[k].theta_deg * kDeg;
        reflected += d.weight[k][0] * std::cos(th) * rho(th);
    }
    EXPECT_NEAR(reflected, std::cos(84 * kDeg) * rho(84 * kDeg), 1e-12);
}

TEST(DomeLighting, CosineBarycentricRuleIsExactForLambertianAndSpreadsALightOverItsTriangle) {
    // Under RoomMap, btf / cos interpolated with barycentric weights that sum to 1 leaves a
    // Lambertian BTF (btf / cos constant) exact, on the dome and on the set with horizon rings
    // (kSumRelTol: sums of positive doubles).
    const RoomMap room;
    const image::Image& img = room.map;
    const double truth = room.lambertian_truth;
    DomeLightingOptions opt;
    opt.rule = CellRule::kCosineBarycentric;
    for (const auto* set : {&ubo2003_dome(), &ubo2003_horizon_dome()}) {
        const Eigen::Vector3d shaded = lambertian_shading(integrate_dome_cells(img, *set, opt), *set);
        EXPECT_NEAR(shaded[0], truth, truth * kSumRelTol) << set->size();
    }
    // A light at the horizon (its image black) takes no weight; its neighbours stand in.
    const std::vector<Direction> with_horizon = {{0, 0}, {60, 0}, {60, 120}, {60, 240}, {90, 0}};
    const DomeLighting hz = integrate_dome_cells(constant_map(32, {1, 1, 1}), with_horizon, opt);
    EXPECT_EQ(hz.weight[4], Eigen::Vector3d::Zero());
    EXPECT_NEAR(lambertian_shading(hz, with_horizon)[0], kPi, kPi * kSumRelTol);
    // A sun on a light direction goes to it alone; between three, to those three (positive
    // shares whose cosine-weighted sum is its irradiance at the normal, exactly); below the
    // plane, nowhere.
    const auto& dome = ubo2003_dome();
    const DomeLighting on = directional_light_weights(dome, dome[40].vector(), {2, 2, 2}, opt);
    // 1e-9: the other two vertices' coordinates are triple products of unit vectors rounded to
    // ~1e-16 each, clamped at 0, and the direction's own vector is rebuilt from its angles.
    for (size_t k = 0; k < dome.size(); ++k) EXPECT_NEAR(on.weight[k][0], k == 40 ? 2.0 : 0.0, 1e-9) << k;
    const Direction between{52, 33};
    const DomeLighting bt = directional_light_weights(dome, between.vector(), {1, 1, 1}, opt);
    int holders = 0;
    double irradiance = 0;
    for (size_t k = 0; k < dome.size(); ++k) {
        EXPECT_GE(bt.weight[k][0], 0.0);
        if (bt.weight[k][0] > 0) {
            ++holders;
            EXPECT_LT(angle_between_deg(dome[k], between), 20.0) << k;  // a vertex of its triangle
        }
        irradiance += bt.weight[k][0] * std::cos(dome[k].theta_deg * kDeg);
    }
    EXPECT_EQ(holders, 3);
    EXPECT_NEAR(irradiance, std::cos(52 * kDeg), 1e-12);  // three products of doubles of size ~1
    const DomeLighting below = directional_light_weights(dome, Eigen::Vector3d(0, 0, -1), {1, 1, 1}, opt);
    EXPECT_EQ(below.below_horizon, Eigen::Vector3d(1, 1, 1));
}

TEST(DomeLighting, AnyChannelCountGivesEachChannelTheThreeChannelWeightsExactly) {
    // integrate_dome_cells_channels finds each direction's cell once for all channels; every
    // channel must come out bit for bit as integrate_dome_cells gives it (same arithmetic, same
    // row order), under every rule, on both light sets, rotated. Five channels: the room, its
    // transpose, a gradient, and two more.
    const RoomMap room;
    const int w = room.map.width, h = room.map.height;
    image::Image five(w, h, 5), first(w, h, 3), last(w, h, 3);
    for (int row = 0; row < h; ++row)
        for (int col = 0; col < w; ++col) {
            const float v[5] = {room.map.at(col, row, 0), room.map.at(w - 1 - col, h - 1 - row, 0),
                                float(row) / h, float(col) / w, room.map.at(col, row, 0) * float(row % 7)};
            for (int c = 0; c < 5; ++c) five.at(col, row, c) = v[c];
            for (int c = 0; c < 3; ++c) first.at(col, row, c) = v[c];
            for (int c = 0; c < 2; ++c) last.at(col, row, c) = v[3 + c];
        }
    for (const auto* set : {&ubo2003_dome(), &ubo2003_horizon_dome()}) {
        for (CellRule rule : {CellRule::kConstant, CellRule::kCosine, CellRule::kBarycentric,
                              CellRule::kExtrapolated, CellRule::kCosineBarycentric}) {
            DomeLightingOptions o;
            o.rule = rule;
            o.subsamples = 2;
            o.sample_from_env = Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
            const Eigen::MatrixXd all = integrate_dome_cells_channels(five, *set, o);
            const DomeLighting a = integrate_dome_cells(first, *set, o), b = integrate_dome_cells(last, *set, o);
            ASSERT_EQ(all.rows(), static_cast<Eigen::Index>(set->size()));
            ASSERT_EQ(all.cols(), 5);
            for (size_t k = 0; k < set->size(); ++k) {
                const auto r = static_cast<Eigen::Index>(k);
                for (int c = 0; c < 3; ++c) EXPECT_EQ(all(r, c), a.weight[k][c]) << to_string(rule) << " " << k;
                for (int c = 0; c < 2; ++c) EXPECT_EQ(all(r, 3 + c), b.weight[k][c]) << to_string(rule) << " " << k;
            }
        }
    }
    EXPECT_NE(testing::error_of([] { integrate_dome_cells_channels(image::Image(3, 2, 1), ubo2003_dome()); })
                  .find("2:1"),
              std::string::npos);
}

TEST(DomeLighting, CellRuleNamesRoundTrip) {
    EXPECT_EQ(cell_rule_from_string(to_string(CellRule::kConstant)), CellRule::kConstant);
    EXPECT_EQ(cell_rule_from_string(to_string(CellRule::kCosine)), CellRule::kCosine);
    EXPECT_EQ(cell_rule_from_string(to_string(CellRule::kBarycentric)), CellRule::kBarycentric);
    EXPECT_EQ(cell_rule_from_string(to_string(CellRule::kExtrapolated)), CellRule::kExtrapolated);
    EXPECT_EQ(cell_rule_from_string(to_string(CellRule::kCosineBarycentric)), CellRule::kCosineBarycentric);
    EXPECT_NE(testing::error_of([] { cell_rule_from_string("voronoi"); }).find("voronoi"),
              std::string::npos);
}

TEST(DomeLighting, BadInputIsAnError) {
    EXPECT_NE(testing::error_of([] { integrate_dome_cells(image::Image(3, 2, 3), ubo2003_dome()); })
                  .find("2:1"),
              std::string::npos);
    image::Image nan = constant_map(4, {1, 1, 1});
    nan.at(1, 1, 1) = std::numeric_limits<float>::quiet_NaN();
    EXPECT_NE(testing::error_of([&] { integrate_dome_cells(nan, ubo2003_dome()); }).find("NaN"),
              std::string::npos);
    EXPECT_NE(testing::error_of([] { integrate_dome_cells(constant_map(4, {1, 1, 1}), {}); })
                  .find("no light"),
              std::string::npos);
}

}  // namespace
}  // namespace inlight::btf
