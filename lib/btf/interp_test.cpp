#include "btf/interp.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "core/conventions.h"
#include "testing/testing.h"

namespace inlight::btf {
namespace {

/// Weights are ratios of 3x3 determinants of unit vectors: rounding is a few ulps of O(1)
/// numbers, so 1e-12 bounds them with margin.
constexpr double kWeightTol = 1e-12;

Eigen::Vector3d dir(double theta_deg, double phi_deg) {
    return Direction{theta_deg, phi_deg}.vector();
}

/// Uniform directions over the upper hemisphere from a fixed seed.
std::vector<Eigen::Vector3d> random_upper(int n, unsigned seed, double max_theta_deg = 90) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0, 1);
    std::vector<Eigen::Vector3d> out;
    const double zmin = std::cos(max_theta_deg * kPi / 180);
    for (int i = 0; i < n; ++i) {
        const double z = zmin + (1 - zmin) * u(rng), phi = 2 * kPi * u(rng);
        const double r = std::sqrt(std::max(0.0, 1 - z * z));
        out.emplace_back(r * std::cos(phi), r * std::sin(phi), z);
    }
    return out;
}

void expect_valid(const DirectionWeights& w, int n) {
    ASSERT_GE(w.count, 1);
    ASSERT_LE(w.count, 3);
    double s = 0;
    for (int i = 0; i < w.count; ++i) {
        EXPECT_GE(w.weight[size_t(i)], 0.0);
        EXPECT_GE(w.index[size_t(i)], 0);
        EXPECT_LT(w.index[size_t(i)], n);
        s += w.weight[size_t(i)];
    }
    EXPECT_NEAR(s, 1.0, kWeightTol);
}

/// sum_i w_i P_i: for exact barycentrics of the ray through q, a vector parallel to q.
Eigen::Vector3d blend(const DirectionWeights& w, const std::vector<Direction>& set) {
    Eigen::Vector3d p = Eigen::Vector3d::Zero();
    for (int i = 0; i < w.count; ++i) p += w.weight[size_t(i)] * set[size_t(w.index[size_t(i)])].vector();
    return p;
}

double sin_angle(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    return a.cross(b).norm() / (a.norm() * b.norm());
}

TEST(DelaunayInterpolator, DomeTriangulationHasEulersCountAndEmptyCircumcircles) {
    const auto& dome = ubo2003_dome();
    const DelaunayInterpolator di(dome);
    // A triangulated disc of n points with h on its boundary has 2n - h - 2 triangles.
    EXPECT_EQ(di.triangles().size(), size_t(2 * 81 - 24 - 2));
    EXPECT_EQ(di.boundary().size(), 24u);
    for (const auto& e : di.boundary()) {
        EXPECT_EQ(dome[size_t(e[0])].theta_deg, 75.0);
        EXPECT_EQ(dome[size_t(e[1])].theta_deg, 75.0);
    }
    // Delaunay by brute force: no direction lies beyond a triangle's plane (inside the
    // circumcircle on the sphere). The Bonn rings have cocircular quadruples, hence <= 1e-12.
    for (const auto& t : di.triangles()) {
        const Eigen::Vector3d a = dome[size_t(t[0])].vector(), b = dome[size_t(t[1])].vector(),
                              c = dome[size_t(t[2])].vector();
        const Eigen::Vector3d n = (b - a).cross(c - a).normalized();
        ASSERT_GT(n.dot(a), 0) << "triangle faces the origin";
        for (const Direction& d : dome) EXPECT_LE(n.dot(d.vector() - a), 1e-12);
    }
}

TEST(DelaunayInterpolator, MeasuredDirectionsPoleEdgesAndInteriorAreExact) {
    const auto& dome = ubo2003_dome();
    const DelaunayInterpolator di(dome);
    for (size_t i = 0; i < dome.size(); ++i) {  // a measured direction (and the pole, i = 0)
        const Eigen::VectorXd w = dense_weights(di.weights(dome[i]), 81);
        EXPECT_NEAR(w[int(i)], 1.0, kWeightTol) << i;
    }
    for (const auto& t : di.triangles()) {
        const Eigen::Vector3d a = dome[size_t(t[0])].vector(), b = dome[size_t(t[1])].vector(),
                              c = dome[size_t(t[2])].vector();
        // Mid-edge: the ray through a + b meets the edge halfway, weights 1/2, 1/2, 0.
        const DirectionWeights we = di.weights(Eigen::Vector3d((a + b).normalized()));
        const Eigen::VectorXd w = dense_weights(we, 81);
        EXPECT_NEAR(w[t[0]], 0.5, kWeightTol);
        EXPECT_NEAR(w[t[1]], 0.5, kWeightTol);
        // Interior: the ray through 0.2 a + 0.3 b + 0.5 c has exactly those weights.
        const Eigen::VectorXd wi =
            dense_weights(di.weights(Eigen::Vector3d((0.2 * a + 0.3 * b + 0.5 * c).normalized())), 81);
        EXPECT_NEAR(wi[t[0]], 0.2, kWeightTol);
        EXPECT_NEAR(wi[t[1]], 0.3, kWeightTol);
        EXPECT_NEAR(wi[t[2]], 0.5, kWeightTol);
        EXPECT_NEAR(wi.sum(), 1.0, kWeightTol);
    }
}

TEST(DelaunayInterpolator, RandomQueriesGiveBarycentricsAndAreContinuous) {
    const auto& dome = ubo2003_dome();
    const DelaunayInterpolator di(dome);
    int inside = 0;
    for (const Eigen::Vector3d& q : random_upper(4000, 11)) {
        const DirectionWeights w = di.weights(q);
        expect_valid(w, 81);
        if (w.outside_deg == 0) {
            ++inside;
            EXPECT_EQ(w.count, 3);
            EXPECT_LT(sin_angle(blend(w, dome), q), kWeightTol);  // the ray passes through q
        }
        // Continuity: a step of 1e-7 rad moves the weights by O(1e-7 / triangle size); the
        // dome's triangles are > 10 deg across, so 1e-5 in L1 bounds it with margin, also when
        // the step crosses an edge (a jump would be O(1)).
        const Eigen::Vector3d q2 = (q + 1e-7 * Eigen::Vector3d(0.3, -0.7, 0.2)).normalized();
        const double jump = (dense_weights(w, 81) - dense_weights(di.weights(q2), 81)).lpNorm<1>();
        EXPECT_LT(jump, 1e-5);
    }
    // Above the 75-degree ring lies 1 - cos 75 = 74.1% of the hemisphere's solid angle (the
    // arcs between ring directions rise above it by < 0.21 deg: < 0.4% less). 0.03 is 4 sigma
    // of the binomial count of 4000 queries.
    EXPECT_NEAR(inside / 4000.0, 1 - std::cos(75 * kPi / 180), 0.03);
}

TEST(DelaunayInterpolator, AzimuthSeamAndEdgeCrossingsAreContinuous) {
    const auto& dome = ubo2003_dome();
    const DelaunayInterpolator di(dome);
    for (double theta : {5.0, 22.5, 37.0, 60.0, 74.0}) {
        const Eigen::VectorXd a = dense_weights(di.weights(dir(theta, 360 - 1e-9)), 81);
        const Eigen::VectorXd b = dense_weights(di.weights(dir(theta, 1e-9)), 81);
        EXPECT_LT((a - b).lpNorm<1>(), 1e-8) << theta;  // 2e-9 deg apart: O(1e-10) change
    }
}

TEST(DelaunayInterpolator, BelowTheOutermostRingProjectsToTheBoundary) {
    const auto& dome = ubo2003_dome();
    const DelaunayInterpolator di(dome);
    // Straight below a ring direction: projected onto it (the meridian meets the boundary at
    // that vertex, where two arcs join), moved by 80 - 75 deg.
    const DirectionWeights w = di.weights(dir(80, 15));
    expect_valid(w, 81);
    EXPECT_NEAR(dense_weights(w, 81)[58], 1.0, 1e-9);  // (75, 15): ring 75 starts at 57
    EXPECT_NEAR(w.outside_deg, 5.0, 1e-9);
    // Between two ring directions: on their arc, whose midpoint rises above theta 75:
    // theta_mid = atan(tan 75 cos 7.5) = 74.79 deg, so the move is 90 - 74.79 from the horizon.
    const DirectionWeights h = di.weights(dir(90, 7.5));
    EXPECT_EQ(h.count, 2);
    EXPECT_NEAR(h.weight[0], 0.5, kWeightTol);
    const double mid = std::atan(std::tan(75 * kPi / 180) * std::cos(7.5 * kPi / 180)) * 180 / kPi;
    EXPECT_NEAR(h.outside_deg, 90 - mid, 1e-9);
    // Continuous across the boundary arc: just inside and just outside agree.
    const Eigen::VectorXd in = dense_weights(di.weights(dir(mid - 1e-7, 7.5)), 81);
    const Eigen::VectorXd out = dense_weights(di.weights(dir(mid + 1e-7, 7.5)), 81);
    EXPECT_LT((in - out).lpNorm<1>(), 1e-5);
    // Also a light from below the sample's plane is projected (the caller decides about it).
    expect_valid(di.weights(Eigen::Vector3d(0.6, 0, -0.8)), 81);
}

TEST(DelaunayInterpolator, OneRingAndSparseSetsWork) {
    // One ring (coplanar, not through the origin): a flat polygon, triangulated.
    std::vector<Direction> ring;
    for (int k = 0; k < 8; ++k) ring.push_back({40, 45.0 * k});
    const DelaunayInterpolator dr(ring);
    EXPECT_EQ(dr.triangles().size(), 6u);
    const DirectionWeights w = dr.weights(dir(0, 0));
    expect_valid(w, 8);
    EXPECT_LT(sin_angle(blend(w, ring), dir(0, 0)), kWeightTol);
    // Three directions: one triangle; a query at its vertex takes it alone.
    const std::vector<Direction> three = {{10, 0}, {50, 100}, {60, 250}};
    const DelaunayInterpolator d3(three);
    EXPECT_EQ(d3.triangles().size(), 1u);
    EXPECT_NEAR(dense_weights(d3.weights(three[1]), 3)[1], 1.0, kWeightTol);
    // A set that surrounds the origin has no boundary; every query is inside.
    const std::vector<Direction> sphere = {{0, 0}, {110, 0}, {110, 120}, {110, 240}};
    const DelaunayInterpolator ds(sphere);
    EXPECT_TRUE(ds.boundary().empty());
    const DirectionWeights wd = ds.weights(Eigen::Vector3d(0, 0, -1));
    expect_valid(wd, 4);
    EXPECT_EQ(wd.outside_deg, 0.0);
}

TEST(DelaunayInterpolator, DegenerateAndDuplicatedSetsAreErrors) {
    const std::string dup = testing::error_of([] {
        DelaunayInterpolator({{10, 0}, {30, 50}, {10, 360}, {50, 90}});
    });
    EXPECT_NE(dup.find("directions 0 and 2"), std::string::npos) << dup;
    // Directions on one great circle (the meridian plane phi = 0 / 180): no triangle.
    const std::string gc = testing::error_of([] {
        DelaunayInterpolator({{0, 0}, {30, 0}, {60, 180}, {80, 0}});
    });
    EXPECT_NE(gc.find("great circle"), std::string::npos) << gc;
    EXPECT_NE(testing::error_of([] { DelaunayInterpolator({{0, 0}, {30, 0}}); }).find("at least 3"),
              std::string::npos);
    const DelaunayInterpolator di(ubo2003_dome());
    EXPECT_NE(testing::error_of([&] { di.weights(Eigen::Vector3d(0, 0, 2)); }).find("unit vector"),
              std::string::npos);
    EXPECT_NE(testing::error_of([&] { di.weights(Eigen::Vector3d(NAN, 0, 1)); }).find("unit vector"),
              std::string::npos);
}

TEST(ThesisInterpolator, MeasuredDirectionsPoleSeamAndBeyond) {
    const auto& dome = ubo2003_dome();
    const ThesisInterpolator ti(dome);
    for (size_t i = 0; i < dome.size(); ++i) {
        const DirectionWeights wi = ti.weights(dome[i]);
        EXPECT_EQ(wi.outside_deg, 0.0) << i;  // also on the outermost ring
        EXPECT_NEAR(dense_weights(wi, 81)[int(i)], 1.0, kWeightTol) << i;
    }
    // Between the pole and the 15-degree ring the triangle (pole, C, D) holds the query, so
    // the volumes are its barycentrics: the ray through the blend is the query.
    for (double phi : {0.0, 17.0, 59.9, 180.0, 359.9}) {
        const Eigen::Vector3d q = dir(7.5, phi);
        const DirectionWeights w = ti.weights(q);
        expect_valid(w, 81);
        EXPECT_LT(sin_angle(blend(w, dome), q), kWeightTol) << phi;
    }
    // The azimuth seam: phi just below 360 and just above 0 blend the same directions.
    for (double theta : {7.0, 22.5, 52.0}) {
        const Eigen::VectorXd a = dense_weights(ti.weights(dir(theta, 360 - 1e-9)), 81);
        const Eigen::VectorXd b = dense_weights(ti.weights(dir(theta, 1e-9)), 81);
        EXPECT_LT((a - b).lpNorm<1>(), 1e-8) << theta;
    }
    // Beyond the outermost ring: linear in phi between the two bracketing ring directions.
    ASSERT_EQ(ti.weights(dir(82, 15 + 15 * 0.25)).count, 2);
    EXPECT_NEAR(ti.weights(dir(82, 15 + 15 * 0.25)).outside_deg, 7.0, 1e-9);
    const Eigen::VectorXd d = dense_weights(ti.weights(dir(82, 15 + 15 * 0.25)), 81);
    EXPECT_NEAR(d[58], 0.75, kWeightTol);  // (75, 15)
    EXPECT_NEAR(d[59], 0.25, kWeightTol);  // (75, 30)
    for (const Eigen::Vector3d& q : random_upper(2000, 5)) expect_valid(ti.weights(q), 81);
}

TEST(ThesisInterpolator, SetsWithoutRingsAreErrors) {
    const std::string e = testing::error_of([] { ThesisInterpolator({{0, 0}, {30, 0}, {30, 100}, {30, 240}}); });
    EXPECT_NE(e.find("evenly spaced"), std::string::npos) << e;
    EXPECT_NE(testing::error_of([] { ThesisInterpolator({}); }).find("empty"), std::string::npos);
}

TEST(InterpScheme, NamesRoundTrip) {
    for (auto s : {InterpScheme::kThesis, InterpScheme::kDelaunay, InterpScheme::kNearest})
        EXPECT_EQ(interp_scheme_from_string(to_string(s)), s);
    // The baseline: the largest cosine. (44, 39) is 1 deg from the dome's (45, 40).
    const NearestInterpolator ni(ubo2003_dome());
    const DirectionWeights w = ni.weights(dir(44, 39));
    EXPECT_EQ(w.count, 1);
    EXPECT_EQ(ubo2003_dome()[size_t(w.index[0])].phi_deg, 40.0);
    EXPECT_EQ(ubo2003_dome()[size_t(w.index[0])].theta_deg, 45.0);
    EXPECT_THROW(interp_scheme_from_string("linear"), UsageError);
}

}  // namespace
}  // namespace inlight::btf
