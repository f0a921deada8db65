// Normal maps from height fields against analytic normals.
#include "image/normal_map.h"

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cmath>
#include <functional>

#include "core/error.h"

namespace inlight::image {
namespace {

// Float storage of pixels: unit-vector components carry ~6e-8 relative rounding.
constexpr double kFloatTol = 1e-6;

Image height_field(int w, int h, const std::function<double(double, double)>& f) {
    Image img(w, h, 1, ColorSpace::kData);
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) img.at(x, y, 0) = static_cast<float>(f(x, y));
    }
    return img;
}

Eigen::Vector3d analytic_normal(double dh_dx, double dh_drow) {
    return Eigen::Vector3d(-dh_dx, dh_drow, 1.0).normalized();
}

Eigen::Vector3d at(const Image& n, int x, int y) {
    return {n.at(x, y, 0), n.at(x, y, 1), n.at(x, y, 2)};
}

TEST(NormalMap, PlaneIsExactAndSignsFollowTheTangentFrame) {
    // h rises 0.3 texel per column (to the right) and 0.2 per row (downward, i.e. toward the
    // bottom of the screen): the surface faces left (-x) and up (+y, toward row 0).
    const Image h = height_field(16, 12, [](double x, double y) { return 0.3 * x + 0.2 * y; });
    const Image n = normal_map_from_height(h, Border::kClamp);
    const Eigen::Vector3d want = analytic_normal(0.3, 0.2);
    EXPECT_LT(want.x(), 0);
    EXPECT_GT(want.y(), 0);
    for (int y = 0; y < 12; ++y) {
        for (int x = 0; x < 16; ++x) EXPECT_NEAR((at(n, x, y) - want).norm(), 0, kFloatTol);
    }
}

TEST(NormalMap, SinusoidMatchesTheCentralDifferenceSlope) {
    // h = A sin(2 pi x / P) cos(2 pi y / Q), tiling the image (P, Q divide its size). Central
    // differences give the slope times sinc(2 pi / P) exactly (sin(a + d) - sin(a - d) =
    // 2 cos a sin d); the same holds along rows. So the normals must equal the analytic ones
    // of the slope-damped field to float precision, and differ from the undamped ones by about
    // the (2 pi / P)^2 / 6 damping, which the second check bounds.
    const int w = 64, hgt = 48;
    const double A = 2.0, P = 16, Q = 12;
    const double kx = 2 * M_PI / P, ky = 2 * M_PI / Q;
    const Image h = height_field(w, hgt, [&](double x, double y) {
        return A * std::sin(kx * x) * std::cos(ky * y);
    });
    const Image n = normal_map_from_height(h, Border::kWrap);
    const double sx = std::sin(kx) / kx, sy = std::sin(ky) / ky;
    double worst_undamped = 0;
    for (int y = 0; y < hgt; ++y) {
        for (int x = 0; x < w; ++x) {
            const double gx = A * kx * std::cos(kx * x) * std::cos(ky * y);
            const double gy = -A * ky * std::sin(kx * x) * std::sin(ky * y);
            EXPECT_NEAR((at(n, x, y) - analytic_normal(gx * sx, gy * sy)).norm(), 0, kFloatTol)
                << x << "," << y;
            worst_undamped = std::max(worst_undamped, (at(n, x, y) - analytic_normal(gx, gy)).norm());
        }
    }
    // The damping moves the slope by at most (1 - sinc) |g|; the normal moves less than that.
    const double max_slope = A * std::max(kx, ky);
    const double damping_bound = (1 - std::min(sx, sy)) * max_slope;
    EXPECT_LE(worst_undamped, damping_bound);
    EXPECT_GT(worst_undamped, 0.1 * damping_bound);  // the effect is real, not zero
}

TEST(NormalMap, WrapMakesTheMapTileable) {
    // A periodic field: the normals at the left and right borders must be those of the
    // continuing field, so column 0 equals what the formula gives with x = -1 wrapped.
    const Image h = height_field(8, 8, [](double x, double) { return std::sin(2 * M_PI * x / 8); });
    const Image n = normal_map_from_height(h, Border::kWrap);
    const double g = (std::sin(2 * M_PI / 8) - std::sin(-2 * M_PI / 8)) / 2;
    EXPECT_NEAR((at(n, 0, 3) - analytic_normal(g, 0)).norm(), 0, kFloatTol);
}

TEST(NormalMap, RejectsNonFiniteHeights) {
    Image h(4, 4, 1, ColorSpace::kData);
    h.at(1, 2, 0) = NAN;
    EXPECT_THROW(normal_map_from_height(h), Error);
    EXPECT_THROW(height_from_albedo(h, 1.0), Error);
    EXPECT_THROW(height_from_albedo(Image(4, 4, 3), -1.0), Error);
}

TEST(HeightFromAlbedo, SpansTheReliefAndFollowsLuminance) {
    Image a(4, 1, 3);
    const float y[] = {0.1f, 0.4f, 0.2f, 0.9f};
    for (int x = 0; x < 4; ++x) {
        for (int c = 0; c < 3; ++c) a.at(x, 0, c) = y[x];
    }
    const Image h = height_from_albedo(a, 2.0, 0);
    EXPECT_NEAR(h.at(0, 0, 0), 0.0, kFloatTol);
    EXPECT_NEAR(h.at(3, 0, 0), 2.0, kFloatTol);
    EXPECT_NEAR(h.at(1, 0, 0), 2.0 * 0.3 / 0.8, kFloatTol);
    // A uniform texture has no relief.
    const Image flat = height_from_albedo(Image(3, 3, 3), 2.0, 1);
    for (float v : flat.pixels) EXPECT_EQ(v, 0.0f);
}

TEST(ResizeBox, AveragesBlocksAndKeepsTheMean) {
    Image img(4, 2, 1, ColorSpace::kData);
    for (int i = 0; i < 8; ++i) img.pixels[i] = static_cast<float>(i);
    const Image half = resize_box(img, 2, 1);
    EXPECT_NEAR(half.at(0, 0, 0), (0 + 1 + 4 + 5) / 4.0, kFloatTol);
    EXPECT_NEAR(half.at(1, 0, 0), (2 + 3 + 6 + 7) / 4.0, kFloatTol);
    const Image up = resize_box(img, 8, 4);
    EXPECT_EQ(up.at(7, 3, 0), 7.0f);
    EXPECT_EQ(up.at(0, 0, 0), 0.0f);
}

}  // namespace
}  // namespace inlight::image
