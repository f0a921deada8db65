#include "image/metrics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/error.h"
#include "core/parallel.h"
#include "image/color.h"
#include "testing/testing.h"

namespace inlight::image {
namespace {

// Sums of a few hundred doubles: rounding far below this.
constexpr double kSumTol = 1e-12;
// Per-pixel maps are stored as float (24-bit significand).
constexpr double kFloatRel = 1e-6;

Image constant(int w, int h, int c, float v, ColorSpace cs = ColorSpace::kLinearSrgb) {
    Image img(w, h, c, cs);
    for (float& x : img.pixels) x = v;
    return img;
}

Image random_image(int w, int h, int c, unsigned seed) {
    return inlight::testing::random_image<Image>(w, h, c, 0.0f, 2.0f, seed, ColorSpace::kLinearSrgb);
}

using inlight::testing::error_of;

TEST(Compare, IdenticalImages) {
    const Image a = random_image(20, 10, 3, 1);
    const Metrics m = compare(a, a);
    EXPECT_EQ(m.mae, 0.0);
    EXPECT_EQ(m.rmse, 0.0);
    EXPECT_TRUE(std::isinf(m.psnr_db) && m.psnr_db > 0);
    EXPECT_EQ(m.max_rel, 0.0);
    EXPECT_EQ(m.mean_de2000, 0.0);
}

TEST(Compare, KnownMaeRmsePsnr) {
    // ref = 1 everywhere (peak 1); test = ref + 0.1 on even pixels, ref - 0.3 on odd ones:
    // MAE = 0.2, RMSE = sqrt((0.01 + 0.09) / 2) = sqrt(0.05), PSNR = -10 log10(0.05) dB.
    const Image ref = constant(4, 4, 3, 1.0f, ColorSpace::kData);
    Image test = ref;
    for (size_t p = 0; p < test.pixel_count(); ++p) {
        for (int k = 0; k < 3; ++k) test.pixels[3 * p + k] += (p % 2 == 0) ? 0.1f : -0.3f;
    }
    const Metrics m = compare(test, ref);
    // The offsets pass through float: 1 + 0.1f is 1.10000002384, so allow float rounding.
    constexpr double kF = 1e-7;
    EXPECT_NEAR(m.mae, 0.2, kF);
    EXPECT_NEAR(m.rmse, std::sqrt(0.05), kF);
    EXPECT_NEAR(m.psnr_db, -10.0 * std::log10(0.05), 1e-5);  // 13.0103 dB
    EXPECT_NEAR(m.mean_rel, 0.2, kF);
    EXPECT_NEAR(m.max_rel, 0.3, kF);
    EXPECT_FALSE(supports_delta_e(ref));  // data: no dE
    EXPECT_EQ(m.mean_de76, 0.0);
}

TEST(Compare, RelativeErrorUsesTheFloor) {
    Image ref = constant(2, 1, 1, 0.0f, ColorSpace::kData);
    ref.pixels[1] = 2.0f;
    Image test = ref;
    test.pixels[0] = 0.01f;  // 0.01 / max(0, 1e-3) = 10
    test.pixels[1] = 3.0f;   // 1 / 2 = 0.5
    const Metrics m = compare(test, ref);
    EXPECT_NEAR(m.max_rel, 10.0, 1e-6);
    EXPECT_NEAR(m.mean_rel, 5.25, 1e-6);
    CompareOptions opt;
    opt.rel_floor = 0.1;
    EXPECT_NEAR(compare(test, ref, opt).max_rel, 0.5, 1e-6);  // 0.01 / 0.1 = 0.1 < 0.5
}

TEST(Compare, DeltaEOfAGreyLightnessChange) {
    // Neutral greys differ only in L* = 116 Y^(1/3) - 16, so dE76 = |dL| and
    // dE00 = |dL| / SL (Sharma et al. eq. 18) with SL at the mean L*.
    const double y_ref = 0.18, y_test = 0.25;
    const Image ref = constant(8, 8, 3, float(y_ref));
    const Image test = constant(8, 8, 3, float(y_test));
    for (double exposure : {1.0, 2.0}) {
        CompareOptions opt;
        opt.exposure = exposure;
        const double l1 = 116 * std::cbrt(double(float(y_ref)) * exposure) - 16;
        const double l2 = 116 * std::cbrt(double(float(y_test)) * exposure) - 16;
        const double lbar = 0.5 * (l1 + l2), d2 = (lbar - 50) * (lbar - 50);
        const double sl = 1 + 0.015 * d2 / std::sqrt(20 + d2);
        const Metrics m = compare(test, ref, opt);
        EXPECT_NEAR(m.mean_de76, l2 - l1, 1e-9) << "exposure " << exposure;
        EXPECT_NEAR(m.mean_de2000, (l2 - l1) / sl, 1e-9);
        EXPECT_NEAR(m.max_de2000, (l2 - l1) / sl, 1e-9);
    }
}

TEST(Compare, RejectsMismatchesNamingBothValues) {
    const Image a = constant(64, 32, 3, 0.5f);
    std::string msg = error_of([&] { compare(a, constant(32, 32, 3, 0.5f)); });
    EXPECT_NE(msg.find("64x32"), std::string::npos) << msg;
    EXPECT_NE(msg.find("32x32"), std::string::npos) << msg;
    msg = error_of([&] { compare(a, constant(64, 32, 4, 0.5f)); });
    EXPECT_NE(msg.find("channel counts differ: test 3, reference 4"), std::string::npos) << msg;
    msg = error_of([&] { compare(a, constant(64, 32, 3, 0.5f, ColorSpace::kAcescg)); });
    EXPECT_NE(msg.find("linear_srgb"), std::string::npos) << msg;
    EXPECT_NE(msg.find("acescg"), std::string::npos) << msg;
    EXPECT_THROW(relative_error_map(a, constant(32, 32, 3, 0.5f)), Error);
    EXPECT_THROW(delta_e2000_map(a, constant(64, 32, 3, 0.5f, ColorSpace::kData)), Error);
}

TEST(Compare, SameResultForAnyThreadCount) {
    const Image ref = random_image(300, 170, 3, 2);
    const Image test = random_image(300, 170, 3, 3);
    parallel::set_thread_count(1);
    const Metrics one = compare(test, ref);
    const Image map1 = delta_e2000_map(test, ref);
    parallel::set_thread_count(2);
    const Metrics two = compare(test, ref);
    const Image map2 = delta_e2000_map(test, ref);
    parallel::set_thread_count(0);
    EXPECT_EQ(one.mae, two.mae);
    EXPECT_EQ(one.rmse, two.rmse);
    EXPECT_EQ(one.mean_rel, two.mean_rel);
    EXPECT_EQ(one.mean_de76, two.mean_de76);
    EXPECT_EQ(one.mean_de2000, two.mean_de2000);
    EXPECT_EQ(map1.pixels, map2.pixels);
}

TEST(RelativeErrorMap, MaxOverColourChannelsIgnoringAlpha) {
    Image ref = constant(3, 1, 4, 1.0f);
    Image test = ref;
    test.at(0, 0, 1) = 1.5f;  // 0.5
    test.at(1, 0, 0) = 0.8f;  // 0.2
    test.at(1, 0, 2) = 1.3f;  // 0.3 (the max of pixel 1)
    test.at(2, 0, 3) = 9.0f;  // alpha only: ignored
    const Image map = relative_error_map(test, ref);
    ASSERT_EQ(map.channels, 1);
    EXPECT_EQ(map.color_space, ColorSpace::kData);
    EXPECT_NEAR(map.pixels[0], 0.5, kFloatRel);
    EXPECT_NEAR(map.pixels[1], 0.3, kFloatRel);
    EXPECT_EQ(map.pixels[2], 0.0f);
}

TEST(DeltaE2000Map, MatchesThePerPixelFormulaAndTheMean) {
    const Image ref = random_image(16, 8, 3, 4);
    const Image test = random_image(16, 8, 3, 5);
    const Image map = delta_e2000_map(test, ref, 0.5);
    ASSERT_EQ(map.channels, 1);
    double sum = 0;
    for (size_t p = 0; p < ref.pixel_count(); ++p) {
        const Eigen::Vector3d a(test.pixels[3 * p], test.pixels[3 * p + 1], test.pixels[3 * p + 2]);
        const Eigen::Vector3d b(ref.pixels[3 * p], ref.pixels[3 * p + 1], ref.pixels[3 * p + 2]);
        const double de = delta_e2000(lab_from_linear_srgb(0.5 * a), lab_from_linear_srgb(0.5 * b));
        EXPECT_NEAR(map.pixels[p], de, kFloatRel * std::max(1.0, de));
        sum += de;
    }
    CompareOptions opt;
    opt.exposure = 0.5;
    EXPECT_NEAR(compare(test, ref, opt).mean_de2000, sum / ref.pixel_count(), kSumTol * 100);
    EXPECT_THROW(delta_e2000_map(constant(2, 2, 1, 0.f), constant(2, 2, 1, 0.f)), Error);
}

TEST(HeatMap, ViridisEndpointsMidpointAndMonotoneLightness) {
    Image ramp(101, 1, 1, ColorSpace::kData);
    for (int x = 0; x < 101; ++x) ramp.pixels[x] = 2.0f * x / 100.0f;  // 0 .. max_value = 2
    const Image map = heat_map(ramp, 2.0);
    ASSERT_EQ(map.channels, 3);
    EXPECT_EQ(map.color_space, ColorSpace::kLinearSrgb);
    // Encoded back to sRGB, the ends and the middle are viridis' published 8-bit colours
    // #440154, #21918c, #fde725 (float rounding only).
    auto code = [&](int x, int k) { return srgb_encode(map.at(x, 0, k)) * 255.0; };
    const int expect[3][4] = {
        {0, 0x44, 0x01, 0x54}, {50, 0x21, 0x91, 0x8c}, {100, 0xfd, 0xe7, 0x25}};
    for (const auto& e : expect) {
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(code(e[0], k), e[k + 1], 1e-3) << "x=" << e[0];
    }
    // Viridis rises monotonically in lightness.
    double last_l = -1;
    for (int x = 0; x < 101; ++x) {
        const double l = lab_from_linear_srgb(
            Eigen::Vector3d(map.at(x, 0, 0), map.at(x, 0, 1), map.at(x, 0, 2)))[0];
        EXPECT_GT(l, last_l) << "x=" << x;
        last_l = l;
    }
}

TEST(HeatMap, ClampsAndRejectsBadInput) {
    Image v(3, 1, 1, ColorSpace::kData);
    v.pixels = {-5.0f, 50.0f, std::nanf("")};
    const Image map = heat_map(v, 1.0);
    Image ends(2, 1, 1, ColorSpace::kData);
    ends.pixels = {0.0f, 1.0f};
    const Image ref = heat_map(ends, 1.0);
    for (int k = 0; k < 3; ++k) {
        EXPECT_EQ(map.at(0, 0, k), ref.at(0, 0, k));
        EXPECT_EQ(map.at(1, 0, k), ref.at(1, 0, k));
        EXPECT_EQ(map.at(2, 0, k), ref.at(1, 0, k));  // NaN shows as the top colour
    }
    EXPECT_THROW(heat_map(constant(2, 2, 3, 0.f), 1.0), Error);
    EXPECT_THROW(heat_map(v, 0.0), Error);
}

}  // namespace
}  // namespace inlight::image
