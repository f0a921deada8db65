#include "calib/solve.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <opencv2/calib3d.hpp>
#include <random>
#include <regex>

#include "calib/bundle.h"
#include "calib/corner_file.h"
#include "calib/refine.h"
#include "core/conventions.h"
#include "core/error.h"
#include "testing/testing.h"

namespace inlight::calib {
namespace {

/// Board pose: board centre at `dist` along (theta_c, phi_c), facing the camera, then tilted
/// about its own x and y axes and rolled about its normal.
Eigen::Isometry3d board_pose(const BoardSpec& b, double theta_c, double phi_c, double dist,
                             double tilt_x, double tilt_y, double roll) {
    const Eigen::Vector3d dir = direction_from_spherical(theta_c, phi_c);
    const Eigen::Matrix3d look =
        Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), dir).toRotationMatrix();
    const Eigen::Matrix3d r = look * Eigen::AngleAxisd(tilt_x, Eigen::Vector3d::UnitX()) *
                              Eigen::AngleAxisd(tilt_y, Eigen::Vector3d::UnitY()) *
                              Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitZ());
    const Eigen::Vector3d centre((b.cols - 1) * b.square_size_m / 2,
                                 (b.rows - 1) * b.square_size_m / 2, 0);
    Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
    t.linear() = r;
    t.translation() = dist * dir - r * centre;
    return t;
}

/// 20 poses in rings at 0, 25, 45 and 60 degrees off axis (corners reach ~90 degrees), tilted
/// by up to `tilt` radians: what a careful user does with a 165-degree lens.
std::vector<Eigen::Isometry3d> ring_poses(const BoardSpec& b, double dist, double tilt) {
    std::vector<Eigen::Isometry3d> poses;
    const std::pair<double, int> rings[] = {{0.0, 1}, {25.0, 5}, {45.0, 6}, {60.0, 8}};
    int k = 0;
    for (const auto& [theta_deg, n] : rings) {
        for (int i = 0; i < n; ++i, ++k) {
            const double phi = 2 * kPi * i / n + 0.4 * theta_deg / 55;
            poses.push_back(board_pose(b, theta_deg * kPi / 180, phi,
                                       dist * (1 + 0.1 * (k % 2 ? 1 : -1)), ((k % 3) - 1) * tilt,
                                       (((k / 3) % 3) - 1) * tilt, 0.4 * ((k % 4) - 1.5)));
        }
    }
    return poses;
}

/// Exact corners of `board` at each pose, keeping views wholly inside the frame.
std::vector<View> exact_views(const CameraModel& cam, const BoardSpec& board,
                              const std::vector<Eigen::Isometry3d>& poses) {
    std::vector<View> views;
    for (size_t i = 0; i < poses.size(); ++i) {
        View v;
        v.name = str("view", i);
        v.object_points = board_object_points(board);
        bool inside = true;
        for (const auto& p : v.object_points) {
            const auto px = cam.project(poses[i] * p);
            inside = inside && px && px->x() > 8 && px->y() > 8 && px->x() < cam.width - 9 &&
                     px->y() < cam.height - 9;
            if (px) v.image_points.push_back(*px);
        }
        if (inside) views.push_back(v);
    }
    return views;
}

/// A pinhole camera with radial and tangential distortion, and 12 board poses that see it
/// from varied angles: shared by the pinhole calibration and uncertainty tests.
CameraModel test_pinhole() {
    CameraModel pin = CameraModel::make(ModelType::kPinhole, 640, 480, 520.0, 521.0, 322.0, 241.0);
    pin.distortion = {-0.21, 0.05, 0.001, -0.0005, 0.01};
    return pin;
}

std::vector<Eigen::Isometry3d> pinhole_poses(const BoardSpec& board) {
    std::vector<Eigen::Isometry3d> poses;
    for (int i = 0; i < 12; ++i) {
        poses.push_back(board_pose(board, (i % 3) * 0.08, i * 0.7, 14.0 + (i % 2),
                                   0.3 * ((i % 3) - 1), 0.25 * (((i / 3) % 3) - 1), 0.2 * i));
    }
    return poses;
}

CameraModel fisheye_truth() {
    CameraModel m = CameraModel::make(ModelType::kFisheye, 960, 720, 225.0, 224.55, 481.3, 358.6);
    m.distortion = {0.021, -0.008, 0.0031, -0.0007};
    return m;
}

// --- Synthetic ---------------------------------------------------------------------------

TEST(Calibrate, SyntheticFisheyeImagesRecoverModel) {
    // The requirement: boards rendered through a known fisheye model (anti-aliased by
    // 3 x 3 supersampling, 0.5 px lens blur) recover it: focal lengths and principal point
    // within 0.1 px, k1..k4 within 1e-3.
    constexpr double kPixelTol = 0.1;
    constexpr double kDistortionTol = 1e-3;
    const CameraModel truth = fisheye_truth();
    const BoardSpec board{9, 6, 1.0};
    RenderOptions ro;
    ro.supersample = 3;
    ro.blur_sigma_px = 0.5;
    const BoardRenderer renderer(truth, ro);
    const auto poses = ring_poses(board, 7.0, 0.3);
    std::vector<GrayImage> images;
    std::vector<View> views;
    DetectOptions dopt;
    dopt.board = board;
    for (size_t i = 0; i < poses.size(); ++i) {
        images.push_back(renderer.render(board, poses[i]));
        const Detection d = detect_board(images.back(), str("view", i), dopt);
        if (d.found) views.push_back(d.view);
        if (!d.found) images.pop_back();
    }
    ASSERT_GE(views.size(), 17u) << "the detector should find nearly every board";
    Calibration cal = calibrate(views, truth.width, truth.height, CalibrateOptions{});
    for (int pass = 0; pass < 2; ++pass) {  // as calibrate geometry's default
        std::vector<View> refined;
        for (size_t k = 0; k < cal.views.size(); ++k) {
            const size_t i = cal.view_index[k];
            refined.push_back(refine_view(images[i], views[i], board, cal.camera, cal.views[k].rvec,
                                          cal.views[k].tvec));
        }
        std::vector<GrayImage> kept;
        for (size_t i : cal.view_index) kept.push_back(images[i]);
        images = std::move(kept);
        views = std::move(refined);
        cal = calibrate(views, truth.width, truth.height, CalibrateOptions{});
    }
    const CameraModel& m = cal.camera;
    EXPECT_NEAR(m.fx, truth.fx, kPixelTol);
    EXPECT_NEAR(m.fy, truth.fy, kPixelTol);
    EXPECT_NEAR(m.cx, truth.cx, kPixelTol);
    EXPECT_NEAR(m.cy, truth.cy, kPixelTol);
    for (int i = 0; i < 4; ++i) EXPECT_NEAR(m.distortion[i], truth.distortion[i], kDistortionTol);
    EXPECT_LT(cal.rms_px, 0.1);
    EXPECT_GT(cal.max_observed_theta, 80 * kPi / 180);
}

TEST(Calibrate, ExactCornersBeyond90DegreesUseFallback) {
    // Boards up to 100 degrees off axis: cv::fisheye::calibrate's initialisation fails on
    // these; the subset + bundle fallback must still recover the model to round-off.
    const CameraModel truth = fisheye_truth();
    const BoardSpec board{9, 6, 1.0};
    auto poses = ring_poses(board, 7.0, 0.2);
    for (int i = 0; i < 8; ++i) {
        poses.push_back(
            board_pose(board, 70 * kPi / 180, 2 * kPi * i / 8, 7.0, 0.2, -0.1, 0.3 * i));
    }
    const auto views = exact_views(truth, board, poses);
    ASSERT_GE(views.size(), 24u);
    const Calibration cal = calibrate(views, truth.width, truth.height, CalibrateOptions{});
    EXPECT_EQ(cal.views.size(), views.size());
    EXPECT_GT(cal.max_observed_theta, 92 * kPi / 180);
    const Eigen::VectorXd d = cal.camera.parameters() - truth.parameters();
    EXPECT_LT(d.cwiseAbs().maxCoeff(), 1e-6) << d.transpose();
    EXPECT_LT(cal.rms_px, 1e-6);
}

TEST(Calibrate, ExactCornersPinholeAndOmnidir) {
    const BoardSpec board{9, 6, 1.0};
    const CameraModel pin = test_pinhole();
    auto views = exact_views(pin, board, pinhole_poses(board));
    ASSERT_GE(views.size(), 8u);
    CalibrateOptions po;
    po.model = ModelType::kPinhole;
    Calibration cal = calibrate(views, pin.width, pin.height, po);
    EXPECT_LT((cal.camera.parameters() - pin.parameters()).cwiseAbs().maxCoeff(), 1e-5);

    CameraModel omni = CameraModel::make(ModelType::kOmnidir, 800, 600, 420.0, 419.0, 401.0, 299.0);
    omni.xi = 1.1;
    omni.distortion = {-0.2, 0.05, 0.001, -0.0004};
    views = exact_views(omni, board, ring_poses(board, 7.0, 0.2));
    ASSERT_GE(views.size(), 12u);
    CalibrateOptions oo;
    oo.model = ModelType::kOmnidir;
    cal = calibrate(views, omni.width, omni.height, oo);
    EXPECT_LT(cal.rms_px, 1e-4);
    // Every parameter (fx, fy, cx, cy, skew, xi, k1, k2, p1, p2) against the truth. With exact
    // corners the only error is where the solver stops: a first-order offset d from the truth
    // leaves residuals r = J d, so |d_i| <= sqrt((J^T J)^-1_ii) |r| = std_dev_i sqrt(2N - p)
    // (std_dev_i = |r| / sqrt(2N - p) sqrt((J^T J)^-1_ii), N corners, p free parameters).
    // xi and the focal lengths are strongly correlated in Mei's model; this bound says how much.
    const Eigen::VectorXd d = cal.camera.parameters() - omni.parameters();
    size_t corners = 0;
    for (const auto& v : views) corners += v.image_points.size();
    int free_count = 6 * static_cast<int>(cal.views.size());
    for (bool f : cal.fixed) free_count += f ? 0 : 1;
    const double dof_factor = std::sqrt(2.0 * double(corners) - free_count);
    std::printf("omnidir on exact corners: RMS %.2e px; parameter error / bound:", cal.rms_px);
    for (int i = 0; i < d.size(); ++i) {
        const double bound = cal.std_dev[i] * dof_factor;
        std::printf(" %s %.1e/%.1e", cal.parameter_names[size_t(i)].c_str(), d[i], bound);
        if (cal.fixed[size_t(i)]) {
            EXPECT_EQ(d[i], 0.0) << cal.parameter_names[size_t(i)];
        } else {
            EXPECT_LE(std::abs(d[i]), bound) << cal.parameter_names[size_t(i)];
        }
    }
    std::printf("\n");
}

TEST(Calibrate, FewerThanThreeViewsIsAnError) {
    const CameraModel truth = fisheye_truth();
    const BoardSpec board{9, 6, 1.0};
    auto views = exact_views(truth, board, ring_poses(board, 7.0, 0.2));
    views.resize(2);
    try {
        calibrate(views, truth.width, truth.height, CalibrateOptions{});
        FAIL() << "expected Error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("need at least 3"), std::string::npos) << e.what();
    }
}

TEST(Calibrate, OutlierViewIsDroppedAndNamed) {
    const CameraModel truth = fisheye_truth();
    const BoardSpec board{9, 6, 1.0};
    auto views = exact_views(truth, board, ring_poses(board, 7.0, 0.2));
    std::mt19937_64 rng(3);
    std::normal_distribution<double> noise(0, 0.1);
    for (View& v : views) {
        for (auto& p : v.image_points) p += Eigen::Vector2d(noise(rng), noise(rng));
    }
    for (auto& p : views[5].image_points) p += Eigen::Vector2d(noise(rng), noise(rng)) * 40;
    const Calibration cal = calibrate(views, truth.width, truth.height, CalibrateOptions{});
    ASSERT_EQ(cal.dropped.size(), 1u);
    EXPECT_EQ(cal.dropped[0].name, views[5].name);
    EXPECT_NE(cal.dropped[0].reason.find("outlier"), std::string::npos);
    EXPECT_EQ(cal.views.size(), views.size() - 1);
}

// --- Corner refinement ------------------------------------------------------------------------

struct CornerErrors {
    double radial_bias_px = 0;  ///< mean of the error's component away from the principal point
    double rms_px = 0;
    size_t n = 0;
};

/// Detected (or refined) corners against the exact projections of the board's corners, with
/// the board's labelling either way round (a 180-degree relabelling is a rigid motion).
CornerErrors corner_errors(const CameraModel& cam, const View& v, const Eigen::Isometry3d& pose) {
    CornerErrors best;
    best.rms_px = INFINITY;
    const size_t n = v.image_points.size();
    for (int flip = 0; flip < 2; ++flip) {
        CornerErrors e;
        e.n = n;
        for (size_t i = 0; i < n; ++i) {
            const auto truth = cam.project(pose * v.object_points[flip ? n - 1 - i : i]);
            const Eigen::Vector2d d = v.image_points[i] - *truth;
            const Eigen::Vector2d out = (*truth - Eigen::Vector2d(cam.cx, cam.cy)).normalized();
            e.radial_bias_px += d.dot(out) / double(n);
            e.rms_px += d.squaredNorm() / double(n);
        }
        e.rms_px = std::sqrt(e.rms_px);
        if (e.rms_px < best.rms_px) best = e;
    }
    return best;
}

TEST(RefineView, RemovesTheDetectorsOutwardBiasFarOffAxis) {
    // refine.h's claim: a detector working in the image places corners of a strongly curved
    // board outward (~0.1 px at 80 degrees); resampling onto the board plane removes that bias.
    // Noise source: each refined corner's own localisation error (cornerSubPix on the resampled,
    // anti-aliased 8-bit render), estimated by the scatter s of the refined errors about their
    // mean; a mean over n corners without bias lies within 3 s / sqrt(n) of zero.
    const CameraModel truth = fisheye_truth();
    const BoardSpec board{9, 6, 1.0};
    RenderOptions ro;
    ro.supersample = 3;
    const BoardRenderer renderer(truth, ro);
    DetectOptions dopt;
    dopt.board = board;
    const auto pose = board_pose(board, 72 * kPi / 180, 0.5, 7.0, 0, 0, 0.3);
    const GrayImage image = renderer.render(board, pose);
    const Detection d = detect_board(image, "off", dopt);
    ASSERT_TRUE(d.found) << d.reason;
    const CornerErrors before = corner_errors(truth, d.view, pose);
    const Eigen::AngleAxisd aa(pose.linear());
    const View refined =
        refine_view(image, d.view, board, truth, aa.angle() * aa.axis(), pose.translation());
    const CornerErrors after = corner_errors(truth, refined, pose);
    const double scatter =
        std::sqrt(std::max(0.0, after.rms_px * after.rms_px - after.radial_bias_px * after.radial_bias_px));
    const double bias_tol = 3 * scatter / std::sqrt(double(after.n));
    std::printf("corners at 72 deg: detected bias %+.3f RMS %.3f px; refined bias %+.4f RMS %.3f "
                "px; tolerance 3 s / sqrt(n) = %.3f px\n",
                before.radial_bias_px, before.rms_px, after.radial_bias_px, after.rms_px, bias_tol);
    // The test has power: the detector's bias is there, beyond the tolerance.
    EXPECT_GT(before.radial_bias_px, bias_tol);
    // And refinement removes it.
    EXPECT_LT(std::abs(after.radial_bias_px), bias_tol);
    EXPECT_LT(after.rms_px, before.rms_px);
}

// --- Uncertainties ---------------------------------------------------------------------------

TEST(IntrinsicStdDev, MatchesOpenCvCalibrateCamera) {
    // Same corners, same model: our Jacobian-based standard deviations against
    // cv::calibrateCamera's stdDeviationsIntrinsics. OpenCV divides the residual sum by
    // (N points - p) where we use (2N - p) (the residuals are 2N numbers), so its values are
    // larger by sqrt((2N - p) / (N - p)); with that factor they agree to finite-difference
    // accuracy (0.5%).
    const BoardSpec board{9, 6, 1.0};
    const CameraModel pin = test_pinhole();
    auto views = exact_views(pin, board, pinhole_poses(board));
    std::mt19937_64 rng(5);
    std::normal_distribution<double> noise(0, 0.2);
    for (View& v : views) {
        for (auto& p : v.image_points) p += Eigen::Vector2d(noise(rng), noise(rng));
    }
    std::vector<std::vector<cv::Point3f>> op;
    std::vector<std::vector<cv::Point2f>> ip;
    for (const View& v : views) {
        op.emplace_back();
        ip.emplace_back();
        for (const auto& p : v.object_points) op.back().emplace_back(p.x(), p.y(), p.z());
        for (const auto& p : v.image_points) ip.back().emplace_back(p.x(), p.y());
    }
    cv::Mat k = cv::Mat::eye(3, 3, CV_64F), d, std_intr, std_extr, per_view;
    std::vector<cv::Mat> rv, tv;
    cv::calibrateCamera(op, ip, cv::Size(640, 480), k, d, rv, tv, std_intr, std_extr, per_view, 0,
                        cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 100,
                                         std::numeric_limits<double>::epsilon()));
    CameraModel cam = CameraModel::make(ModelType::kPinhole, 640, 480, k.at<double>(0, 0),
                                        k.at<double>(1, 1), k.at<double>(0, 2), k.at<double>(1, 2));
    for (int i = 0; i < 5; ++i) cam.distortion[i] = d.at<double>(i);
    std::vector<Pose> pv;
    for (size_t i = 0; i < views.size(); ++i) {
        pv.push_back(
            {Eigen::Vector3d(rv[i].at<double>(0), rv[i].at<double>(1), rv[i].at<double>(2)),
             Eigen::Vector3d(tv[i].at<double>(0), tv[i].at<double>(1), tv[i].at<double>(2))});
    }
    FreeParameters free;
    free.fixed = {false, false, false, false, true, false, false, false, false, false};
    const Eigen::VectorXd ours = intrinsic_std_dev(cam, free, views, pv);
    const double n = static_cast<double>(views.size() * 54), p = 9 + 6.0 * views.size();
    const double factor = std::sqrt((2 * n - p) / (n - p));
    // OpenCV's order: fx fy cx cy k1 k2 p1 p2 k3 ...; ours: fx fy cx cy skew k1 k2 p1 p2 k3.
    const int ours_index[] = {0, 1, 2, 3, 5, 6, 7, 8, 9};
    for (int i = 0; i < 9; ++i) {
        EXPECT_NEAR(ours[ours_index[i]] * factor / std_intr.at<double>(i), 1.0, 0.005)
            << "parameter " << cam.parameter_names()[ours_index[i]];
    }
}

// --- Real data -------------------------------------------------------------------------------

struct OstYaml {
    double fx, fy, cx, cy, k[4];
};

OstYaml read_ost(const std::string& path) {
    std::ifstream in(path);
    std::stringstream ss;
    ss << in.rdbuf();
    const std::string text = ss.str();
    auto numbers_after = [&](const std::string& key) {
        const size_t at = text.find(key);
        const size_t open = text.find('[', text.find("data:", at));
        const size_t close = text.find(']', open);
        std::vector<double> v;
        std::stringstream list(text.substr(open + 1, close - open - 1));
        std::string item;
        while (std::getline(list, item, ',')) v.push_back(std::stod(item));
        return v;
    };
    const auto k = numbers_after("camera_matrix");
    const auto d = numbers_after("distortion_coefficients");
    EXPECT_EQ(k.size(), 9u);
    EXPECT_EQ(d.size(), 4u);
    return {k[0], k[4], k[2], k[5], {d[0], d[1], d[2], d[3]}};
}

TEST(CalibrateRealData, RosFisheyeReproducesOstYaml) {
    // The requirement: the ROS fisheye photographs recover the intrinsics of their
    // ost.yaml within 0.5 px and 0.003 on each k. ost.yaml was made by ROS camera_calibration,
    // so its detection procedure is used (--detector ros, no refinement), with OpenCV's fisheye
    // solver and flags FIX_SKEW | RECOMPUTE_EXTRINSIC as ROS calls it.
    constexpr double kPixelTol = 0.5;
    constexpr double kDistortionTol = 0.003;
    const std::string dir = testing::shared_data("fisheye-ros-mono");
    INLIGHT_SKIP_IF_MISSING(dir, "fisheye-ros-mono");
    const OstYaml ost = read_ost(dir + "/ost.yaml");
    DetectOptions dopt;
    dopt.board = parse_board("8x6", 0.108);
    dopt.detector = Detector::kRos;
    const Detections det = detect_boards(expand_image_inputs({dir}), dopt);
    ASSERT_EQ(det.views.size(), 24u);
    ASSERT_EQ(det.width, 800);
    ASSERT_EQ(det.height, 503);
    const Calibration cal = calibrate(det.views, det.width, det.height, CalibrateOptions{});
    EXPECT_TRUE(cal.dropped.empty());
    const CameraModel& m = cal.camera;
    EXPECT_NEAR(m.fx, ost.fx, kPixelTol);
    EXPECT_NEAR(m.fy, ost.fy, kPixelTol);
    EXPECT_NEAR(m.cx, ost.cx, kPixelTol);
    EXPECT_NEAR(m.cy, ost.cy, kPixelTol);
    for (int i = 0; i < 4; ++i)
        EXPECT_NEAR(m.distortion[i], ost.k[i], kDistortionTol) << "k" << i + 1;
    RecordProperty("reproj_rms_px", std::to_string(cal.rms_px));
}

TEST(CalibrateRealData, JyCornerFilesMatchOpenCvReference) {
    // OpenCV's own fisheye test (modules/calib3d/test/test_fisheye.cpp, fisheyeTest::K and ::D)
    // calibrates these corners with FIX_SKEW | RECOMPUTE_EXTRINSIC | CHECK_COND and 20
    // iterations (eps 1e-6). We converge fully (joint LM), to the optimum their 20 iterations
    // approach: measured 1.4e-5 px and 2e-7 apart, tested at 1e-3 px and 1e-6.
    const std::string dir = testing::shared_data("fisheye-opencv-jy-points");
    INLIGHT_SKIP_IF_MISSING(dir, "fisheye-opencv-jy-points");
    const CornerSet set = read_corner_files(dir + "/left.xml", dir + "/object.xml", BoardSpec{});
    ASSERT_EQ(set.views.size(), 34u);
    const Calibration cal = calibrate(set.views, 1280, 800, CalibrateOptions{});
    EXPECT_TRUE(cal.dropped.empty());
    const CameraModel& m = cal.camera;
    EXPECT_NEAR(m.fx, 558.478087865323, 1e-3);
    EXPECT_NEAR(m.fy, 560.506767351568, 1e-3);
    EXPECT_NEAR(m.cx, 620.458515360843, 1e-3);
    EXPECT_NEAR(m.cy, 381.939424848348, 1e-3);
    const double k_ref[4] = {-0.0014613319981768, -0.00329861110580401, 0.00605760088590183,
                             -0.00374209380722371};
    for (int i = 0; i < 4; ++i) EXPECT_NEAR(m.distortion[i], k_ref[i], 1e-6) << "k" << i + 1;
    // OpenCV's EstimateUncertainties reports 3-sigma errors with sigma from the residuals'
    // standard deviation over 2N - 1 (rms 0.263782587133546, f error 1.29837104202046); ours
    // are 1-sigma over 2N - p: theirs = 3 sqrt((2N - p) / (2N - 1)) ours.
    EXPECT_NEAR(cal.rms_px, 0.263782587133546, 1e-6);
    const double n2 = 2.0 * 34 * 48, p = 8 + 6.0 * 34;
    const double to_opencv = 3 * std::sqrt((n2 - p) / (n2 - 1));
    // Same Jacobian, same optimum (to 1e-5 px): the ratios agree to finite-difference accuracy.
    constexpr double kStdRel = 1e-3;
    EXPECT_NEAR(cal.std_dev[0] * to_opencv / 1.29837104202046, 1.0, kStdRel);
    EXPECT_NEAR(cal.std_dev[1] * to_opencv / 1.31565641071524, 1.0, kStdRel);
    EXPECT_NEAR(cal.std_dev[2] * to_opencv / 0.890439368129246, 1.0, kStdRel);
    EXPECT_NEAR(cal.std_dev[3] * to_opencv / 0.816096854937896, 1.0, kStdRel);
    EXPECT_NEAR(cal.std_dev[5] * to_opencv / 0.00516248605191506, 1.0, kStdRel);
    EXPECT_NEAR(cal.std_dev[6] * to_opencv / 0.0168181467500934, 1.0, kStdRel);
    EXPECT_NEAR(cal.std_dev[7] * to_opencv / 0.0213118690274604, 1.0, kStdRel);
    EXPECT_NEAR(cal.std_dev[8] * to_opencv / 0.00916010877545648, 1.0, kStdRel);
}

}  // namespace
}  // namespace inlight::calib
