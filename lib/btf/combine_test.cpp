// Environment shading of a compressed BTF (btf/lighting.h shading_terms through
// CompressedBtf::combine) against the raw BTF's.
#include <cmath>

#include <gtest/gtest.h>

#include "btf/compressed.h"
#include "btf/lighting.h"
#include "btf/pca_run.h"
#include "btf/synthetic.h"
#include "core/conventions.h"
#include "testing/testing.h"

namespace inlight::btf {
namespace {

struct Shaded {
    double max_diff = 0;   // largest |compressed - raw| over pixels and channels
    double bound = 0;      // sum_k |W_k| / E x the largest reconstruction error of one image value
    double recon_max = 0;  // the largest reconstruction error of one image value
};

Shaded shade_both(int components) {
    AnalyticBtfOptions ao;
    ao.width = 10;
    ao.height = 8;
    ao.rank = 4;
    ao.views = {{0, 0}, {30, 0}, {45, 180}};
    const AnalyticBtf raw(ao);
    PcaRunOptions po;
    po.output = testing::temp_dir("shade_compressed_" + std::to_string(components));
    po.pca.view_group_size = 3;
    po.pca.components = components;
    po.encoding = ComponentEncoding::kExrFloat;
    compress_to_folder(raw, po, 0);
    const auto c = CompressedBtf::open(po.output);
    const auto env = testing::random_image<image::Image>(32, 16, 3, 0.0f, 4.0f, 5u, image::ColorSpace::kLinearSrgb);
    const DomeLighting lighting = integrate_dome_cells(env, raw.shape().lights);
    const double irradiance = kPi;
    Shaded s;
    for (int v = 0; v < raw.shape().n_views(); ++v)
        for (int l = 0; l < raw.shape().n_lights(); ++l) {
            const image::Image a = raw.read_image(l, v), b = c->read_image(l, v);
            for (size_t i = 0; i < a.pixels.size(); ++i)
                s.recon_max = std::max(s.recon_max, std::abs(double(a.pixels[i]) - b.pixels[i]));
        }
    double wsum = 0;
    for (const auto& w : lighting.weight) wsum += w.cwiseAbs().maxCoeff() / irradiance;
    // Float32 rounding of the sums of ~81 terms of |value| <= 1 in double: 1e-6 x wsum.
    s.bound = wsum * s.recon_max + 1e-6 * wsum;
    for (int v = 0; v < raw.shape().n_views(); ++v) {
        const auto terms = shading_terms(lighting, {v}, {1.0}, irradiance);
        const image::Image a = raw.combine(terms), b = c->combine(terms);
        for (size_t i = 0; i < a.pixels.size(); ++i)
            s.max_diff = std::max(s.max_diff, std::abs(double(a.pixels[i]) - b.pixels[i]));
    }
    return s;
}

TEST(ShadeCompressed, FullRankEqualsTheRawShadingWithinTheReconstructionBound) {
    // Rank 4 with C = 8 (clamped to the rank): float components reproduce every value to
    // float32 rounding, and the shading is a linear map of the values.
    const Shaded full = shade_both(8);
    EXPECT_LT(full.recon_max, 1e-5);  // float32 storage of a rank-4 model of values <= 1
    EXPECT_LE(full.max_diff, full.bound);
    // A truncated model (C = 1) misses what the bound of the full model allows: the check
    // above can fail.
    const Shaded cut = shade_both(1);
    EXPECT_GT(cut.max_diff, 100 * full.bound);
}

TEST(ShadeCompressed, ShadingTermsWeightEachLightByItsCellOverTheIrradiance) {
    DomeLighting lighting;
    lighting.weight = {Eigen::Vector3d(1, 2, 3), Eigen::Vector3d(4, 5, 6)};
    const auto t = shading_terms(lighting, {3, 5}, {0.25, 0.75}, 2.0);
    ASSERT_EQ(t.size(), 4u);
    EXPECT_EQ(t[1].light, 1);
    EXPECT_EQ(t[1].view, 3);
    EXPECT_EQ(t[1].weight, Eigen::Vector3d(4, 5, 6) * 0.125);
    EXPECT_EQ(t[2].view, 5);
    EXPECT_EQ(t[2].weight, Eigen::Vector3d(1, 2, 3) * 0.375);
}

}  // namespace
}  // namespace inlight::btf
