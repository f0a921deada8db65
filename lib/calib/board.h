// calib/board.h: the chessboard target (its inner-corner grid in board coordinates) and a
// renderer that photographs it through a known CameraModel, for tests and demonstrations.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <vector>

#include "calib/camera_model.h"

namespace inlight::calib {

/// A chessboard by its inner corners: `cols` x `rows` corners (a board of (cols+1) x (rows+1)
/// squares), squares of side `square_size_m` metres (any unit works: it scales only the
/// translations, never the intrinsics).
struct BoardSpec {
    int cols = 0;
    int rows = 0;
    double square_size_m = 1.0;
};

/// Largest number of inner corners along one side of a board that parse_board accepts.
inline constexpr int kMaxBoardCorners = 1000;

/// Parses "COLSxROWS" (inner corners, e.g. "8x6"), each in [2, kMaxBoardCorners], and checks
/// square_size_m is finite and > 0. Throws UsageError naming --board / --square-size-m.
BoardSpec parse_board(const std::string& spec, double square_size_m);

/// Board-frame corners in OpenCV's detection order: row-major, point (c, r) at
/// (c * square, r * square, 0) for r in [0, rows), c in [0, cols).
std::vector<Eigen::Vector3d> board_object_points(const BoardSpec& board);

/// An 8-bit single-channel image, row-major, row 0 on top.
struct GrayImage {
    int width = 0;
    int height = 0;
    std::vector<uint8_t> pixels;
    uint8_t at(int x, int y) const { return pixels[static_cast<size_t>(y) * width + x]; }
};

/// How render_board draws.
struct RenderOptions {
    int supersample = 4;          ///< n x n samples per pixel (box filter = pixel integration)
    double margin_squares = 1.0;  ///< white border around the squares, in squares
    uint8_t black = 25;           ///< code of the dark squares
    uint8_t white = 230;          ///< code of the light squares and the border
    uint8_t background = 100;     ///< code where the ray misses the board (or the image circle)
    double blur_sigma_px = 0;     ///< Gaussian blur (lens PSF) before noise and quantisation, px
    double noise_sigma = 0;       ///< Gaussian noise, codes (0 = none); seeded, deterministic
    uint64_t seed = 1;
    /// Pixels farther than this from (circle_cx, circle_cy) are black, imitating a lens'
    /// image circle (0 = no circle).
    double circle_radius_px = 0;
    double circle_cx = 0;
    double circle_cy = 0;
};

/// Renders boards seen by one camera by casting each sample's ray onto the board plane. The
/// rays are computed once per camera: a pixel-centre ray and its derivatives along x and y
/// (samples use the first-order expansion, off by < 1e-3 px for focal lengths above 100 px).
/// Deterministic for any thread count. Memory: 36 bytes per pixel.
class BoardRenderer {
  public:
    /// Precondition: camera.width, camera.height > 0 (checked).
    BoardRenderer(const CameraModel& camera, const RenderOptions& options = {});

    /// `board` placed by `camera_from_board` (board coordinates into the OpenCV camera frame).
    GrayImage render(const BoardSpec& board, const Eigen::Isometry3d& camera_from_board) const;

  private:
    CameraModel m_camera;
    RenderOptions m_options;
    std::vector<float> m_rays;  ///< per pixel: centre ray (3), d/dx (3), d/dy (3); NaN = none
};

/// One-off convenience over BoardRenderer.
GrayImage render_board(const CameraModel& camera, const BoardSpec& board,
                       const Eigen::Isometry3d& camera_from_board,
                       const RenderOptions& options = {});

}  // namespace inlight::calib
