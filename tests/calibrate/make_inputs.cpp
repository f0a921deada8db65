// Synthetic inputs for the calibrate CLI tests (deterministic):
//   make_inputs boards DIR W H N [CIRCLE_R]  N chessboard views (9x6 inner corners) through a
//                                            known 165-degree fisheye, PNG, + DIR/truth.json;
//                                            with CIRCLE_R, black outside that image circle
//   make_inputs blank DIR W H N              N frames without a board
//   make_inputs bracket DIR W H              3 exposures (0.004, 0.016, 0.064 s) of a still scene
//                                            through a known response (gamma 2.2)
//   make_inputs png16 PATH W H               a 16-bit grey PNG
#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>

#include "calib/board.h"
#include "core/conventions.h"
#include "image/image.h"

using namespace inlight;

namespace {

void write_gray(const std::string& path, const calib::GrayImage& g, int bits = 8) {
    image::Image img(g.width, g.height, 1, image::ColorSpace::kData);
    for (size_t i = 0; i < g.pixels.size(); ++i) img.pixels[i] = g.pixels[i] / 255.0f;
    image::WriteOptions wo;
    wo.bits = bits;
    wo.encode_srgb = false;
    image::write_image(path, img, wo);
}

calib::CameraModel truth_model(int w, int h) {
    calib::CameraModel m = calib::CameraModel::make(calib::ModelType::kFisheye, w, h, 0.234 * w,
                                                    0.2336 * w, 0.5 * w + 1.3, 0.5 * h - 1.4);
    m.distortion = {0.021, -0.008, 0.0031, -0.0007};
    return m;
}

Eigen::Isometry3d board_pose(const calib::BoardSpec& b, double theta_c, double phi_c, double dist,
                             double tilt_x, double tilt_y, double roll) {
    const Eigen::Vector3d dir = direction_from_spherical(theta_c, phi_c);
    const Eigen::Matrix3d r =
        Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), dir).toRotationMatrix() *
        Eigen::AngleAxisd(tilt_x, Eigen::Vector3d::UnitX()) *
        Eigen::AngleAxisd(tilt_y, Eigen::Vector3d::UnitY()) *
        Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitZ());
    Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
    t.linear() = r;
    t.translation() =
        dist * dir - r * Eigen::Vector3d(4 * b.square_size_m, 2.5 * b.square_size_m, 0);
    return t;
}

int boards(const std::string& dir, int w, int h, int n, double circle_r) {
    const calib::CameraModel m = truth_model(w, h);
    const calib::BoardSpec board{9, 6, 0.03};
    calib::RenderOptions ro;
    ro.supersample = 3;
    ro.blur_sigma_px = 0.5;
    if (circle_r > 0) {
        ro.circle_radius_px = circle_r;
        ro.circle_cx = m.cx;
        ro.circle_cy = m.cy;
    }
    const calib::BoardRenderer renderer(m, ro);
    // Rings at 0, 25, 45 and 60 degrees off axis, as a careful user would hold the board.
    const double rings[][2] = {{0, 1}, {25, 5}, {45, 6}, {60, 8}};
    int k = 0;
    for (const auto& ring : rings) {
        for (int i = 0; i < ring[1] && k < n; ++i, ++k) {
            const double phi = 2 * kPi * i / ring[1] + 0.4 * ring[0] / 55;
            const auto pose =
                board_pose(board, ring[0] * kPi / 180, phi, 0.21 * (1 + 0.1 * (k % 2 ? 1 : -1)),
                           ((k % 3) - 1) * 0.3, (((k / 3) % 3) - 1) * 0.3, 0.4 * ((k % 4) - 1.5));
            char name[64];
            std::snprintf(name, sizeof name, "/view_%02d.png", k);
            write_gray(dir + name, renderer.render(board, pose));
        }
    }
    std::ofstream t(dir + "/truth.json");
    t.precision(17);
    t << "{\"fx\": " << m.fx << ", \"fy\": " << m.fy << ", \"cx\": " << m.cx << ", \"cy\": " << m.cy
      << ", \"k1\": " << m.distortion[0] << ", \"k2\": " << m.distortion[1]
      << ", \"k3\": " << m.distortion[2] << ", \"k4\": " << m.distortion[3] << "}\n";
    return 0;
}

int blank(const std::string& dir, int w, int h, int n) {
    std::mt19937 rng(1);
    for (int k = 0; k < n; ++k) {
        calib::GrayImage g;
        g.width = w;
        g.height = h;
        g.pixels.resize(static_cast<size_t>(w) * h);
        for (size_t i = 0; i < g.pixels.size(); ++i)
            g.pixels[i] = static_cast<uint8_t>(90 + rng() % 40);
        char name[64];
        std::snprintf(name, sizeof name, "/blank_%02d.png", k);
        write_gray(dir + name, g);
    }
    return 0;
}

int bracket(const std::string& dir, int w, int h) {
    const double exposures[3] = {0.004, 0.016, 0.064};
    for (int j = 0; j < 3; ++j) {
        image::Image img(w, h, 3, image::ColorSpace::kData);
        for (int y = 0; y < h; ++y) {
            for (int x = 0; x < w; ++x) {
                // Radiance from 1 to ~300 across the frame, a different slope per channel.
                for (int c = 0; c < 3; ++c) {
                    const double e =
                        std::pow(10.0, 2.5 * (x + 0.37 * y) / (w + 0.37 * h)) * (1 - 0.2 * c);
                    const double v = std::pow(std::min(e * exposures[j] / 1.2, 1.0), 1 / 2.2);
                    img.at(x, y, c) = static_cast<float>(std::round(255 * v) / 255);
                }
            }
        }
        image::WriteOptions wo;
        wo.encode_srgb = false;
        image::write_image(dir + "/exposure_" + std::to_string(j) + ".png", img, wo);
    }
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    try {
        const std::string mode = argc > 1 ? argv[1] : "";
        if (argc >= 6 && mode == "boards") {
            std::filesystem::create_directories(argv[2]);
            return boards(argv[2], std::stoi(argv[3]), std::stoi(argv[4]), std::stoi(argv[5]),
                          argc > 6 ? std::stod(argv[6]) : 0.0);
        }
        if (argc == 6 && mode == "blank") {
            std::filesystem::create_directories(argv[2]);
            return blank(argv[2], std::stoi(argv[3]), std::stoi(argv[4]), std::stoi(argv[5]));
        }
        if (argc == 5 && mode == "bracket") {
            std::filesystem::create_directories(argv[2]);
            return bracket(argv[2], std::stoi(argv[3]), std::stoi(argv[4]));
        }
        if (argc == 5 && mode == "png16") {
            calib::GrayImage g;
            g.width = std::stoi(argv[3]);
            g.height = std::stoi(argv[4]);
            g.pixels.assign(static_cast<size_t>(g.width) * g.height, 128);
            write_gray(argv[2], g, 16);
            return 0;
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "make_inputs: %s\n", e.what());
        return 1;
    }
    std::fprintf(stderr,
                 "usage: make_inputs boards DIR W H N [CIRCLE_R] | blank DIR W H N | "
                 "bracket DIR W H | png16 PATH W H\n");
    return 2;
}
