#include "calib/camera_yaml.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <opencv2/core.hpp>

#include "testing/testing.h"

namespace inlight::calib {
namespace {

// Values like a solved fisheye (the ROS reference set's magnitudes), not round numbers, so a
// lost digit would show. Doubles are written with 17 significant digits (ours) or %.16e
// (cv::FileStorage): both read back exactly, so the comparisons below are exact.
CameraModel fisheye() {
    CameraModel c = CameraModel::make(ModelType::kFisheye, 800, 503, 253.71301, 254.10987,
                                      402.62418, 247.95153);
    c.skew = 0.0123456789;
    c.distortion = {-0.0151734, 0.0219853, -0.0204741, 0.00564218};
    return c;
}

std::vector<double> read_vector(const cv::FileNode& n) {
    std::vector<double> v;
    for (const auto& x : n) v.push_back(static_cast<double>(x));
    return v;
}

TEST(CameraYaml, OpenCvFileStorageReadsKAndD) {
    const CameraModel c = fisheye();
    const std::string path = testing::temp_dir("camera_yaml") + "/opencv_camera.yml";
    write_opencv_camera_yaml(path, c);
    cv::FileStorage fs(path, cv::FileStorage::READ);
    ASSERT_TRUE(fs.isOpened());
    cv::Mat k, d;
    fs["K"] >> k;
    fs["D"] >> d;
    ASSERT_EQ(k.rows, 3);
    ASSERT_EQ(k.cols, 3);
    EXPECT_EQ(k.at<double>(0, 0), c.fx);
    EXPECT_EQ(k.at<double>(0, 1), c.skew);
    EXPECT_EQ(k.at<double>(0, 2), c.cx);
    EXPECT_EQ(k.at<double>(1, 1), c.fy);
    EXPECT_EQ(k.at<double>(1, 2), c.cy);
    EXPECT_EQ(k.at<double>(2, 2), 1.0);
    ASSERT_EQ(d.total(), c.distortion.size());
    for (size_t i = 0; i < c.distortion.size(); ++i)
        EXPECT_EQ(d.at<double>(static_cast<int>(i)), c.distortion[i]) << i;
    EXPECT_EQ(static_cast<int>(fs["image_width"]), 800);
    EXPECT_EQ(static_cast<std::string>(fs["model"]), "fisheye");
}

TEST(CameraYaml, RosCameraInfoParsesBackWithTheSolvedIntrinsics) {
    for (const ModelType type : {ModelType::kFisheye, ModelType::kPinhole}) {
        CameraModel c = fisheye();
        if (type == ModelType::kPinhole) {
            c.type = type;
            c.skew = 0;
            c.distortion = {-0.28, 0.07, 1.2e-3, -4.5e-4, -0.0081};
        }
        // The file is ROS's plain YAML (no directive, as camera_calibration writes it);
        // cv::FileStorage wants its "%YAML:1.0" line first, so the test adds it in memory.
        const std::string text = "%YAML:1.0\n" + ros_camera_info_yaml(c, "left cam");
        cv::FileStorage f(text, cv::FileStorage::READ | cv::FileStorage::MEMORY |
                                    cv::FileStorage::FORMAT_YAML);
        ASSERT_TRUE(f.isOpened());
        EXPECT_EQ(static_cast<int>(f["image_width"]), 800);
        EXPECT_EQ(static_cast<int>(f["image_height"]), 503);
        EXPECT_EQ(static_cast<std::string>(f["camera_name"]), "left_cam");
        EXPECT_EQ(static_cast<std::string>(f["distortion_model"]),
                  type == ModelType::kFisheye ? "equidistant" : "plumb_bob");
        EXPECT_EQ(static_cast<int>(f["camera_matrix"]["rows"]), 3);
        EXPECT_EQ(read_vector(f["camera_matrix"]["data"]),
                  (std::vector<double>{c.fx, c.skew, c.cx, 0, c.fy, c.cy, 0, 0, 1}));
        EXPECT_EQ(static_cast<int>(f["distortion_coefficients"]["cols"]),
                  static_cast<int>(c.distortion.size()));
        EXPECT_EQ(read_vector(f["distortion_coefficients"]["data"]), c.distortion);
        EXPECT_EQ(read_vector(f["rectification_matrix"]["data"]),
                  (std::vector<double>{1, 0, 0, 0, 1, 0, 0, 0, 1}));
        EXPECT_EQ(read_vector(f["projection_matrix"]["data"]),
                  (std::vector<double>{c.fx, c.skew, c.cx, 0, 0, c.fy, c.cy, 0, 0, 0, 1, 0}));
    }
}

TEST(CameraYaml, NoRosModelForOmnidir) {
    EXPECT_TRUE(has_ros_camera_info(ModelType::kFisheye));
    EXPECT_TRUE(has_ros_camera_info(ModelType::kPinhole));
    EXPECT_FALSE(has_ros_camera_info(ModelType::kOmnidir));
}

// ROS's camera_info_manager accepts only letters, digits and '_' (setCameraName), so '-', '.',
// spaces and non-ASCII bytes (here the two of UTF-8 'e'-acute) become '_'.
TEST(CameraYaml, CameraNamesAreWhatRosAccepts) {
    EXPECT_TRUE(is_ros_camera_name("left_cam2"));
    for (const char* bad : {"", "left-cam", "left cam", "a.b", "caf\xc3\xa9"})
        EXPECT_FALSE(is_ros_camera_name(bad)) << bad;
    EXPECT_EQ(ros_camera_name("fisheye-ros-mono"), "fisheye_ros_mono");
    EXPECT_EQ(ros_camera_name("caf\xc3\xa9"), "caf__");
    EXPECT_EQ(ros_camera_name(""), "camera");
}

TEST(CameraYaml, DefaultCameraNameIsTheInputsName) {
    const std::string dir = testing::temp_dir("camera_yaml_names") + "/fisheye-ros mono";
    std::filesystem::create_directories(dir);
    for (const char* f : {"/a.png", "/b.png"}) std::ofstream(dir + f) << "x";
    EXPECT_EQ(default_camera_name({dir}, ""), "fisheye_ros_mono");       // a folder: its name
    EXPECT_EQ(default_camera_name({dir + "/"}, ""), "fisheye_ros_mono");  // trailing slash
    EXPECT_EQ(default_camera_name({dir + "/a.png"}, ""), "a");           // one file: its stem
    EXPECT_EQ(default_camera_name({dir + "/a.png", dir + "/b.png"}, ""), "fisheye_ros_mono");
    EXPECT_EQ(default_camera_name({}, "/x/left-corners.xml"), "left_corners");  // corner file
}

}  // namespace
}  // namespace inlight::calib
