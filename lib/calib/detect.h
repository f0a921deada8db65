// calib/detect.h: finding chessboard corners in photographs (OpenCV's findChessboardCorners +
// cornerSubPix, or findChessboardCornersSB), with the reasons a view is rejected.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "calib/board.h"

namespace inlight::calib {

/// One view of the board: matched image and board points.
struct View {
    std::string name;                            ///< file name (or "image_<i>" from corner files)
    std::vector<Eigen::Vector2d> image_points;   ///< pixels, OpenCV convention (see camera_model.h)
    std::vector<Eigen::Vector3d> object_points;  ///< board frame, metres
};

/// A view left out of the calibration and why ("board not found", "reprojection outlier ...").
struct DroppedView {
    std::string name;
    std::string reason;
};

/// Corner detectors.
enum class Detector {
    /// kClassic, and kSectorBased where kClassic finds no board (strongly curved boards near
    /// the edge of a fisheye image). Use with fronto-parallel refinement (refine.h), which
    /// removes the bias of both.
    kAuto,
    /// cv::findChessboardCorners (adaptive threshold, normalised image) on a copy scaled to about
    /// `detect_max_pixels`, then cv::cornerSubPix at that scale (window radius half the smallest
    /// corner spacing) and again at full resolution (radius = the scale factor, at least 2):
    /// the procedure of ROS camera_calibration, which produced fisheye-ros-mono's ost.yaml.
    kClassic,
    /// cv::findChessboardCornersSB (exhaustive, accuracy flags) at full resolution; its own
    /// sub-pixel estimate, no cornerSubPix.
    kSectorBased,
    /// ROS camera_calibration's procedure exactly, quirks included (corners scaled up as
    /// x * scale without the half-pixel shift, its corner-spacing index, cornerSubPix stopping at
    /// 0.1 px steps), to reproduce calibrations made with it, such as fisheye-ros-mono/ost.yaml.
    kRos,
};

/// "auto" / "classic" / "sb" / "ros"; the inverse throws UsageError.
std::string to_string(Detector detector);
Detector detector_from_string(const std::string& name);

struct DetectOptions {
    BoardSpec board;
    Detector detector = Detector::kAuto;
    /// kClassic, kRos: detect on a copy downscaled to about this many pixels when the image is
    /// larger (0 = detect at full resolution). 640 x 480, as ROS camera_calibration.
    int64_t detect_max_pixels = 640 * 480;
    /// kClassic: cornerSubPix iterates until a step moves the corner less than this (pixels) or
    /// for subpix_max_iterations.
    double subpix_epsilon_px = 0.001;
    int subpix_max_iterations = 100;
    /// A board with a corner closer than this to the image edge is rejected (corners there are
    /// cut by the frame and biased). Pixels.
    double border_px = 8;
};

/// Reads any image OpenCV or OpenImageIO reads (8 or 16 bit, grey or colour, or float) as 8-bit
/// grey. 16-bit and float images are scaled so their maximum maps to 255. Throws Error naming
/// the file.
GrayImage load_gray(const std::string& path);

/// Width and height from the file header (no pixel decoding). Throws Error naming the file.
Eigen::Vector2i image_size(const std::string& path);

/// Result of looking for the board in one image: the view, or an empty `reason`-bearing miss.
struct Detection {
    bool found = false;
    View view;           ///< valid when found (object points from options.board)
    std::string reason;  ///< why not, when !found
};

/// Looks for the board in one image. Deterministic. Thread-compatible.
Detection detect_board(const GrayImage& image, const std::string& name,
                       const DetectOptions& options);

/// All views found in a set of images, and the ones that were not.
struct Detections {
    int width = 0;
    int height = 0;
    std::vector<View> views;              ///< in input order
    std::vector<std::string> view_paths;  ///< the file of each view
    std::vector<DroppedView> dropped;     ///< in input order
};

/// Checks that all images have the same size (throws Error naming the files of each size
/// otherwise), then detects the board in each, in parallel; the result does not depend on the
/// thread count. An empty list throws Error. If `brightest` is given, it receives the
/// per-pixel maximum of all images (for detect_image_circle).
Detections detect_boards(const std::vector<std::string>& paths, const DetectOptions& options,
                         GrayImage* brightest = nullptr);

/// Expands folders into the image files they contain (by extension: png jpg jpeg tif tiff bmp
/// pgm ppm pnm exr hdr webp), sorted by name; files are kept as given. Throws Error for a
/// missing path or a folder without images.
std::vector<std::string> expand_image_inputs(const std::vector<std::string>& inputs);

}  // namespace inlight::calib
