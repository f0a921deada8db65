// calib/solve.h: intrinsic calibration from views of a planar board (Zhang 2000, "A flexible new
// technique for camera calibration"): solved by OpenCV 4.6 (cv::fisheye::calibrate,
// cv::calibrateCamera, cv::omnidir::calibrate), then finished by a joint Levenberg-Marquardt
// over intrinsics and poses (bundle.h), with outlier views dropped and named, and the standard
// deviations of the intrinsics from the Jacobian of all reprojection residuals (covariance
// sigma^2 (J^T J)^-1, sigma^2 = sum r^2 / (2N - p), as cv::calibrateCamera's
// stdDeviationsIntrinsics).
//
// cv::fisheye::calibrate fails (an assertion in its homography initialisation) on some sets
// with corners near 90 degrees off axis. Then the largest subset it accepts, grown from the
// views nearest the image centre, gives the intrinsics; every other view's pose is estimated
// under them (bundle.h estimate_pose) and all views are refined jointly.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "calib/camera_model.h"
#include "calib/detect.h"

namespace inlight::calib {

struct CalibrateOptions {
    ModelType model = ModelType::kFisheye;
    /// Keep skew at 0 (fisheye, omnidir; the pinhole model has none).
    bool fix_skew = true;
    /// Pinhole only: fx = fy.
    bool fix_aspect_ratio = false;
    /// Pinhole only: estimate k3 (the 5-term model). Off: k3 = 0.
    bool pinhole_k3 = true;
    /// A view is an outlier when its RMS reprojection error exceeds both outlier_factor x the
    /// median view RMS and outlier_min_px. Outliers are dropped one at a time, worst first, and
    /// the calibration is repeated. outlier_factor <= 0 disables the rejection.
    double outlier_factor = 3.0;
    double outlier_min_px = 1.0;
    /// Fewer usable views than this is an error (three poses are the minimum for Zhang's
    /// method with a free principal point).
    int min_views = 3;
    /// Finish every solve with the joint Levenberg-Marquardt of bundle.h (the same cost, so it
    /// only moves a converged OpenCV result by round-off; it matters where OpenCV stopped early).
    bool polish = true;
};

/// Fit quality of one view.
struct ViewError {
    std::string name;
    int points = 0;
    double rms_px = 0;        ///< sqrt(mean over points of |projected - detected|^2)
    double max_error_px = 0;  ///< largest single-point error
    Eigen::Vector3d rvec = Eigen::Vector3d::Zero();  ///< camera_from_board rotation (Rodrigues)
    Eigen::Vector3d tvec = Eigen::Vector3d::Zero();  ///< camera_from_board translation, metres
};

/// A calibration and everything known about its quality.
struct Calibration {
    CameraModel camera;
    std::vector<std::string> parameter_names;  ///< as camera.parameter_names()
    std::vector<bool> fixed;                   ///< per parameter: held, not estimated
    Eigen::VectorXd std_dev;                   ///< per parameter, 0 when fixed
    double rms_px = 0;                         ///< over all points of all used views
    std::vector<ViewError> views;              ///< used views, in input order
    std::vector<size_t> view_index;            ///< index into the input of each used view
    std::vector<DroppedView> dropped;          ///< views left out by calibrate(), with reasons
    /// Largest polar angle (radians) of any used corner under the final model: the model is
    /// extrapolated beyond it.
    double max_observed_theta = 0;
    int rounds = 0;  ///< solver runs (1 + outliers dropped)
    /// How the last solve went: "opencv", "opencv+polish", or "opencv-subset+bundle" (the
    /// fisheye fallback described at the top).
    std::string solver;
};

/// Calibrates `model` from views of images of `width` x `height`. Throws Error when fewer than
/// options.min_views views remain (naming every dropped view and why) or the solver fails.
Calibration calibrate(const std::vector<View>& views, int width, int height,
                      const CalibrateOptions& options);

/// Reprojection error of one view under `camera` with pose (rvec, tvec).
ViewError view_error(const CameraModel& camera, const View& view, const Eigen::Vector3d& rvec,
                     const Eigen::Vector3d& tvec);

}  // namespace inlight::calib
