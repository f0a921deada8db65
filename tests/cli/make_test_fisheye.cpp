// Writes a synthetic 8-bit fisheye camera frame with a clipped sun for the CLI tests:
//   inlight_make_test_fisheye DIR N THETA_MAX_DEG SKY_CODE SUN_THETA_DEG SUN_PHI_DEG SUN_RADIUS_DEG
// The equidistant fisheye of envmap::testmaps::fisheye_frame (r = f theta, f = (N / 2) /
// theta_max, looking along +z of the device frame; pixel solid angle sin theta / (f^2 theta) sr;
// pixel centres beyond theta_max unobserved: code 0, solid angle 0). Writes DIR/frame.png
// (codes: SKY_CODE, and 255 = clipped where the pixel centre is within SUN_RADIUS of the sun's
// direction (sin t cos p, sin t sin p, cos t)), DIR/directions.exr, DIR/solid_angle.exr.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "envmap/envmap_testing.h"
#include "image/image.h"

int main(int argc, char** argv) {
    if (argc != 8) {
        std::fprintf(stderr,
                     "usage: %s DIR N THETA_MAX_DEG SKY_CODE SUN_THETA_DEG SUN_PHI_DEG "
                     "SUN_RADIUS_DEG\n",
                     argv[0]);
        return 2;
    }
    const std::string dir = argv[1];
    const double deg = M_PI / 180;
    const double st = std::atof(argv[5]) * deg, sp = std::atof(argv[6]) * deg;
    const Eigen::Vector3d sun(std::sin(st) * std::cos(sp), std::sin(st) * std::sin(sp),
                              std::cos(st));
    const double cos_r = std::cos(std::atof(argv[7]) * deg), sky = std::atoi(argv[4]) / 255.0;
    const inlight::envmap::Environment fe = inlight::envmap::testmaps::fisheye_frame(
        std::atoi(argv[2]), std::atof(argv[3]) * deg, [&](const Eigen::Vector3d& d) {
            return Eigen::Vector3d::Constant(d.dot(sun) >= cos_r ? 1.0 : sky);
        });
    inlight::image::WriteOptions wo;
    wo.encode_srgb = false;  // the PNG's code is round(255 * value): the camera's own codes
    inlight::image::write_image(dir + "/frame.png", fe.radiance, wo);
    inlight::image::write_image(dir + "/directions.exr", fe.directions, wo);
    inlight::image::write_image(dir + "/solid_angle.exr", fe.solid_angle, wo);
    return 0;
}
