#include "btf/interp_run.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "btf/compressed.h"
#include "btf/pca_run.h"
#include "btf/synthetic.h"
#include "core/conventions.h"
#include "image/color.h"
#include "testing/testing.h"

namespace inlight::btf {
namespace {

/// float32 sums of <= 32 products of values <= ~1 against the same sums in double: a few
/// hundred float ulps (6e-8) at most, so 1e-5 absolute bounds them with margin.
constexpr double kFloatSumTol = 1e-5;

double max_abs_diff(const image::Image& a, const image::Image& b) {
    EXPECT_EQ(a.pixels.size(), b.pixels.size());
    double m = 0;
    for (size_t i = 0; i < a.pixels.size(); ++i) m = std::max(m, std::abs(double(a.pixels[i]) - b.pixels[i]));
    return m;
}

double rmse(const image::Image& a, const image::Image& b) {
    double s = 0;
    for (size_t i = 0; i < a.pixels.size(); ++i) s += std::pow(double(a.pixels[i]) - b.pixels[i], 2);
    return std::sqrt(s / double(a.pixels.size()));
}

/// The weighted sum done by hand from read_image (or a decoder).
template <typename Decode>
image::Image sum_by_hand(const BtfShape& s, const std::vector<ImageTerm>& terms, Decode decode) {
    image::Image out(s.width, s.height, 3);
    std::vector<double> acc(out.pixels.size(), 0.0);
    for (const ImageTerm& t : terms) {
        const image::Image img = decode(t.light, t.view);
        for (size_t i = 0; i < acc.size(); ++i) acc[i] += img.pixels[i] * t.weight[int(i % 3)];
    }
    for (size_t i = 0; i < acc.size(); ++i) out.pixels[i] = float(acc[i]);
    return out;
}

std::vector<ImageTerm> random_terms(const BtfShape& s, int n, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-0.5, 1.0);
    std::vector<ImageTerm> t;
    for (int i = 0; i < n; ++i)
        t.push_back({int(rng() % unsigned(s.n_lights())), int(rng() % unsigned(s.n_views())),
                     Eigen::Vector3d(u(rng), u(rng), u(rng))});
    return t;
}

TEST(CombineImages, CompressedFoldsWeightsIntoComponentsAndEqualsTheDecodedSum) {
    AnalyticBtfOptions ao;
    ao.width = 12;
    ao.height = 9;
    ao.rank = 4;
    ao.lights = {{0, 0}, {15, 0}, {15, 120}, {30, 60}, {30, 240}, {45, 0}, {60, 90}, {75, 300}};
    ao.views = {{0, 0}, {30, 0}, {30, 120}, {45, 180}, {60, 270}};
    const AnalyticBtf truth(ao);
    PcaRunOptions po;
    po.output = testing::temp_dir("combine_compressed");
    po.pca.view_group_size = 2;  // 3 groups: terms touch several
    po.pca.components = 3;
    po.encoding = ComponentEncoding::kExrFloat;
    compress_to_folder(truth, po, 0);
    const auto c = CompressedBtf::open(po.output);
    const auto terms = random_terms(truth.shape(), 25, 3);
    EXPECT_LT(max_abs_diff(c->combine(terms), sum_by_hand(truth.shape(), terms, [&](int l, int v) {
                  return c->read_image(l, v);
              })),
              kFloatSumTol);
    for (int64_t sent : {int64_t(0), int64_t(2), int64_t(5)})
        EXPECT_LT(max_abs_diff(c->combine_streamed(terms, sent), sum_by_hand(truth.shape(), terms, [&](int l, int v) {
                      return c->read_image_streamed(l, v, sent);
                  })),
                  kFloatSumTol)
            << sent;
    // The default (raw) path is the same sum.
    EXPECT_LT(max_abs_diff(truth.combine(terms), sum_by_hand(truth.shape(), terms, [&](int l, int v) {
                  return truth.read_image(l, v);
              })),
              kFloatSumTol);
}

TEST(InterpolateBtf, ExactOnTheGridAndCloserThanTheNearestPairOffIt) {
    AnalyticBtfOptions ao;
    ao.width = 6;
    ao.height = 5;
    ao.rank = 3;  // Lambert, highlight, sheen: smooth in the directions
    const AnalyticBtf btf(ao);
    const auto& dome = ubo2003_dome();
    for (InterpScheme scheme : {InterpScheme::kThesis, InterpScheme::kDelaunay}) {
        const auto li = make_interpolator(scheme, dome), vi = make_interpolator(scheme, dome);
        // A measured pair: one term, the measured image.
        const auto on = interpolation_terms(*li, *vi, dome[20].vector(), dome[44].vector());
        ASSERT_EQ(on.size(), 1u);
        EXPECT_LT(max_abs_diff(btf.combine(on), btf.read_image(20, 44)), 1e-6);
        // Off the grid (theta <= 70, inside both schemes' triangles): interpolation beats the
        // nearest measured pair on average over 40 pairs (it is first-order exact).
        std::mt19937 rng(9);
        std::uniform_real_distribution<double> u(0, 1);
        auto random_dir = [&] {
            const double z = std::cos(70 * kPi / 180) + (1 - std::cos(70 * kPi / 180)) * u(rng), p = 2 * kPi * u(rng);
            const double r = std::sqrt(1 - z * z);
            return Eigen::Vector3d(r * std::cos(p), r * std::sin(p), z);
        };
        double err_interp = 0, err_nearest = 0;
        for (int i = 0; i < 40; ++i) {
            const Eigen::Vector3d l = random_dir(), v = random_dir();
            const image::Image truth = btf.render(l, v);
            err_interp += rmse(btf.combine(interpolation_terms(*li, *vi, l, v)), truth);
            int nl = 0, nv = 0;
            for (size_t k = 0; k < dome.size(); ++k) {
                if (dome[k].vector().dot(l) > dome[size_t(nl)].vector().dot(l)) nl = int(k);
                if (dome[k].vector().dot(v) > dome[size_t(nv)].vector().dot(v)) nv = int(k);
            }
            err_nearest += rmse(btf.read_image(nl, nv), truth);
        }
        EXPECT_LT(err_interp, 0.8 * err_nearest) << to_string(scheme);
    }
}

TEST(ImageErrors, ZeroForEqualImagesAndClosedFormForAnOffset) {
    image::Image t(4, 3, 3), x(4, 3, 3);
    for (size_t i = 0; i < t.pixels.size(); ++i) t.pixels[i] = x.pixels[i] = 0.25f;
    const ImageErrors z = image_errors(x, t);
    EXPECT_EQ(z.rmse, 0.0);
    EXPECT_EQ(z.delta_e2000_mean, 0.0);
    for (float& p : x.pixels) p = 0.5f;
    const ImageErrors e = image_errors(x, t);
    EXPECT_NEAR(e.rmse, 0.25, 1e-7);  // float inputs, double sums
    EXPECT_NEAR(e.rel_rmse, 1.0, 1e-6);
    EXPECT_NEAR(e.mean_rel_diff, 1.0, 1e-6);
    // Grey 0.25 and 0.5: a and b are 0, L* differs by L*(0.5) - L*(0.25), averaged over L, a, b.
    const double dl = image::lab_from_linear_srgb(Eigen::Vector3d::Constant(0.5))[0] -
                      image::lab_from_linear_srgb(Eigen::Vector3d::Constant(0.25))[0];
    EXPECT_NEAR(e.mae_lab, dl / 3, 1e-6);
    EXPECT_NEAR(e.rmse_rgb8, 255.0 * (image::srgb_encode(0.5f) - image::srgb_encode(0.25f)), 1e-4);
    EXPECT_NE(testing::error_of([&] { image_errors(image::Image(2, 2, 3), t); }).find("against a truth"),
              std::string::npos);
}

}  // namespace
}  // namespace inlight::btf
