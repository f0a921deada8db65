#include "calib/refine.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "core/check.h"
#include "core/parallel.h"

namespace inlight::calib {

namespace {

/// Canvas pixels per board square: about 1.25 x the largest corner spacing seen in the image,
/// so the resampling never loses resolution, within [16, 128] to bound cost and keep the
/// cornerSubPix window meaningful.
int pixels_per_square(const View& view, const BoardSpec& board) {
    double spacing = 0;
    const double s = board.square_size_m;
    for (size_t i = 0; i < view.object_points.size(); ++i) {
        for (size_t j = i + 1; j < view.object_points.size(); ++j) {
            if (std::abs((view.object_points[i] - view.object_points[j]).norm() - s) < 1e-6 * s) {
                spacing = std::max(spacing, (view.image_points[i] - view.image_points[j]).norm());
            }
        }
    }
    return std::clamp(static_cast<int>(std::ceil(1.25 * spacing)), 16, 128);
}

}  // namespace

View refine_view(const GrayImage& image, const View& view, const BoardSpec& board,
                 const CameraModel& camera, const Eigen::Vector3d& rvec,
                 const Eigen::Vector3d& tvec) {
    INLIGHT_CHECK_EQ(view.image_points.size(), view.object_points.size());
    const double s = board.square_size_m;
    const int pps = pixels_per_square(view, board);
    const int cw = (board.cols + 1) * pps, ch = (board.rows + 1) * pps;
    const Eigen::Matrix3d rot = rotation_from_rodrigues(rvec);

    // Canvas pixel (i, j) samples board point (((i + 0.5) / pps - 1) s, ((j + 0.5) / pps - 1) s).
    auto board_point = [&](double i, double j) {
        return Eigen::Vector3d(((i + 0.5) / pps - 1) * s, ((j + 0.5) / pps - 1) * s, 0.0);
    };
    cv::Mat map_x(ch, cw, CV_32F), map_y(ch, cw, CV_32F);
    cv::Mat inside(ch, cw, CV_8U);
    parallel::for_chunks(ch, 16, [&](int64_t j0, int64_t j1) {
        for (int j = static_cast<int>(j0); j < static_cast<int>(j1); ++j) {
            for (int i = 0; i < cw; ++i) {
                const auto px = camera.project(rot * board_point(i, j) + tvec);
                const bool ok = px && px->x() >= 1 && px->y() >= 1 && px->x() <= image.width - 2 &&
                                px->y() <= image.height - 2;
                map_x.at<float>(j, i) = ok ? static_cast<float>(px->x()) : -1.0f;
                map_y.at<float>(j, i) = ok ? static_cast<float>(px->y()) : -1.0f;
                inside.at<uint8_t>(j, i) = ok ? 1 : 0;
            }
        }
    });
    cv::Mat src(image.height, image.width, CV_8UC1, const_cast<uint8_t*>(image.pixels.data()));
    cv::Mat src_f, canvas;
    src.convertTo(src_f, CV_32F);
    cv::remap(src_f, canvas, map_x, map_y, cv::INTER_CUBIC, cv::BORDER_CONSTANT, 0);

    const int radius = std::max(2, static_cast<int>(0.4 * pps));
    std::vector<cv::Point2f> start, pts;
    std::vector<size_t> which;
    for (size_t k = 0; k < view.object_points.size(); ++k) {
        const Eigen::Vector3d& p = view.object_points[k];
        const double ci = (p.x() / s + 1) * pps - 0.5, cj = (p.y() / s + 1) * pps - 0.5;
        const int i0 = static_cast<int>(std::floor(ci)) - radius - 2;
        const int j0 = static_cast<int>(std::floor(cj)) - radius - 2;
        const int i1 = static_cast<int>(std::ceil(ci)) + radius + 2;
        const int j1 = static_cast<int>(std::ceil(cj)) + radius + 2;
        if (i0 < 0 || j0 < 0 || i1 >= cw || j1 >= ch) continue;
        if (cv::countNonZero(inside(cv::Rect(i0, j0, i1 - i0 + 1, j1 - j0 + 1))) !=
            (i1 - i0 + 1) * (j1 - j0 + 1)) {
            continue;  // the window reaches outside the image: keep the detection
        }
        start.emplace_back(static_cast<float>(ci), static_cast<float>(cj));
        which.push_back(k);
    }
    View out = view;
    if (start.empty()) return out;
    pts = start;
    cv::cornerSubPix(canvas, pts, cv::Size(radius, radius), cv::Size(-1, -1),
                     cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 100, 1e-4));
    for (size_t n = 0; n < which.size(); ++n) {
        if (cv::norm(pts[n] - start[n]) > 0.25 * pps) continue;
        const auto px = camera.project(rot * board_point(pts[n].x, pts[n].y) + tvec);
        if (px) out.image_points[which[n]] = *px;
    }
    return out;
}

}  // namespace inlight::calib
