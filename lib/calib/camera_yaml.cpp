#include "calib/camera_yaml.h"

#include <opencv2/core.hpp>

#include <cctype>
#include <cstdio>
#include <sstream>

#include "core/check.h"
#include "core/error.h"
#include "core/fs.h"

namespace inlight::calib {
namespace {

/// Shortest text that reads back as the same double (17 significant digits).
std::string num(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.17g", v);
    return buf;
}

std::string matrix(int rows, int cols, const std::vector<double>& data) {
    std::ostringstream s;
    s << "\n  rows: " << rows << "\n  cols: " << cols << "\n  data: [";
    for (size_t i = 0; i < data.size(); ++i) s << (i ? ", " : "") << num(data[i]);
    s << "]\n";
    return s.str();
}

}  // namespace

bool has_ros_camera_info(ModelType type) {
    return type == ModelType::kFisheye || type == ModelType::kPinhole;
}

std::string ros_camera_info_yaml(const CameraModel& c, const std::string& camera_name) {
    INLIGHT_CHECK(has_ros_camera_info(c.type)) << to_string(c.type);
    std::string name = camera_name.empty() ? "camera" : camera_name;
    for (char& ch : name)
        if (!std::isalnum(static_cast<unsigned char>(ch)) && ch != '_' && ch != '-') ch = '_';
    const std::vector<double> k = {c.fx, c.skew, c.cx, 0, c.fy, c.cy, 0, 0, 1};
    const std::vector<double> p = {c.fx, c.skew, c.cx, 0, 0, c.fy, c.cy, 0, 0, 0, 1, 0};
    std::ostringstream s;
    s << "image_width: " << c.width << "\nimage_height: " << c.height
      << "\ncamera_name: " << name << "\ncamera_matrix:" << matrix(3, 3, k)
      << "distortion_model: " << (c.type == ModelType::kFisheye ? "equidistant" : "plumb_bob")
      << "\ndistortion_coefficients:"
      << matrix(1, static_cast<int>(c.distortion.size()), c.distortion)
      << "rectification_matrix:" << matrix(3, 3, {1, 0, 0, 0, 1, 0, 0, 0, 1})
      << "projection_matrix:" << matrix(3, 4, p);
    return s.str();
}

void write_opencv_camera_yaml(const std::string& path, const CameraModel& c) {
    fs::write_atomic(path, [&](const std::string& tmp) {
        // FORMAT_YAML: the temporary name does not end in .yml.
        cv::FileStorage out(tmp, cv::FileStorage::WRITE | cv::FileStorage::FORMAT_YAML);
        if (!out.isOpened()) throw Error(str(path, ": cannot write"));
        const cv::Matx33d k(c.fx, c.skew, c.cx, 0, c.fy, c.cy, 0, 0, 1);
        out << "model" << to_string(c.type) << "image_width" << c.width << "image_height"
            << c.height << "K" << cv::Mat(k)
            << "D" << cv::Mat(c.distortion, true).reshape(1, 1);
        if (c.type == ModelType::kOmnidir) out << "xi" << c.xi;
        out.release();
    });
}

}  // namespace inlight::calib
