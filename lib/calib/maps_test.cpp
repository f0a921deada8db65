#include "calib/maps.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/conventions.h"
#include "core/error.h"
#include "core/parallel.h"
#include "testing/testing.h"

namespace inlight::calib {
namespace {

/// The requirement for the solid-angle map: its sum over the mask equals the field of
/// view's solid angle within 0.1%. (The pixel-centre mask misassigns only boundary pixels, in
/// both directions; measured error is ~1e-5.)
constexpr double kFovSolidAngleRel = 1e-3;

/// A 165-degree fisheye whose whole image circle lies inside an 800 x 600 frame.
CameraModel fisheye_165() {
    CameraModel m = CameraModel::make(ModelType::kFisheye, 800, 600, 150.0, 149.6, 401.3, 298.7);
    m.distortion = {0.021, -0.008, 0.0031, -0.0007};
    return m;
}

TEST(Maps, SolidAngleSumsToFieldOfView) {
    const CameraModel m = fisheye_165();
    const double theta_max = 0.5 * 165.0 * kPi / 180;
    // The circle theta <= theta_max must be entirely inside the frame for the closed form.
    ASSERT_LT(m.radial(theta_max) * m.fx + 2, std::min(m.cx, m.width - 1 - m.cx));
    ASSERT_LT(m.radial(theta_max) * m.fy + 2, std::min(m.cy, m.height - 1 - m.cy));
    MapOptions opt;
    opt.max_theta = theta_max;
    const DirectionMaps maps = compute_maps(m, opt);
    const double cap = 2 * kPi * (1 - std::cos(theta_max));
    EXPECT_NEAR(maps.covered_solid_angle_sr / cap, 1.0, kFovSolidAngleRel);
    // About pi r^2 pixels inside the circle's image (r = radial(theta_max) f).
    const double area = kPi * m.radial(theta_max) * m.radial(theta_max) * m.fx * m.fy;
    EXPECT_NEAR(maps.valid_pixels / area, 1.0, 0.01);
}

TEST(Maps, SolidAngleBeyondHemisphere) {
    // An equidistant lens seeing 340 degrees: the quads still tile the sphere exactly.
    CameraModel m = CameraModel::make(ModelType::kFisheye, 640, 640, 95.0, 95.0, 319.5, 319.5);
    const double theta_max = 170.0 * kPi / 180;
    ASSERT_LT(m.radial(theta_max) * m.fx + 2, 319.5);
    MapOptions opt;
    opt.max_theta = theta_max;
    const DirectionMaps maps = compute_maps(m, opt);
    EXPECT_NEAR(maps.covered_solid_angle_sr / (2 * kPi * (1 - std::cos(theta_max))), 1.0,
                kFovSolidAngleRel);
}

TEST(Maps, QuadAreaMatchesJacobian) {
    // Within the 165-degree field, the exact quad area and the differential |d_x x d_y| at the
    // centre differ by the second-order term of the area element over one pixel: relative
    // (1/24) |d^2 log J| ~ 1e-4 at 150 px per radian.
    const CameraModel m = fisheye_165();
    MapOptions opt;
    opt.max_theta = 0.5 * 165.0 * kPi / 180;
    const DirectionMaps maps = compute_maps(m, opt);
    const Unprojector unproject(m);
    int checked = 0;
    for (int y = 50; y < 550; y += 37) {
        for (int x = 100; x < 700; x += 41) {
            if (maps.mask.at(x, y, 0) == 0) continue;
            const double h = 1e-3;
            const auto xp = unproject(Eigen::Vector2d(x + h, y)),
                       xm = unproject(Eigen::Vector2d(x - h, y));
            const auto yp = unproject(Eigen::Vector2d(x, y + h)),
                       ym = unproject(Eigen::Vector2d(x, y - h));
            const double jac = ((*xp - *xm) / (2 * h)).cross((*yp - *ym) / (2 * h)).norm();
            EXPECT_NEAR(maps.solid_angle.at(x, y, 0) / jac, 1.0, 1e-4) << x << "," << y;
            ++checked;
        }
    }
    EXPECT_GT(checked, 100);
}

TEST(Maps, DirectionsInDeviceFrame) {
    const CameraModel m = fisheye_165();
    const DirectionMaps maps = compute_maps(m, MapOptions{});
    auto dir = [&](int x, int y) {
        return Eigen::Vector3d(maps.directions.at(x, y, 0), maps.directions.at(x, y, 1),
                               maps.directions.at(x, y, 2));
    };
    // The principal point looks along +z (toward the viewer).
    EXPECT_GT(dir(401, 299).z(), 0.99999);
    // Right of centre in the raw image is the viewer's left (-x); above centre is up (+y).
    EXPECT_LT(dir(600, 299).x(), -0.5);
    EXPECT_GT(dir(401, 100).y(), 0.5);
    for (int y = 0; y < m.height; y += 13) {
        for (int x = 0; x < m.width; x += 13) {
            if (maps.mask.at(x, y, 0) > 0) {
                EXPECT_NEAR(dir(x, y).norm(), 1.0, 1e-6);
            } else {
                EXPECT_EQ(dir(x, y).norm(), 0.0);
                EXPECT_EQ(maps.solid_angle.at(x, y, 0), 0.0f);
            }
        }
    }
    // A rotation applied after the default turns every direction.
    MapOptions turned;
    turned.device_from_camera = parse_rotation("z=90") * default_device_from_camera();
    const DirectionMaps t = compute_maps(m, turned);
    EXPECT_NEAR(t.directions.at(600, 299, 1), maps.directions.at(600, 299, 0), 1e-6);
}

TEST(Maps, ImageCircleLimitsMask) {
    const CameraModel m = fisheye_165();
    MapOptions opt;
    opt.circle = {401.3, 298.7, 100.0};
    const DirectionMaps maps = compute_maps(m, opt);
    EXPECT_NEAR(static_cast<double>(maps.valid_pixels), kPi * 100 * 100, 2 * kPi * 100);
    EXPECT_EQ(maps.mask.at(401, 299 + 105, 0), 0.0f);
    EXPECT_EQ(maps.mask.at(401, 299 + 95, 0), 1.0f);
}

TEST(Maps, DownscaleSumsSolidAngleAndKeepsUnitDirections) {
    // A pinhole covering the whole frame: every block is fully valid, so the sum is preserved.
    CameraModel pin = CameraModel::make(ModelType::kPinhole, 640, 480, 500, 500, 319.5, 239.5);
    const DirectionMaps full = compute_maps(pin, MapOptions{});
    ASSERT_EQ(full.valid_pixels, 640 * 480);
    for (const Eigen::Vector2i& s : parse_sizes("160x120,100x75,7x5")) {
        const DirectionMaps small = downscale_maps(full, s.x(), s.y());
        EXPECT_NEAR(small.covered_solid_angle_sr, full.covered_solid_angle_sr,
                    1e-6 * full.covered_solid_angle_sr);
        for (int y = 0; y < s.y(); ++y) {
            for (int x = 0; x < s.x(); ++x) {
                const Eigen::Vector3d d(small.directions.at(x, y, 0), small.directions.at(x, y, 1),
                                        small.directions.at(x, y, 2));
                EXPECT_NEAR(d.norm(), 1.0, 1e-6);
            }
        }
    }
    // Fisheye: only edge blocks lose their minority of valid pixels.
    const CameraModel m = fisheye_165();
    MapOptions opt;
    opt.max_theta = 80.0 * kPi / 180;
    const DirectionMaps f = compute_maps(m, opt);
    const DirectionMaps q = downscale_maps(f, 200, 150);
    EXPECT_NEAR(q.covered_solid_angle_sr / f.covered_solid_angle_sr, 1.0, 0.01);
    EXPECT_THROW(downscale_maps(f, 801, 10), UsageError);
}

TEST(Maps, DeterministicForAnyThreadCount) {
    const CameraModel m = fisheye_165();
    parallel::set_thread_count(1);
    const DirectionMaps a = compute_maps(m, MapOptions{});
    const DirectionMaps da = downscale_maps(a, 200, 150);
    parallel::set_thread_count(0);
    const DirectionMaps b = compute_maps(m, MapOptions{});
    const DirectionMaps db = downscale_maps(b, 200, 150);
    EXPECT_EQ(a.directions.pixels, b.directions.pixels);
    EXPECT_EQ(a.solid_angle.pixels, b.solid_angle.pixels);
    EXPECT_EQ(a.covered_solid_angle_sr, b.covered_solid_angle_sr);
    EXPECT_EQ(da.directions.pixels, db.directions.pixels);
}

TEST(Maps, WriteAndReadBack) {
    const CameraModel m = fisheye_165();
    const DirectionMaps full = compute_maps(m, MapOptions{});
    const DirectionMaps small = downscale_maps(full, 100, 75);
    const std::string dir = testing::temp_dir("maps_write") + "/100x75";
    const auto paths = write_maps(dir, small);
    ASSERT_EQ(paths.size(), 3u);
    const image::Image d = image::read_image(paths[0]);
    const image::Image o = image::read_image(paths[1]);
    image::ReadOptions lin;
    lin.decode_srgb = false;
    const image::Image k = image::read_image(paths[2], lin);
    ASSERT_EQ(d.channels, 3);
    ASSERT_EQ(o.channels, 1);
    ASSERT_EQ(k.channels, 1);
    EXPECT_EQ(d.pixels, small.directions.pixels);  // float EXR: exact
    EXPECT_EQ(o.pixels, small.solid_angle.pixels);
    for (size_t i = 0; i < k.pixels.size(); ++i) EXPECT_EQ(k.pixels[i], small.mask.pixels[i]);
}

TEST(Maps, ParseSizes) {
    EXPECT_EQ(parse_sizes("64x40").size(), 1u);
    EXPECT_EQ(parse_sizes("64x40,32x20")[1], Eigen::Vector2i(32, 20));
    EXPECT_THROW(parse_sizes("64x"), UsageError);
    EXPECT_THROW(parse_sizes("64x40;32x20"), UsageError);
    EXPECT_THROW(parse_sizes("0x4"), UsageError);
    EXPECT_EQ(testing::error_of([] { parse_sizes("0x0"); }),
              "--downscale '0x0': width: 0 is outside [1, 16384]");
    EXPECT_THROW(parse_sizes("64x40,"), UsageError);
}

TEST(Maps, DetectsImageCircle) {
    GrayImage img;
    img.width = 400;
    img.height = 300;
    img.pixels.assign(400 * 300, 0);
    for (int y = 0; y < 300; ++y) {
        for (int x = 0; x < 400; ++x) {
            if (std::hypot(x - 200.0, y - 150.0) < 120)
                img.pixels[y * 400 + x] = 50 + (x * 7 + y * 3) % 150;
        }
    }
    const ImageCircle c = detect_image_circle(img, 200, 150);
    EXPECT_NEAR(c.radius_px, 120, 1.5);
    // Lit to the corners: no circle.
    std::fill(img.pixels.begin(), img.pixels.end(), 100);
    EXPECT_EQ(detect_image_circle(img, 200, 150).radius_px, 0.0);
}

}  // namespace
}  // namespace inlight::calib
