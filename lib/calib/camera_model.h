// calib/camera_model.h: the camera models `calibrate` fits, with projection and unprojection in
// Eigen (no OpenCV types), numerically identical to OpenCV 4.6's implementations:
//  - fisheye: Kannala and Brandt 2006 ("A generic camera model and calibration method for
//    conventional, wide-angle, and fish-eye lenses", eq. 6 with four terms), as cv::fisheye:
//    theta_d = theta (1 + k1 theta^2 + k2 theta^4 + k3 theta^6 + k4 theta^8);
//  - pinhole: Brown-Conrady radial + tangential distortion (k1, k2, p1, p2, k3), as
//    cv::calibrateCamera's default 5-term model;
//  - omnidir: Mei and Rives 2007 ("Single view point omnidirectional camera calibration from
//    planar grids", eq. 1-6), the unified sphere model with xi, as cv::omnidir.
//
// Frames and pixels (OpenCV's conventions, used throughout lib/calib):
//  - camera frame: x right (image columns), y down (image rows), z forward along the optical axis;
//  - pixel coordinates: the centre of the top-left pixel is (0, 0), x right, y down. (inlight's
//    own convention puts that centre at (0.5, 0.5); subtract 0.5 to convert.)
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

namespace inlight::calib {

/// Which projection a CameraModel uses.
enum class ModelType {
    kFisheye,  ///< "fisheye": Kannala-Brandt, distortion k1..k4 (cv::fisheye)
    kPinhole,  ///< "pinhole": radial + tangential, distortion k1, k2, p1, p2, k3
    kOmnidir,  ///< "omnidir": Mei unified model, xi plus distortion k1, k2, p1, p2 (cv::omnidir)
};

/// "fisheye", "pinhole", "omnidir".
std::string to_string(ModelType type);
/// Inverse of to_string. Throws UsageError naming the accepted names.
ModelType model_type_from_string(const std::string& name);

/// Intrinsics of one camera at one resolution.
struct CameraModel {
    ModelType type = ModelType::kFisheye;
    int width = 0;   ///< image width the intrinsics refer to, pixels
    int height = 0;  ///< image height, pixels
    double fx = 0;   ///< focal length along x, pixels
    double fy = 0;   ///< focal length along y, pixels
    double cx = 0;   ///< principal point x, pixels (OpenCV pixel convention, see top)
    double cy = 0;   ///< principal point y, pixels
    /// K(0,1) in pixels: u = fx * x + skew * y + cx. (OpenCV's fisheye "alpha" is skew / fx;
    /// the pinhole model has no skew and keeps it 0.)
    double skew = 0;
    /// Mei's xi (omnidir only; 0 for the other models). xi = 0 is a pinhole, xi = 1 a parabola.
    double xi = 0;
    /// fisheye: k1, k2, k3, k4; pinhole: k1, k2, p1, p2, k3; omnidir: k1, k2, p1, p2.
    std::vector<double> distortion;

    /// A model of `type` with zero distortion of the right length.
    static CameraModel make(ModelType type, int width, int height, double fx, double fy, double cx,
                            double cy);

    /// Pixel of a camera-frame point (any non-zero length). std::nullopt when the model cannot
    /// image it: behind a pinhole (z <= 0) or where z / |p| + xi <= 0 (omnidir). The fisheye
    /// model images every direction but is one-to-one only up to max_theta().
    std::optional<Eigen::Vector2d> project(const Eigen::Vector3d& p_camera) const;

    /// Unit camera-frame ray through a pixel, std::nullopt outside the model's one-to-one
    /// domain. Slow for many pixels: use Unprojector, which precomputes the domain.
    std::optional<Eigen::Vector3d> unproject(const Eigen::Vector2d& pixel) const;

    /// Largest polar angle (radians from +z, at most pi) up to which the radial mapping is
    /// increasing, i.e. the model is one-to-one (ignoring the small tangential terms).
    double max_theta() const;

    /// Names of the parameter vector below: fx fy cx cy skew [xi] then the distortion names.
    std::vector<std::string> parameter_names() const;
    /// fx, fy, cx, cy, skew, [xi,] distortion... in the order of parameter_names().
    Eigen::VectorXd parameters() const;
    /// Inverse of parameters(). Precondition: p.size() == parameter_names().size() (checked).
    void set_parameters(const Eigen::VectorXd& p);

    /// Normalised distorted radius (|K^-1 pixel| without tangential terms) of polar angle theta:
    /// fisheye theta_d; pinhole r (1 + k1 r^2 + k2 r^4 + k3 r^6), r = tan theta; omnidir the
    /// same on r = sin theta / (cos theta + xi). +infinity where the model cannot image theta.
    double radial(double theta) const;
};

/// Unprojects many pixels with the model's one-to-one domain computed once. Thread-safe.
class Unprojector {
  public:
    explicit Unprojector(const CameraModel& model);

    /// Unit camera-frame ray through `pixel` (OpenCV pixel convention), std::nullopt outside the
    /// one-to-one domain (or where the iterative inverse does not converge to 1e-9).
    std::optional<Eigen::Vector3d> operator()(const Eigen::Vector2d& pixel) const;

    double max_theta() const { return m_max_theta; }
    const CameraModel& model() const { return m_model; }

  private:
    CameraModel m_model;
    double m_max_theta = 0;     ///< polar angle limit of the one-to-one domain, radians
    double m_max_radial = 0;    ///< radial(m_max_theta)
    double m_max_undist_r = 0;  ///< pinhole/omnidir: undistorted radius at m_max_theta
};

/// Angle-axis (Rodrigues) vector to rotation matrix, as cv::Rodrigues.
Eigen::Matrix3d rotation_from_rodrigues(const Eigen::Vector3d& rvec);
/// Rotation matrix to angle-axis vector.
Eigen::Vector3d rodrigues_from_rotation(const Eigen::Matrix3d& rotation);

}  // namespace inlight::calib
