#include "calib/board.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "core/check.h"
#include "core/error.h"
#include "core/number.h"
#include "core/parallel.h"

namespace inlight::calib {

namespace {

/// Separable Gaussian blur with clamped edges, in place.
void gaussian_blur(std::vector<float>& img, int w, int h, double sigma) {
    const int radius = static_cast<int>(std::ceil(3 * sigma));
    std::vector<double> k(static_cast<size_t>(2 * radius + 1));
    double sum = 0;
    for (int i = -radius; i <= radius; ++i) {
        k[static_cast<size_t>(i + radius)] = std::exp(-0.5 * i * i / (sigma * sigma));
        sum += k[static_cast<size_t>(i + radius)];
    }
    for (double& v : k) v /= sum;
    std::vector<float> tmp(img.size());
    parallel::for_chunks(h, 16, [&](int64_t y0, int64_t y1) {
        for (int64_t y = y0; y < y1; ++y) {
            for (int x = 0; x < w; ++x) {
                double acc = 0;
                for (int i = -radius; i <= radius; ++i) {
                    const int xx = std::clamp(x + i, 0, w - 1);
                    acc +=
                        k[static_cast<size_t>(i + radius)] * img[static_cast<size_t>(y) * w + xx];
                }
                tmp[static_cast<size_t>(y) * w + x] = static_cast<float>(acc);
            }
        }
    });
    parallel::for_chunks(h, 16, [&](int64_t y0, int64_t y1) {
        for (int64_t y = y0; y < y1; ++y) {
            for (int x = 0; x < w; ++x) {
                double acc = 0;
                for (int i = -radius; i <= radius; ++i) {
                    const int yy = std::clamp(static_cast<int>(y) + i, 0, h - 1);
                    acc +=
                        k[static_cast<size_t>(i + radius)] * tmp[static_cast<size_t>(yy) * w + x];
                }
                img[static_cast<size_t>(y) * w + x] = static_cast<float>(acc);
            }
        }
    });
}

}  // namespace

BoardSpec parse_board(const std::string& spec, double square_size_m) {
    const std::string context = str("--board '", spec, "'");
    BoardSpec b;
    b.square_size_m = square_size_m;
    const size_t x = spec.find_first_of("xX");
    if (x == std::string::npos) {
        throw UsageError(str(context, ": expected COLSxROWS inner corners, e.g. 8x6"));
    }
    b.cols = static_cast<int>(parse_integer(spec.substr(0, x), str(context, ": columns"), 2,
                                            kMaxBoardCorners));
    b.rows = static_cast<int>(parse_integer(spec.substr(x + 1), str(context, ": rows"), 2,
                                            kMaxBoardCorners));
    if (!(square_size_m > 0) || !std::isfinite(square_size_m)) {
        throw UsageError(str("--square-size-m ", square_size_m, ": must be a finite number > 0"));
    }
    return b;
}

std::vector<Eigen::Vector3d> board_object_points(const BoardSpec& board) {
    std::vector<Eigen::Vector3d> pts;
    pts.reserve(static_cast<size_t>(board.cols) * board.rows);
    for (int r = 0; r < board.rows; ++r) {
        for (int c = 0; c < board.cols; ++c) {
            pts.emplace_back(c * board.square_size_m, r * board.square_size_m, 0.0);
        }
    }
    return pts;
}

BoardRenderer::BoardRenderer(const CameraModel& camera, const RenderOptions& options)
    : m_camera(camera), m_options(options) {
    INLIGHT_CHECK(camera.width > 0 && camera.height > 0) << "camera size not set";
    INLIGHT_CHECK_GE(options.supersample, 1);
    const Unprojector unproject(camera);
    const int w = camera.width, h = camera.height;
    m_rays.assign(static_cast<size_t>(w) * h * 9, std::numeric_limits<float>::quiet_NaN());
    constexpr double kStep = 0.25;  // central differences over +-0.25 px
    parallel::for_chunks(h, 8, [&](int64_t y_begin, int64_t y_end) {
        for (int64_t y = y_begin; y < y_end; ++y) {
            for (int x = 0; x < w; ++x) {
                const Eigen::Vector2d c(x, static_cast<double>(y));
                const auto r = unproject(c);
                const auto xp = unproject(c + Eigen::Vector2d(kStep, 0));
                const auto xm = unproject(c - Eigen::Vector2d(kStep, 0));
                const auto yp = unproject(c + Eigen::Vector2d(0, kStep));
                const auto ym = unproject(c - Eigen::Vector2d(0, kStep));
                if (!r || !xp || !xm || !yp || !ym) continue;
                // Rays scaled to z-independent form are not needed: the plane intersection
                // below is invariant to the ray's length.
                const Eigen::Vector3d dx = (*xp - *xm) / (2 * kStep);
                const Eigen::Vector3d dy = (*yp - *ym) / (2 * kStep);
                float* out = &m_rays[(static_cast<size_t>(y) * w + x) * 9];
                for (int k = 0; k < 3; ++k) {
                    out[k] = static_cast<float>((*r)[k]);
                    out[3 + k] = static_cast<float>(dx[k]);
                    out[6 + k] = static_cast<float>(dy[k]);
                }
            }
        }
    });
}

GrayImage BoardRenderer::render(const BoardSpec& board,
                                const Eigen::Isometry3d& camera_from_board) const {
    const RenderOptions& opt = m_options;
    GrayImage img;
    img.width = m_camera.width;
    img.height = m_camera.height;
    img.pixels.assign(static_cast<size_t>(img.width) * img.height, opt.background);
    std::vector<float> value(img.pixels.size());

    const Eigen::Isometry3d board_from_camera = camera_from_board.inverse();
    const Eigen::Vector3d origin = board_from_camera.translation();
    const Eigen::Matrix3d rot = board_from_camera.linear();
    const double s = board.square_size_m;
    const double x0 = -s * (1 + opt.margin_squares), x1 = s * (board.cols + opt.margin_squares);
    const double y0 = -s * (1 + opt.margin_squares), y1 = s * (board.rows + opt.margin_squares);
    const int n = opt.supersample;

    auto sample = [&](const Eigen::Vector3d& ray_camera, double px, double py) -> double {
        if (opt.circle_radius_px > 0 &&
            std::hypot(px - opt.circle_cx, py - opt.circle_cy) > opt.circle_radius_px) {
            return 0.0;
        }
        const Eigen::Vector3d d = rot * ray_camera;
        if (std::abs(d.z()) < 1e-12) return opt.background;
        const double t = -origin.z() / d.z();
        if (t <= 0) return opt.background;
        const double bx = origin.x() + t * d.x(), by = origin.y() + t * d.y();
        if (bx < x0 || bx > x1 || by < y0 || by > y1) return opt.background;
        const double fx = std::floor(bx / s), fy = std::floor(by / s);
        // Squares exist for x in [-s, cols*s] and y in [-s, rows*s]; the rest is the border.
        if (fx < -1 || fx > board.cols - 1 || fy < -1 || fy > board.rows - 1) return opt.white;
        const bool dark = (static_cast<long>(fx) + static_cast<long>(fy)) % 2 == 0;
        return dark ? opt.black : opt.white;
    };

    parallel::for_chunks(img.height, 8, [&](int64_t y_begin, int64_t y_end) {
        for (int64_t y = y_begin; y < y_end; ++y) {
            for (int x = 0; x < img.width; ++x) {
                const float* r = &m_rays[(static_cast<size_t>(y) * img.width + x) * 9];
                double v = opt.background;
                if (opt.circle_radius_px > 0 &&
                    std::hypot(x - opt.circle_cx, static_cast<double>(y) - opt.circle_cy) >
                        opt.circle_radius_px + 1) {
                    v = 0.0;  // wholly outside the image circle
                } else if (!std::isnan(r[0])) {
                    const Eigen::Vector3d c(r[0], r[1], r[2]), dx(r[3], r[4], r[5]),
                        dy(r[6], r[7], r[8]);
                    double sum = 0;
                    for (int j = 0; j < n; ++j) {
                        const double oy = (j + 0.5) / n - 0.5;
                        for (int i = 0; i < n; ++i) {
                            // Pixel (x, y) covers [x - 0.5, x + 0.5] in OpenCV pixel coordinates.
                            const double ox = (i + 0.5) / n - 0.5;
                            sum +=
                                sample(c + ox * dx + oy * dy, x + ox, static_cast<double>(y) + oy);
                        }
                    }
                    v = sum / (n * n);
                }
                value[static_cast<size_t>(y) * img.width + x] = static_cast<float>(v);
            }
        }
    });
    if (opt.blur_sigma_px > 0) gaussian_blur(value, img.width, img.height, opt.blur_sigma_px);
    parallel::for_chunks(img.height, 8, [&](int64_t y_begin, int64_t y_end) {
        std::mt19937_64 rng(opt.seed * 1000003ULL + static_cast<uint64_t>(y_begin));
        std::normal_distribution<double> noise(0.0, 1.0);
        for (int64_t y = y_begin; y < y_end; ++y) {
            for (int x = 0; x < img.width; ++x) {
                const size_t i = static_cast<size_t>(y) * img.width + x;
                double v = value[i];
                if (opt.noise_sigma > 0) v += opt.noise_sigma * noise(rng);
                img.pixels[i] = static_cast<uint8_t>(std::clamp(std::lround(v), 0L, 255L));
            }
        }
    });
    return img;
}

GrayImage render_board(const CameraModel& camera, const BoardSpec& board,
                       const Eigen::Isometry3d& camera_from_board, const RenderOptions& options) {
    return BoardRenderer(camera, options).render(board, camera_from_board);
}

}  // namespace inlight::calib
