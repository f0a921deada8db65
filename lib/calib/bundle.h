// calib/bundle.h: joint refinement of intrinsics and board poses by Levenberg-Marquardt on the
// pixel reprojection residuals (Triggs et al. 2000, "Bundle adjustment - a modern synthesis",
// section 4), their covariance, and pose initialisation that works up to 90 degrees off axis.
// Eigen only, for every CameraModel; used to finish (and, where OpenCV's solvers fail, to
// replace) the OpenCV calibration in solve.cpp.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <vector>

#include "calib/camera_model.h"
#include "calib/detect.h"

namespace inlight::calib {

/// camera_from_board as OpenCV writes it: rotation (Rodrigues vector) and translation (metres).
struct Pose {
    Eigen::Vector3d rvec = Eigen::Vector3d::Zero();
    Eigen::Vector3d tvec = Eigen::Vector3d::Zero();
};

/// Which intrinsics move. `fixed` follows camera.parameter_names(); with fx_follows_fy (a
/// pinhole with a fixed aspect ratio) fx is not a parameter but fx = (fx / fy at start) * fy.
struct FreeParameters {
    std::vector<bool> fixed;
    bool fx_follows_fy = false;
};

struct BundleResult {
    int iterations = 0;
    double initial_rms_px = 0;
    double final_rms_px = 0;
};

/// Minimises the sum of squared pixel residuals over the free intrinsics and every pose.
/// Stops when an accepted step lowers the cost by less than a relative 1e-12, or after
/// `max_iterations`. Preconditions: poses.size() == views.size(), every view projects under the
/// start values (checked: throws Error naming the view otherwise).
BundleResult bundle_adjust(CameraModel& camera, const FreeParameters& free,
                           const std::vector<View>& views, std::vector<Pose>& poses,
                           int max_iterations = 200);

/// Standard deviations of the intrinsics (order of camera.parameter_names(), 0 when fixed):
/// sqrt(diag(sigma^2 (J^T J)^-1)) over the free intrinsics and all poses, with sigma^2 = sum of
/// squared residuals / (2N - number of parameters), J by central differences.
Eigen::VectorXd intrinsic_std_dev(const CameraModel& camera, const FreeParameters& free,
                                  const std::vector<View>& views, const std::vector<Pose>& poses);

/// Pose of a view under known intrinsics: the corners are unprojected to rays, the rays turned
/// so their mean lies on the optical axis (keeping the perspective division well conditioned
/// even for boards near 90 degrees), solved as a planar PnP (IPPE), turned back, and refined
/// on the pixel residuals. std::nullopt if a corner does not unproject or PnP fails.
std::optional<Pose> estimate_pose(const CameraModel& camera, const View& view);

/// Residuals (projected - detected, x then y per point) of one view; false if a point does
/// not project. `out` holds 2 * view.image_points.size() values.
bool view_residuals(const CameraModel& camera, const View& view, const Pose& pose, double* out);

}  // namespace inlight::calib
