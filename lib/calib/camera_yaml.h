// calib/camera_yaml.h: the solved intrinsics in the camera files OpenCV and ROS read.
//  - camera_info.yaml: ROS camera_calibration's format (image_width, image_height, camera_name,
//    camera_matrix, distortion_model, distortion_coefficients, rectification_matrix,
//    projection_matrix), read by camera_info_manager. distortion_model is "equidistant" for the
//    fisheye (Kannala-Brandt k1..k4, cv::fisheye) and "plumb_bob" for the pinhole (k1, k2, p1,
//    p2, k3). ROS has no Mei model, so the omnidir model has no camera_info.yaml.
//  - opencv_camera.yml: cv::FileStorage YAML with K (3x3), D (1xN, the model's distortion in
//    OpenCV's order), image_width, image_height, model, and xi (omnidir).
// Pixel convention of both: OpenCV's (the centre of the top-left pixel is (0, 0)), as
// calibration.json. Rectification is the identity and the projection matrix [K | 0]: a
// monocular camera, not rectified.
#pragma once

#include <string>
#include <vector>

#include "calib/camera_model.h"

namespace inlight::calib {

/// True when ROS's camera_info has a distortion model for `type` (fisheye, pinhole).
bool has_ros_camera_info(ModelType type);

/// True when `name` is a camera name ROS's camera_info_manager accepts: not empty, only ASCII
/// letters, digits and '_' (setCameraName refuses anything else, '-' included).
bool is_ros_camera_name(const std::string& name);

/// `text` made a ROS camera name: every other character becomes '_'; "" gives "camera".
std::string ros_camera_name(const std::string& text);

/// The camera name calibrate writes when --camera-name is not given, from what the images are
/// known by: the first input when it is a folder (its name), else one input file's stem, else
/// the folder holding the input files; with a corner file (no inputs), that file's stem.
/// Made a ROS name by ros_camera_name().
std::string default_camera_name(const std::vector<std::string>& inputs,
                                const std::string& image_points);

/// The text of camera_info.yaml for `camera`, named ros_camera_name(camera_name).
/// Requires has_ros_camera_info(camera.type).
std::string ros_camera_info_yaml(const CameraModel& camera, const std::string& camera_name);

/// Writes opencv_camera.yml for `camera` to `path` atomically (fs::write_atomic). Throws Error
/// naming the file when it cannot be written.
void write_opencv_camera_yaml(const std::string& path, const CameraModel& camera);

}  // namespace inlight::calib
