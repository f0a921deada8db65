#include "calib/camera_yaml.h"

#include <opencv2/core.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>
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

namespace {

bool ros_name_char(char ch) {
    return (ch >= 'a' && ch <= 'z') || (ch >= 'A' && ch <= 'Z') || (ch >= '0' && ch <= '9') ||
           ch == '_';
}

}  // namespace

bool is_ros_camera_name(const std::string& name) {
    return !name.empty() && std::all_of(name.begin(), name.end(), ros_name_char);
}

std::string ros_camera_name(const std::string& text) {
    std::string name = text.empty() ? "camera" : text;
    for (char& ch : name)
        if (!ros_name_char(ch)) ch = '_';
    return name;
}

std::string default_camera_name(const std::vector<std::string>& inputs,
                                const std::string& image_points) {
    namespace stdfs = std::filesystem;
    std::string name;
    if (inputs.empty()) {
        name = stdfs::path(image_points).stem().string();
    } else {
        // A trailing '/' leaves an empty filename: lexically_normal + parent of "dir/." fixes it.
        stdfs::path first = stdfs::path(inputs.front()).lexically_normal();
        if (first.filename().empty()) first = first.parent_path();
        std::error_code ec;
        if (stdfs::is_directory(first, ec)) {
            name = stdfs::absolute(first, ec).lexically_normal().filename().string();
            if (name.empty() || name == ".") name = stdfs::current_path(ec).filename().string();
        } else if (inputs.size() == 1) {
            name = first.stem().string();
        } else {
            name = stdfs::absolute(first, ec).parent_path().filename().string();
        }
    }
    return ros_camera_name(name);
}

std::string ros_camera_info_yaml(const CameraModel& c, const std::string& camera_name) {
    INLIGHT_CHECK(has_ros_camera_info(c.type)) << to_string(c.type);
    const std::string name = ros_camera_name(camera_name);
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
