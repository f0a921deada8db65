#include "calib/response.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/conventions.h"
#include "core/error.h"
#include "testing/testing.h"

namespace inlight::calib {
namespace {

/// A known camera: an S-curve over a gamma, different per channel.
/// code = round(255 * S(min(X, 1)^(1 / gamma))), S(t) = t - a sin(2 pi t) / (2 pi), a = 0.5.
constexpr double kSCurve = 0.5;
const double kGamma[3] = {2.2, 2.0, 2.4};
const double kChannelScale[3] = {1.0, 0.8, 0.6};
const std::vector<double> kExposures = {1.0 / 1000, 1.0 / 250, 1.0 / 60, 1.0 / 15};

double s_curve(double t) { return t - kSCurve * std::sin(2 * kPi * t) / (2 * kPi); }

/// X (exposure, saturating at 1) whose ideal code is `code` (real-valued), by bisection.
double exposure_of_code(double code, double gamma) {
    const double target = std::clamp(code / 255.0, 0.0, 1.0);
    double lo = 0, hi = 1;
    for (int i = 0; i < 80; ++i) {
        const double mid = 0.5 * (lo + hi);
        (s_curve(mid) < target ? lo : hi) = mid;
    }
    return std::pow(0.5 * (lo + hi), gamma);
}

int code_of_exposure(double x, double gamma) {
    return static_cast<int>(std::lround(255 * s_curve(std::pow(std::min(x, 1.0), 1 / gamma))));
}

struct Scene {
    std::vector<image::Image> bracket;
    image::Image radiance;  // truth
};

Scene make_scene(int w, int h, uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(0, 1);
    Scene s;
    s.radiance = image::Image(w, h, 3, image::ColorSpace::kRawCamera);
    for (size_t i = 0; i < s.radiance.pixel_count(); ++i) {
        const double e = std::pow(10.0, 2.7 * u(rng));  // 1 .. 500, log-uniform
        for (int c = 0; c < 3; ++c)
            s.radiance.pixels[i * 3 + c] = static_cast<float>(e * kChannelScale[c]);
    }
    for (double dt : kExposures) {
        image::Image img(w, h, 3, image::ColorSpace::kData);
        for (size_t i = 0; i < img.pixels.size(); ++i) {
            img.pixels[i] =
                static_cast<float>(code_of_exposure(s.radiance.pixels[i] * dt, kGamma[i % 3]));
        }
        s.bracket.push_back(std::move(img));
    }
    return s;
}

TEST(Response, RecoversKnownCurveUpToConstant) {
    const Scene scene = make_scene(200, 150, 7);
    const ResponseFit fit = recover_response(scene.bracket, kExposures);
    ASSERT_EQ(fit.curve.channels(), 3);
    // Codes 16..240: seen with weight in at least two exposures for most pixels. The ends carry
    // little weight and are shaped by the smoothness term alone.
    const int lo = 16, hi = 240;
    for (int c = 0; c < 3; ++c) {
        const auto& g = fit.curve.log_exposure[c];
        EXPECT_DOUBLE_EQ(g[kReferenceCode], 0.0);
        double mean = 0;
        for (int z = lo; z <= hi; ++z) mean += g[z] - std::log(exposure_of_code(z, kGamma[c]));
        mean /= (hi - lo + 1);
        for (int z = lo; z <= hi; ++z) {
            const double truth = std::log(exposure_of_code(z, kGamma[c]));
            // An 8-bit code stands for every exposure of its bin: g(z) can be anywhere in
            // [ln X(z - 0.5), ln X(z + 0.5)], so half the bin width, plus 0.01 for the
            // smoothness term's pull.
            const double half_bin = 0.5 * (std::log(exposure_of_code(z + 0.5, kGamma[c])) -
                                           std::log(exposure_of_code(z - 0.5, kGamma[c])));
            EXPECT_NEAR(g[z] - mean, truth, half_bin + 0.01) << "channel " << c << " code " << z;
        }
        EXPECT_LT(fit.fit_rms_log[c], 0.05);
    }
}

TEST(Response, MergesToTrueRadiance) {
    const Scene scene = make_scene(200, 150, 11);
    const ResponseFit fit = recover_response(scene.bracket, kExposures);
    const MergeResult m = merge_radiance(scene.bracket, kExposures, fit.curve);
    EXPECT_EQ(m.saturated_pixels, 0);  // the shortest exposure clips nothing (X <= 0.5)
    for (int c = 0; c < 3; ++c) {
        // The merged radiance equals the truth up to one scale per channel (g's constant).
        std::vector<double> log_ratio;
        for (size_t i = 0; i < m.radiance.pixel_count(); ++i) {
            log_ratio.push_back(
                std::log(m.radiance.pixels[i * 3 + c] / scene.radiance.pixels[i * 3 + c]));
        }
        double mean = 0;
        for (double r : log_ratio) mean += r;
        mean /= log_ratio.size();
        std::vector<double> err;
        int over = 0;
        for (size_t i = 0; i < log_ratio.size(); ++i) {
            const double e = std::abs(log_ratio[i] - mean);
            err.push_back(e);
            // Each exposure j contributes g(Z_j) - ln dt_j, off from ln E by at most half its
            // code's bin (quantisation) plus the curve's own error (half a bin + 0.01, as in
            // RecoversKnownCurveUpToConstant); the merge is their hat-weighted mean.
            double num = 0, den = 0;
            for (const image::Image& b : scene.bracket) {
                const int z = static_cast<int>(b.pixels[i * 3 + c]);
                const double half_bin = 0.5 * (std::log(exposure_of_code(z + 0.5, kGamma[c])) -
                                               std::log(exposure_of_code(z - 0.5, kGamma[c])));
                num += hat_weight(z) * (2 * half_bin + 0.01);
                den += hat_weight(z);
            }
            if (e > num / den) ++over;
        }
        EXPECT_EQ(over, 0) << "pixels beyond their quantisation bound, channel " << c;
        std::sort(err.begin(), err.end());
        EXPECT_LT(err[err.size() / 2], 0.01) << "median, channel " << c;
        RecordProperty(str("median_log_error_c", c), std::to_string(err[err.size() / 2]));
    }
}

TEST(Response, FrameMarksSaturationAndBoundsHiddenLight) {
    ResponseCurve curve;
    curve.channel_names = {"y"};
    curve.log_exposure.resize(1);
    for (int z = 0; z < kCodes; ++z) curve.log_exposure[0][z] = std::log((z + 1) / 129.0);
    image::Image frame(4, 1, 1, image::ColorSpace::kData);
    frame.pixels = {0, 128, 255, 255};
    image::Image omega(4, 1, 1, image::ColorSpace::kData);
    omega.pixels = {0.1f, 0.2f, 0.3f, 0.4f};
    const double dt = 0.5;
    const FrameRadiance f = radiance_from_frame(frame, curve, dt, &omega);
    EXPECT_EQ(f.saturated_pixels, 2);
    EXPECT_DOUBLE_EQ(f.saturated_fraction, 0.5);
    EXPECT_NEAR(f.radiance.pixels[1], 1.0 / dt, 1e-6);
    const double l255 = (256 / 129.0) / dt;
    EXPECT_NEAR(f.clipped_light_lower_bound[0], l255 * (0.3 + 0.4), 1e-6);
    EXPECT_NEAR(f.unclipped_light[0], (1 / 129.0) / dt * 0.1 + (129 / 129.0) / dt * 0.2, 1e-6);
    // A mask leaves pixels out of everything.
    image::Image mask(4, 1, 1, image::ColorSpace::kData);
    mask.pixels = {1, 1, 1, 0};
    const FrameRadiance fm = radiance_from_frame(frame, curve, dt, &omega, &mask);
    EXPECT_EQ(fm.saturated_pixels, 1);
    EXPECT_NEAR(fm.saturated_fraction, 1.0 / 3, 1e-12);
    EXPECT_EQ(fm.radiance.pixels[3], 0.0f);
}

TEST(Response, RejectsBadInput) {
    const Scene scene = make_scene(20, 10, 3);
    EXPECT_THROW(recover_response({scene.bracket[0]}, {0.1}), Error);
    EXPECT_THROW(recover_response(scene.bracket, {0.1, 0.2}), Error);
    EXPECT_THROW(recover_response(scene.bracket, {0.1, 0.1, 0.1, 0.1}), Error);
    image::Image bad = scene.bracket[0];
    bad.pixels[0] = 300;
    EXPECT_THROW(recover_response({bad, scene.bracket[1]}, {0.1, 0.2}), Error);
}

TEST(Response, FileRoundTrip) {
    const Scene scene = make_scene(100, 80, 5);
    const ResponseFit fit = recover_response(scene.bracket, kExposures);
    const std::string path = testing::temp_dir("response_roundtrip") + "/response.json";
    write_response(path, fit, 50, kExposures, {"a.png", "b.png", "c.png", "d.png"});
    const ResponseCurve back = read_response(path);
    ASSERT_EQ(back.channels(), 3);
    for (int c = 0; c < 3; ++c) {
        for (int z = 0; z < kCodes; ++z)
            EXPECT_DOUBLE_EQ(back.log_exposure[c][z], fit.curve.log_exposure[c][z]);
    }
    EXPECT_EQ(back.channel_names, (std::vector<std::string>{"r", "g", "b"}));
}

}  // namespace
}  // namespace inlight::calib
