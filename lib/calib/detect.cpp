#include "calib/detect.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <mutex>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "core/enum_names.h"
#include "core/error.h"
#include "core/fs.h"
#include "core/parallel.h"
#include "image/image.h"

namespace inlight::calib {

namespace {

/// ROS camera_calibration's cornerSubPix termination: steps below 0.1 px, or 30 iterations.
constexpr double kRosSubpixEpsilonPx = 0.1;
constexpr int kRosSubpixMaxIterations = 30;

cv::Mat as_mat(const GrayImage& img) {
    return cv::Mat(img.height, img.width, CV_8UC1, const_cast<uint8_t*>(img.pixels.data()));
}

GrayImage from_mat(const cv::Mat& m) {
    GrayImage g;
    g.width = m.cols;
    g.height = m.rows;
    g.pixels.resize(static_cast<size_t>(m.cols) * m.rows);
    for (int y = 0; y < m.rows; ++y) {
        std::copy(m.ptr<uint8_t>(y), m.ptr<uint8_t>(y) + m.cols,
                  g.pixels.begin() + static_cast<ptrdiff_t>(y) * m.cols);
    }
    return g;
}

/// cornerSubPix window radius as a fraction of the smallest corner spacing. ROS uses 0.5; with
/// cornerSubPix run to convergence (eps 0.001 px) a window reaching the neighbouring corners
/// lets them pull the estimate: on OpenCV's left01-14.jpg, 0.5 gives 1.3 px RMS, 0.35 gives
/// 0.18 px; on fisheye-ros-mono both give 0.47 px.
constexpr double kSubpixRadiusFraction = 0.35;

/// The cornerSubPix radius: large enough to snap to the corner, small enough not to reach the
/// next one.
int half_min_spacing(const std::vector<cv::Point2f>& c, int cols, int rows) {
    double md = std::numeric_limits<double>::infinity();
    for (int r = 0; r < rows; ++r) {
        for (int k = 0; k < cols; ++k) {
            const cv::Point2f& p = c[static_cast<size_t>(r * cols + k)];
            if (k + 1 < cols)
                md = std::min(md, cv::norm(p - c[static_cast<size_t>(r * cols + k + 1)]));
            if (r + 1 < rows)
                md = std::min(md, cv::norm(p - c[static_cast<size_t>((r + 1) * cols + k)]));
        }
    }
    return std::max(2, static_cast<int>(std::ceil(kSubpixRadiusFraction * md)));
}

/// ROS camera_calibration's version: its index is row * rows + col (not row * cols + col), so
/// it compares a different set of neighbours; kept to reproduce its results exactly.
int ros_half_min_spacing(const std::vector<cv::Point2f>& c, int cols, int rows) {
    double md = std::numeric_limits<double>::infinity();
    const int n = cols * rows;
    for (int r = 0; r < rows; ++r) {
        for (int k = 0; k + 1 < cols; ++k) {
            const int i = r * rows + k;
            if (i + 1 < n)
                md = std::min(md,
                              cv::norm(c[static_cast<size_t>(i)] - c[static_cast<size_t>(i + 1)]));
        }
    }
    for (int r = 0; r + 1 < rows; ++r) {
        for (int k = 0; k < cols; ++k) {
            const int i = r * rows + k;
            if (i + cols < n)
                md = std::min(
                    md, cv::norm(c[static_cast<size_t>(i)] - c[static_cast<size_t>(i + cols)]));
        }
    }
    return std::max(1, static_cast<int>(std::ceil(0.5 * md)));
}

void subpix(const cv::Mat& img, std::vector<cv::Point2f>& corners, int radius, double eps,
            int iterations) {
    cv::cornerSubPix(
        img, corners, cv::Size(radius, radius), cv::Size(-1, -1),
        cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, iterations, eps));
}

bool is_image_file(const std::filesystem::path& p) {
    static const char* const kExt[] = {"png", "jpg", "jpeg", "tif", "tiff", "bmp",
                                       "pgm", "ppm", "pnm",  "exr", "hdr",  "webp"};
    const std::string ext = fs::extension(p.string());
    return std::any_of(std::begin(kExt), std::end(kExt), [&](const char* e) { return ext == e; });
}

}  // namespace

constexpr EnumName<Detector> kDetectorNames[] = {
    {Detector::kAuto, "auto"},
    {Detector::kClassic, "classic"},
    {Detector::kSectorBased, "sb"},
    {Detector::kRos, "ros"},
};

std::string to_string(Detector detector) { return enum_to_string(kDetectorNames, detector); }

Detector detector_from_string(const std::string& name) {
    return enum_from_string(kDetectorNames, name, "detector");
}

GrayImage load_gray(const std::string& path) {
    // EXIF orientation is ignored: calibration refers to the sensor's own pixel grid.
    fs::check_input_file(path);  // cv::imread of a FIFO or /dev/zero never returns
    cv::Mat m;
    try {
        m = cv::imread(path,
                       cv::IMREAD_ANYDEPTH | cv::IMREAD_GRAYSCALE | cv::IMREAD_IGNORE_ORIENTATION);
    } catch (const cv::Exception&) {
        m = cv::Mat();
    }
    if (!m.empty()) {
        if (m.depth() == CV_8U) return from_mat(m);
        double lo, hi;
        cv::minMaxLoc(m, &lo, &hi);
        if (!(hi > 0)) throw Error(str(path, ": image is black (maximum ", hi, ")"));
        cv::Mat out;
        m.convertTo(out, CV_8U, 255.0 / hi);
        return from_mat(out);
    }
    // OpenCV cannot read it: try OpenImageIO (EXR, HDR, ...) through lib/image.
    image::ReadOptions ro;
    ro.decode_srgb = false;
    const image::ImageInfo info = image::read_info(path);
    const image::Image img = image::read_image(path, ro);
    GrayImage g;
    g.width = img.width;
    g.height = img.height;
    g.pixels.resize(img.pixel_count());
    std::vector<float> luma(img.pixel_count());
    float hi = 0;
    for (size_t i = 0; i < luma.size(); ++i) {
        const float* p = &img.pixels[i * img.channels];
        luma[i] = img.channels >= 3 ? 0.299f * p[0] + 0.587f * p[1] + 0.114f * p[2] : p[0];
        hi = std::max(hi, luma[i]);
    }
    const float scale = (!info.is_float && info.bits_per_channel == 8) ? 255.0f
                        : hi > 0                                       ? 255.0f / hi
                                                                       : 0.0f;
    if (scale == 0) throw Error(str(path, ": image is black"));
    for (size_t i = 0; i < luma.size(); ++i) {
        g.pixels[i] = static_cast<uint8_t>(std::clamp(std::lround(luma[i] * scale), 0L, 255L));
    }
    return g;
}

Eigen::Vector2i image_size(const std::string& path) {
    try {
        const image::ImageInfo info = image::read_info(path);
        return {info.width, info.height};
    } catch (const Error&) {
        const GrayImage g = load_gray(path);
        return {g.width, g.height};
    }
}

Detection detect_board(const GrayImage& image, const std::string& name,
                       const DetectOptions& options) {
    if (options.detector == Detector::kAuto) {
        DetectOptions o = options;
        o.detector = Detector::kClassic;
        Detection det = detect_board(image, name, o);
        if (det.found || det.reason.find("not found") == std::string::npos) return det;
        o.detector = Detector::kSectorBased;
        return detect_board(image, name, o);
    }
    Detection det;
    const BoardSpec& b = options.board;
    const cv::Size pattern(b.cols, b.rows);
    const cv::Mat full = as_mat(image);
    std::vector<cv::Point2f> corners;
    const std::string not_found = str("board of ", b.cols, "x", b.rows, " inner corners not found");

    if (options.detector == Detector::kSectorBased) {
        const bool ok = cv::findChessboardCornersSB(
            full, pattern, corners, cv::CALIB_CB_EXHAUSTIVE | cv::CALIB_CB_ACCURACY);
        if (!ok || corners.size() != static_cast<size_t>(b.cols * b.rows)) {
            det.reason = not_found;
            return det;
        }
    } else {
        const bool ros = options.detector == Detector::kRos;
        const double pixels = static_cast<double>(image.width) * image.height;
        const double scale =
            options.detect_max_pixels > 0 && pixels > options.detect_max_pixels
                ? std::sqrt(pixels / static_cast<double>(options.detect_max_pixels))
                : 1.0;
        cv::Mat small = full;
        if (scale > 1) {
            cv::resize(full, small,
                       cv::Size(static_cast<int>(image.width / scale),
                                static_cast<int>(image.height / scale)));
        }
        const int flags =
            cv::CALIB_CB_ADAPTIVE_THRESH | cv::CALIB_CB_NORMALIZE_IMAGE | cv::CALIB_CB_FAST_CHECK;
        if (!cv::findChessboardCorners(small, pattern, corners, flags)) {
            det.reason = not_found;
            return det;
        }
        if (corners.front().y > corners.back().y) std::reverse(corners.begin(), corners.end());
        if (ros) {
            subpix(small, corners, ros_half_min_spacing(corners, b.cols, b.rows),
                   kRosSubpixEpsilonPx, kRosSubpixMaxIterations);
            if (scale > 1) {
                // ROS scales coordinates up ignoring the half-pixel shift, then refines with a
                // window of radius ceil(scale).
                const double sx = static_cast<double>(image.width) / small.cols;
                const double sy = static_cast<double>(image.height) / small.rows;
                for (cv::Point2f& p : corners) {
                    p.x = static_cast<float>(p.x * sx);
                    p.y = static_cast<float>(p.y * sy);
                }
                subpix(full, corners, static_cast<int>(std::ceil(scale)), kRosSubpixEpsilonPx,
                       kRosSubpixMaxIterations);
            }
        } else {
            if (scale > 1) {
                const double sx = static_cast<double>(image.width) / small.cols;
                const double sy = static_cast<double>(image.height) / small.rows;
                for (cv::Point2f& p : corners) {  // pixel centres: x + 0.5 = (x_small + 0.5) sx
                    p.x = static_cast<float>((p.x + 0.5) * sx - 0.5);
                    p.y = static_cast<float>((p.y + 0.5) * sy - 0.5);
                }
            }
            // One refinement at full resolution, window radius half the corner spacing.
            subpix(full, corners, half_min_spacing(corners, b.cols, b.rows),
                   options.subpix_epsilon_px, options.subpix_max_iterations);
        }
    }
    // One orientation for every view: first corner above the last (as ROS does). A 180 degree
    // relabelling is a rigid motion of a planar grid, so this never changes the intrinsics.
    if (corners.front().y > corners.back().y) std::reverse(corners.begin(), corners.end());

    for (const cv::Point2f& p : corners) {
        if (p.x < options.border_px || p.y < options.border_px ||
            p.x > image.width - 1 - options.border_px ||
            p.y > image.height - 1 - options.border_px) {
            det.reason = str("board corner at (", p.x, ", ", p.y, ") within ", options.border_px,
                             " px of the image edge");
            return det;
        }
    }
    det.found = true;
    det.view.name = name;
    det.view.object_points = board_object_points(b);
    for (const cv::Point2f& p : corners) det.view.image_points.emplace_back(p.x, p.y);
    return det;
}

Detections detect_boards(const std::vector<std::string>& paths, const DetectOptions& options,
                         GrayImage* brightest) {
    if (paths.empty()) throw Error("no input images");
    // Sizes first, from the headers: mixed sizes are rejected before any detection work.
    std::vector<Eigen::Vector2i> sizes(paths.size());
    parallel::for_chunks(static_cast<int64_t>(paths.size()), 1, [&](int64_t b, int64_t e) {
        for (int64_t i = b; i < e; ++i) sizes[i] = image_size(paths[i]);
    });
    std::map<std::pair<int, int>, std::vector<std::string>> by_size;
    for (size_t i = 0; i < paths.size(); ++i) {
        by_size[{sizes[i].x(), sizes[i].y()}].push_back(
            std::filesystem::path(paths[i]).filename().string());
    }
    if (by_size.size() > 1) {
        std::string msg =
            "mixed image sizes (all views must come from one camera at one "
            "resolution):";
        for (const auto& [size, names] : by_size) {
            msg += str(" ", size.first, "x", size.second, " (", names.size(), " file",
                       names.size() == 1 ? "" : "s", ": ");
            for (size_t i = 0; i < names.size() && i < 6; ++i) msg += (i ? ", " : "") + names[i];
            if (names.size() > 6) msg += str(", and ", names.size() - 6, " more");
            msg += ");";
        }
        msg.pop_back();
        throw Error(msg);
    }

    std::vector<Detection> found(paths.size());
    std::mutex max_mutex;  // the maximum does not depend on the order of accumulation
    parallel::for_chunks(static_cast<int64_t>(paths.size()), 1, [&](int64_t b, int64_t e) {
        for (int64_t i = b; i < e; ++i) {
            const GrayImage img = load_gray(paths[i]);
            found[i] =
                detect_board(img, std::filesystem::path(paths[i]).filename().string(), options);
            if (brightest) {
                std::lock_guard<std::mutex> lock(max_mutex);
                if (brightest->pixels.empty()) {
                    *brightest = img;
                } else {
                    for (size_t k = 0; k < img.pixels.size(); ++k) {
                        brightest->pixels[k] = std::max(brightest->pixels[k], img.pixels[k]);
                    }
                }
            }
        }
    });

    Detections out;
    out.width = sizes[0].x();
    out.height = sizes[0].y();
    for (size_t i = 0; i < paths.size(); ++i) {
        if (found[i].found) {
            out.views.push_back(std::move(found[i].view));
            out.view_paths.push_back(paths[i]);
        } else {
            out.dropped.push_back(
                {std::filesystem::path(paths[i]).filename().string(), found[i].reason});
        }
    }
    return out;
}

std::vector<std::string> expand_image_inputs(const std::vector<std::string>& inputs) {
    namespace sfs = std::filesystem;
    std::vector<std::string> out;
    for (const std::string& in : inputs) {
        std::error_code ec;
        if (sfs::is_directory(in, ec)) {
            std::vector<std::string> files;
            for (const auto& entry : sfs::directory_iterator(in)) {
                if (entry.is_regular_file() && is_image_file(entry.path())) {
                    files.push_back(entry.path().string());
                }
            }
            if (files.empty()) throw Error(str(in, ": folder contains no image files"));
            std::sort(files.begin(), files.end());
            out.insert(out.end(), files.begin(), files.end());
        } else if (sfs::exists(in, ec)) {
            out.push_back(in);
        } else {
            throw Error(str(in, ": no such file or folder"));
        }
    }
    return out;
}

}  // namespace inlight::calib
