// Tests of render/compare.h's image comparison: the dE2000 map against the published pairs of
// Sharma, Wu and Dalal (2005) through a stated exposure, the relative-error map and the
// automatic exposure against their definitions.
#include "render/compare.h"

#include <gtest/gtest.h>

#include <cmath>

#include "image/color.h"
#include "image/sharma2005_testing.h"

namespace inlight::render {
namespace {

/// Linear sRGB of a CIELAB colour (D65), by the CIE inverse (CIE 15:2004, 8.2.1): f^-1(t) = t^3
/// above 6/29, 3 (6/29)^2 (t - 4/29) below; written here, not with the library's Lab code.
Eigen::Vector3d linear_srgb_from_lab(const double lab[3]) {
    auto finv = [](double t) {
        const double d = 6.0 / 29;
        return t > d ? t * t * t : 3 * d * d * (t - 4.0 / 29);
    };
    const double fy = (lab[0] + 16) / 116, fx = fy + lab[1] / 500, fz = fy - lab[2] / 200;
    const Eigen::Vector3d xyz(0.95047 * finv(fx), finv(fy), 1.08883 * finv(fz));
    return image::linear_srgb_from_xyz(xyz);
}

TEST(CompareImages, De2000MapMatchesSharmaPairsThroughTheExposure) {
    // Pixel i of the truth and of the test hold pair i's two colours divided by the exposure, so
    // the map (which multiplies by the exposure before CIELAB) must give the published dE00.
    // Tolerance: the table's 4-decimal rounding (5e-5) plus float32 pixel storage, which moves
    // L*, a*, b* by at most ~(500 / 3) 2^-24 ~ 1e-5 each: 1e-4.
    constexpr double kPublishedTol = 1e-4;
    constexpr double kExposure = 2.5;
    const int n = 34;
    image::Image truth(n, 1, 3), test(n, 1, 3);
    for (int i = 0; i < n; ++i) {
        const auto& p = image::testdata::kSharma[i];
        const Eigen::Vector3d a = linear_srgb_from_lab(p.lab1) / kExposure;
        const Eigen::Vector3d b = linear_srgb_from_lab(p.lab2) / kExposure;
        for (int c = 0; c < 3; ++c) {
            truth.at(i, 0, c) = static_cast<float>(a[c]);
            test.at(i, 0, c) = static_cast<float>(b[c]);
        }
    }
    const Comparison cmp = compare_images(truth, test, kExposure, CompareOptions{});
    ASSERT_EQ(cmp.de2000.width, n);
    ASSERT_EQ(cmp.de2000.channels, 1);
    double sum = 0, worst = 0;
    for (int i = 0; i < n; ++i) {
        const double want = image::testdata::kSharma[i].de2000;
        sum += cmp.de2000.at(i, 0, 0);
        worst = std::max<double>(worst, cmp.de2000.at(i, 0, 0));
        // Pairs 10 and 14 sit exactly on the hue-mean branch point (|h1 - h2| = 180 degrees),
        // where float32 storage picks the branch; color_test checks them in double.
        if (i + 1 == 10 || i + 1 == 14) continue;
        EXPECT_NEAR(cmp.de2000.at(i, 0, 0), want, kPublishedTol) << "pair " << i + 1;
    }
    // The summary metrics are the map's mean and maximum.
    EXPECT_NEAR(cmp.metrics.mean_de2000, sum / n, 1e-6);
    EXPECT_NEAR(cmp.metrics.max_de2000, worst, 1e-6);
}

TEST(CompareImages, RelativeErrorMapIsTheWorstChannelOverTheFlooredTruth) {
    // |test - truth| / max(|truth|, rel_floor), the maximum over R, G, B; values exact in float.
    CompareOptions opt;
    opt.rel_floor = 0.25;
    image::Image truth(3, 1, 3), test(3, 1, 3);
    const float t[3][3] = {{1, 2, 4}, {0.5f, 0.5f, 0.5f}, {0, 0.125f, 1}};
    const float s[3][3] = {{1.5f, 2, 3}, {0.5f, 0.25f, 0.625f}, {0.125f, 0.125f, 1}};
    for (int x = 0; x < 3; ++x) {
        for (int c = 0; c < 3; ++c) truth.at(x, 0, c) = t[x][c], test.at(x, 0, c) = s[x][c];
    }
    const Comparison cmp = compare_images(truth, test, 1.0, opt);
    // Pixel 0: 0.5 / 1, 0, 1 / 4 -> 0.5. Pixel 1: 0, 0.25 / 0.5, 0.125 / 0.5 -> 0.5.
    // Pixel 2: 0.125 / max(0, 0.25) = 0.5 (the floor), 0, 0 -> 0.5; with floor 1e-3: 125.
    EXPECT_EQ(cmp.rel_error.at(0, 0, 0), 0.5f);
    EXPECT_EQ(cmp.rel_error.at(1, 0, 0), 0.5f);
    EXPECT_EQ(cmp.rel_error.at(2, 0, 0), 0.5f);
    opt.rel_floor = 1e-3;
    EXPECT_NEAR(compare_images(truth, test, 1.0, opt).rel_error.at(2, 0, 0), 125.0, 1e-4);
    EXPECT_NEAR(cmp.metrics.max_rel, 0.5, 1e-7);
}

TEST(AutoExposure, MapsTheMeanRec709LuminanceToMiddleGrey) {
    // Y = 0.2126 R + 0.7152 G + 0.0722 B (ITU-R BT.709); exposure = 0.18 / mean Y.
    image::Image img(2, 1, 3);
    img.at(0, 0, 0) = 1;  // pure red: Y = 0.2126
    img.at(1, 0, 2) = 2;  // blue at 2: Y = 0.1444
    const double mean_y = (0.2126 + 2 * 0.0722) / 2;
    EXPECT_NEAR(auto_exposure(img), 0.18 / mean_y, 1e-15);
    // Green alone shows that the weights are not swapped.
    image::Image green(1, 1, 3);
    green.at(0, 0, 1) = 0.5f;
    EXPECT_NEAR(auto_exposure(green), 0.18 / (0.5 * 0.7152), 1e-15);
    EXPECT_EQ(auto_exposure(image::Image(4, 4, 3)), 1.0);  // black: exposure 1, not infinity
}

}  // namespace
}  // namespace inlight::render
