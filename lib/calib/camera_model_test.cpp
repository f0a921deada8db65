#include "calib/camera_model.h"

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/calib3d.hpp>
#include <opencv2/ccalib/omnidir.hpp>
#include <random>

#include "core/conventions.h"
#include "core/error.h"

namespace inlight::calib {
namespace {

/// Same formulas evaluated in the same order, so only rounding differs: 1e-9 px.
constexpr double kMatchOpenCvPx = 1e-9;
/// Unproject then project: the inverse converges to 1e-10 normalised units (< 1e-7 px at
/// focal lengths below 1,000 px).
constexpr double kRoundTripPx = 1e-7;

CameraModel fisheye_model() {
    CameraModel m = CameraModel::make(ModelType::kFisheye, 800, 600, 210.5, 209.8, 401.3, 298.6);
    m.skew = 0.35;
    m.distortion = {0.031, -0.012, 0.004, -0.0009};
    return m;
}

CameraModel pinhole_model() {
    CameraModel m = CameraModel::make(ModelType::kPinhole, 640, 480, 535.9, 536.2, 342.3, 235.6);
    m.distortion = {-0.266, -0.0386, 0.00178, -0.00028, 0.238};
    return m;
}

CameraModel omnidir_model() {
    CameraModel m = CameraModel::make(ModelType::kOmnidir, 800, 600, 560.0, 558.0, 399.0, 301.0);
    m.xi = 1.05;
    m.skew = 0.2;
    m.distortion = {-0.45, 0.15, 0.004, -0.0002};
    return m;
}

std::vector<Eigen::Vector3d> random_points(double max_theta, int n, uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(0, 1);
    std::vector<Eigen::Vector3d> pts;
    for (int i = 0; i < n; ++i) {
        const double theta = max_theta * std::sqrt(u(rng)), phi = 2 * kPi * u(rng);
        pts.push_back(direction_from_spherical(theta, phi) * (0.5 + 3 * u(rng)));
    }
    return pts;
}

TEST(CameraModel, FisheyeProjectMatchesOpenCv) {
    const CameraModel m = fisheye_model();
    const auto pts = random_points(1.5, 200, 1);  // cv::fisheye needs z > 0
    std::vector<cv::Point3d> cv_pts;
    for (const auto& p : pts) cv_pts.emplace_back(p.x(), p.y(), p.z());
    std::vector<cv::Point2d> out;
    const cv::Matx33d k(m.fx, m.skew, m.cx, 0, m.fy, m.cy, 0, 0, 1);
    cv::fisheye::projectPoints(
        cv_pts, out, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), k,
        cv::Vec4d(m.distortion[0], m.distortion[1], m.distortion[2], m.distortion[3]),
        m.skew / m.fx);
    for (size_t i = 0; i < pts.size(); ++i) {
        const auto px = m.project(pts[i]);
        ASSERT_TRUE(px.has_value());
        EXPECT_NEAR(px->x(), out[i].x, kMatchOpenCvPx);
        EXPECT_NEAR(px->y(), out[i].y, kMatchOpenCvPx);
    }
}

TEST(CameraModel, PinholeProjectMatchesOpenCv) {
    const CameraModel m = pinhole_model();
    const auto pts = random_points(0.6, 200, 2);
    std::vector<cv::Point3d> cv_pts;
    for (const auto& p : pts) cv_pts.emplace_back(p.x(), p.y(), p.z());
    std::vector<cv::Point2d> out;
    const cv::Matx33d k(m.fx, 0, m.cx, 0, m.fy, m.cy, 0, 0, 1);
    cv::projectPoints(cv_pts, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), k, m.distortion, out);
    for (size_t i = 0; i < pts.size(); ++i) {
        const auto px = m.project(pts[i]);
        ASSERT_TRUE(px.has_value());
        EXPECT_NEAR(px->x(), out[i].x, kMatchOpenCvPx);
        EXPECT_NEAR(px->y(), out[i].y, kMatchOpenCvPx);
    }
}

TEST(CameraModel, OmnidirProjectMatchesOpenCv) {
    const CameraModel m = omnidir_model();
    const auto pts = random_points(1.7, 200, 3);  // beyond 90 degrees: xi > 1 images them
    cv::Mat cv_pts(1, static_cast<int>(pts.size()), CV_64FC3), out;
    for (size_t i = 0; i < pts.size(); ++i) {
        cv_pts.at<cv::Vec3d>(0, static_cast<int>(i)) =
            cv::Vec3d(pts[i].x(), pts[i].y(), pts[i].z());
    }
    const cv::Matx33d k(m.fx, m.skew, m.cx, 0, m.fy, m.cy, 0, 0, 1);
    cv::omnidir::projectPoints(
        cv_pts, out, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), k, m.xi,
        cv::Vec4d(m.distortion[0], m.distortion[1], m.distortion[2], m.distortion[3]));
    for (size_t i = 0; i < pts.size(); ++i) {
        const auto px = m.project(pts[i]);
        ASSERT_TRUE(px.has_value());
        const cv::Vec2d o = out.at<cv::Vec2d>(0, static_cast<int>(i));
        EXPECT_NEAR(px->x(), o[0], kMatchOpenCvPx);
        EXPECT_NEAR(px->y(), o[1], kMatchOpenCvPx);
    }
}

void expect_round_trip(const CameraModel& m) {
    const Unprojector unproject(m);
    int valid = 0;
    for (int y = 0; y < m.height; y += 7) {
        for (int x = 0; x < m.width; x += 7) {
            const auto ray = unproject(Eigen::Vector2d(x, y));
            if (!ray) continue;
            ++valid;
            EXPECT_NEAR(ray->norm(), 1.0, 1e-12);
            EXPECT_LE(std::acos(std::clamp(ray->z(), -1.0, 1.0)), unproject.max_theta() + 1e-9);
            const auto px = m.project(*ray);
            ASSERT_TRUE(px.has_value());
            EXPECT_NEAR(px->x(), x, kRoundTripPx) << to_string(m.type) << " at " << x << "," << y;
            EXPECT_NEAR(px->y(), y, kRoundTripPx) << to_string(m.type) << " at " << x << "," << y;
        }
    }
    // The principal region is always valid: a test that finds no valid pixel must fail.
    EXPECT_GT(valid, 100);
}

TEST(Unprojector, RoundTripFisheye) { expect_round_trip(fisheye_model()); }
TEST(Unprojector, RoundTripPinhole) { expect_round_trip(pinhole_model()); }
TEST(Unprojector, RoundTripOmnidir) { expect_round_trip(omnidir_model()); }

TEST(CameraModel, MaxThetaEquidistantIsPi) {
    const CameraModel m = CameraModel::make(ModelType::kFisheye, 100, 100, 30, 30, 50, 50);
    EXPECT_NEAR(m.max_theta(), kPi, 1e-3);
}

TEST(CameraModel, MaxThetaAtTurningPoint) {
    // theta_d = theta (1 + k1 theta^2) turns where 1 + 3 k1 theta^2 = 0.
    const double theta0 = 1.2;
    CameraModel m = CameraModel::make(ModelType::kFisheye, 100, 100, 30, 30, 50, 50);
    m.distortion[0] = -1.0 / (3 * theta0 * theta0);
    EXPECT_NEAR(m.max_theta(), theta0, 1e-6);
    // Beyond the turning point's image radius nothing unprojects.
    const double rd = m.radial(theta0) * m.fx;
    EXPECT_FALSE(m.unproject(Eigen::Vector2d(50 + rd * 1.01, 50)).has_value());
    EXPECT_TRUE(m.unproject(Eigen::Vector2d(50 + rd * 0.99, 50)).has_value());
}

TEST(CameraModel, MaxThetaPinholeAndOmnidir) {
    // Undistorted pinhole: tan theta grows up to 90 degrees.
    const CameraModel p = CameraModel::make(ModelType::kPinhole, 100, 100, 30, 30, 50, 50);
    EXPECT_NEAR(p.max_theta(), 0.5 * kPi, 1e-3);
    // Mei with xi < 1 and no distortion: r = sin / (cos + xi) grows until cos theta = -xi.
    CameraModel o = CameraModel::make(ModelType::kOmnidir, 100, 100, 30, 30, 50, 50);
    o.xi = 0.5;
    EXPECT_NEAR(o.max_theta(), std::acos(-0.5), 1e-3);
}

TEST(CameraModel, ParametersRoundTrip) {
    for (const CameraModel& m : {fisheye_model(), pinhole_model(), omnidir_model()}) {
        CameraModel c = CameraModel::make(m.type, m.width, m.height, 1, 1, 0, 0);
        c.set_parameters(m.parameters());
        EXPECT_EQ(c.parameters(), m.parameters());
        EXPECT_EQ(c.parameter_names().size(), static_cast<size_t>(m.parameters().size()));
    }
}

TEST(CameraModel, ModelNames) {
    EXPECT_EQ(model_type_from_string("omnidir"), ModelType::kOmnidir);
    EXPECT_EQ(to_string(ModelType::kPinhole), "pinhole");
    EXPECT_THROW(model_type_from_string("kannala"), UsageError);
}

TEST(Rodrigues, RoundTrip) {
    const Eigen::Vector3d r(0.3, -1.1, 0.7);
    EXPECT_LT((rodrigues_from_rotation(rotation_from_rodrigues(r)) - r).norm(), 1e-12);
    cv::Matx33d cv_r;
    cv::Rodrigues(cv::Vec3d(r.x(), r.y(), r.z()), cv_r);
    const Eigen::Matrix3d e = rotation_from_rodrigues(r);
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) EXPECT_NEAR(e(i, j), cv_r(i, j), 1e-12);
    }
}

}  // namespace
}  // namespace inlight::calib
