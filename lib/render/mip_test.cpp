// Tests of the mip chain (render/mip.h) against brute force: levels minified 16x and 64x
// against the mean of their level-0 blocks, non-power-of-two and 1 x 1 textures against a
// fine-grid area average, a pure-noise normal map against the analytic mean resultant length,
// and the level of detail against the GL formula.
#include "render/mip.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/conventions.h"
#include "image/color.h"
#include "render/material.h"

namespace inlight::render {
namespace {

/// Float storage of a mean of <= 4096 values in [0, 1], accumulated in double: one float
/// rounding (6e-8 relative), with margin.
constexpr double kFloatTol = 1e-6;

image::Image random_image(int w, int h, unsigned seed) {
    image::Image img(w, h, 3);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    for (float& v : img.pixels) v = u(rng);
    return img;
}

Eigen::Vector3d texel(const MipAtlas& m, int level, int i, int j) {
    const MipRect& r = m.levels[level];
    return {m.atlas.at(r.x + i, r.y + j, 0), m.atlas.at(r.x + i, r.y + j, 1),
            m.atlas.at(r.x + i, r.y + j, 2)};
}

TEST(Mip, SizesHalveWithFloorDownToOne) {
    const auto s = mip_sizes(7, 5);
    ASSERT_EQ(s.size(), 3u);
    EXPECT_EQ(s[1], Eigen::Vector2i(3, 2));
    EXPECT_EQ(s[2], Eigen::Vector2i(1, 1));
    EXPECT_EQ(mip_sizes(1, 1).size(), 1u);
    EXPECT_EQ(mip_sizes(256, 4).size(), 9u);  // 256 -> 1 in 8 halvings, the short side stays 1
}

TEST(Mip, LevelsMinified16xAnd64xAreTheMeansOfTheirBlocks) {
    const image::Image src = random_image(128, 64, 1);
    const MipAtlas m = build_mip_atlas(src, TextureKind::kNormalMap, false, MipFilter::kBox);
    ASSERT_EQ(m.levels.size(), 8u);
    EXPECT_EQ(m.atlas.width, 128 + 64);
    EXPECT_EQ(m.atlas.height, 64);
    for (const int level : {4, 6}) {
        const int block = 1 << level;
        for (int j = 0; j < 64 / block; ++j) {
            for (int i = 0; i < 128 / block; ++i) {
                Eigen::Vector3d mean = Eigen::Vector3d::Zero();
                for (int y = j * block; y < (j + 1) * block; ++y)
                    for (int x = i * block; x < (i + 1) * block; ++x)
                        for (int c = 0; c < 3; ++c) mean[c] += src.at(x, y, c);
                mean /= block * block;
                EXPECT_LT((texel(m, level, i, j) - mean).cwiseAbs().maxCoeff(), kFloatTol)
                    << "level " << level << " texel " << i << "," << j;
            }
        }
    }
    // Level 0 is the source, and its lookup is render::sample_texture's, bit for bit.
    const Eigen::Vector2d uv(0.3712, -1.77);
    EXPECT_EQ(sample_level(m, 0, uv), sample_texture(src, uv));
}

TEST(Mip, NonPowerOfTwoLevelsAreAreaAveragesOnAFineGrid) {
    // 7 x 5 -> 3 x 2 -> 1 x 1: footprints 7/3 and 5/2 texels wide, multiples of 1/60.
    const image::Image src = random_image(7, 5, 2);
    const MipAtlas m = build_mip_atlas(src, TextureKind::kNormalMap, false, MipFilter::kBox);
    ASSERT_EQ(m.levels.size(), 3u);
    constexpr int kSub = 60;  // sub-cells per texel side: every footprint edge lies on the grid
    for (size_t k = 1; k < m.levels.size(); ++k) {
        const MipRect& r = m.levels[k];
        for (int j = 0; j < r.height; ++j) {
            for (int i = 0; i < r.width; ++i) {
                Eigen::Vector3d sum = Eigen::Vector3d::Zero();
                int count = 0;
                for (int sy = 0; sy < 5 * kSub; ++sy) {
                    for (int sx = 0; sx < 7 * kSub; ++sx) {
                        const double cx = (sx + 0.5) / kSub * r.width / 7.0;
                        const double cy = (sy + 0.5) / kSub * r.height / 5.0;
                        if (static_cast<int>(cx) != i || static_cast<int>(cy) != j) continue;
                        for (int c = 0; c < 3; ++c) sum[c] += src.at(sx / kSub, sy / kSub, c);
                        ++count;
                    }
                }
                EXPECT_LT((texel(m, static_cast<int>(k), i, j) - sum / count).cwiseAbs().maxCoeff(),
                          kFloatTol)
                    << "level " << k << " texel " << i << "," << j;
            }
        }
    }
}

TEST(Mip, BilinearLevelsAverageTheDrawnTextureOverTheFootprint) {
    // The texture as drawn (render::sample_texture) averaged on a fine grid over each
    // footprint: 24 x 24 samples per level-0 texel, midpoint rule on a piecewise bilinear
    // function whose kinks lie on the grid, so exact up to the products' O(h^2) term per cell
    // (h = 1/24: ~1e-4 of the texel contrast; 2e-4 with margin).
    constexpr double kMidpointTol = 2e-4;
    for (const Eigen::Vector2i& size : {Eigen::Vector2i(64, 32), Eigen::Vector2i(7, 5)}) {
        const image::Image src = random_image(size.x(), size.y(), 5);
        const MipAtlas m = build_mip_atlas(src, TextureKind::kNormalMap, false, MipFilter::kBilinear);
        constexpr int kSub = 24;
        for (const int level : {1, static_cast<int>(m.levels.size()) - 1}) {
            const MipRect& r = m.levels[level];
            const int i = r.width / 2, j = r.height / 2;  // one texel per level suffices
            const double x0 = static_cast<double>(i) * size.x() / r.width;
            const double x1 = static_cast<double>(i + 1) * size.x() / r.width;
            const double y0 = static_cast<double>(j) * size.y() / r.height;
            const double y1 = static_cast<double>(j + 1) * size.y() / r.height;
            const int nx = static_cast<int>(std::lround((x1 - x0) * kSub));
            const int ny = static_cast<int>(std::lround((y1 - y0) * kSub));
            Eigen::Vector3d sum = Eigen::Vector3d::Zero();
            for (int sy = 0; sy < ny; ++sy)
                for (int sx = 0; sx < nx; ++sx)
                    sum += sample_texture(src, {(x0 + (sx + 0.5) / kSub) / size.x(),
                                                (y0 + (sy + 0.5) / kSub) / size.y()});
            EXPECT_LT((texel(m, level, i, j) - sum / (nx * ny)).cwiseAbs().maxCoeff(), kMidpointTol)
                << size.transpose() << " level " << level;
        }
    }
}

TEST(Mip, OneTexelTextureIsItsOwnChainAtEveryLevelOfDetail) {
    image::Image src(1, 1, 3);
    src.at(0, 0, 0) = 0.25f, src.at(0, 0, 1) = 0.5f, src.at(0, 0, 2) = 0.75f;
    const MipAtlas m = build_mip_atlas(src, TextureKind::kColor, true);
    ASSERT_EQ(m.levels.size(), 1u);
    for (const double lod : {-3.0, 0.0, 2.5, 40.0}) {
        EXPECT_EQ(sample_trilinear(m, {0.37, 5.2}, lod), Eigen::Vector3d(0.25, 0.5, 0.75));
    }
}

TEST(Mip, ColourLevelsAreStoredAsTheSrgbCodeOfTheLinearMean) {
    // Two texels, black and white: the linear mean 0.5 is sRGB code 188 (0.7354 x 255 =
    // 187.5..), not the code mean 127.5 that GL's generated mipmaps of sRGB bytes would give.
    image::Image src(2, 1, 3);
    for (int c = 0; c < 3; ++c) src.at(1, 0, c) = 1.0f;
    const MipAtlas m = build_mip_atlas(src, TextureKind::kColor, true);
    const double code = std::round(image::srgb_encode(0.5f) * 255.0);
    EXPECT_EQ(code, 188.0);
    EXPECT_FLOAT_EQ(static_cast<float>(texel(m, 1, 0, 0)[0]),
                    image::srgb_decode(static_cast<float>(code / 255.0)));
}

/// A normal map of normals drawn from `draw`, stored as rgb = (n + 1) / 2.
template <typename Draw>
image::Image normal_noise(int side, Draw draw) {
    image::Image img(side, side, 3);
    for (int y = 0; y < side; ++y) {
        for (int x = 0; x < side; ++x) {
            const Eigen::Vector3d n = draw();
            for (int c = 0; c < 3; ++c) img.at(x, y, c) = static_cast<float>(0.5 * (n[c] + 1));
        }
    }
    return img;
}

double top_length(const MipAtlas& m) {
    return (2 * texel(m, static_cast<int>(m.levels.size()) - 1, 0, 0) - Eigen::Vector3d::Ones())
        .norm();
}

TEST(Mip, PureNoiseNormalMapKeepsTheMeanResultantLength) {
    constexpr int kSide = 256;
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    // Uniform on the upper hemisphere: mean (0, 0, 1/2), so the 1 x 1 level has length 1/2.
    const image::Image hemi = normal_noise(kSide, [&] {
        const double z = u(rng), phi = 2 * kPi * u(rng), s = std::sqrt(1 - z * z);
        return Eigen::Vector3d(s * std::cos(phi), s * std::sin(phi), z);
    });
    // Statistical error of a mean of 65536 normals: sd 0.29 (z) and 0.58 (x, y) over 256, so
    // the length is off by ~0.0011 (z) + 0.0023^2 terms; 5 sigma of z plus float storage.
    constexpr double kStatTol = 0.006;
    EXPECT_NEAR(top_length(build_mip_atlas(hemi, TextureKind::kNormalMap, false)), 0.5, kStatTol);
    // Stored in 8 bits each level's vector moves by at most half a code per channel:
    // sqrt(3) x 1/255 in 2 rgb - 1 units.
    EXPECT_NEAR(top_length(build_mip_atlas(hemi, TextureKind::kNormalMap, true)), 0.5,
                kStatTol + std::sqrt(3.0) / 255);

    // vMF of concentration 10 around +z: mean resultant length coth(10) - 1/10, and the
    // Banerjee inverse gives back kappa within its known error (~4% at r = 0.9).
    constexpr double kKappa = 10;
    const image::Image vmf = normal_noise(kSide, [&] {
        const double w = 1 + std::log(u(rng) + (1 - u(rng)) * std::exp(-2 * kKappa)) / kKappa;
        const double phi = 2 * kPi * u(rng), s = std::sqrt(std::max(0.0, 1 - w * w));
        return Eigen::Vector3d(s * std::cos(phi), s * std::sin(phi), w);
    });
    const double r = top_length(build_mip_atlas(vmf, TextureKind::kNormalMap, false));
    // sd of w for kappa = 10 is ~0.1: 5 sigma over 256 is 0.002.
    EXPECT_NEAR(r, 1 / std::tanh(kKappa) - 1 / kKappa, 0.002);
    EXPECT_NEAR(1 / vmf_inv_kappa(r), kKappa, 0.05 * kKappa);
}

TEST(Mip, LevelOfDetailIsTheGlFormula) {
    const Eigen::Vector2i size(256, 128);
    // 4 level-0 texels per pixel along x: lod 2.
    EXPECT_DOUBLE_EQ(mip_lod({4.0 / 256, 0}, {0, 1.0 / 128}, size), 2.0);
    // rho is the longer of the two derivative vectors in texels: (3, 4) -> 5.
    EXPECT_DOUBLE_EQ(mip_lod({0, 0}, {3.0 / 256, 4.0 / 128}, size), std::log2(5.0));
    // 64x minified: lod 6.
    EXPECT_DOUBLE_EQ(mip_lod({64.0 / 256, 0}, {0, 64.0 / 128}, size), 6.0);
    EXPECT_EQ(mip_lod({0, 0}, {0, 0}, size), -std::numeric_limits<double>::infinity());
}

TEST(Mip, BoxMatchedLodHasThePixelBoxVariance) {
    // L = log2(rho^2 / 3 + 2 / 3) / 2: rho = 1 (no minification) gives level 0; rho = 2 gives
    // 4^L = 2, L = 1/2; a level-L lookup's variance 4^L / 4 equals rho^2 / 12 + 1 / 6 at rho = 8.
    EXPECT_NEAR(box_matched_lod(0.0), 0.0, 1e-15);  // log2 of 1 from 1/3 + 2/3: one rounding
    EXPECT_NEAR(box_matched_lod(1.0), 0.5, 1e-15);
    const double l = box_matched_lod(3.0);
    EXPECT_NEAR(std::exp2(2 * l) / 4, 64.0 / 12 + 1.0 / 6, 1e-12);
    // No derivative (GL lod -inf): below 0, so level 0 after the clamp.
    EXPECT_LT(box_matched_lod(-std::numeric_limits<double>::infinity()), 0.0);
}

TEST(Mip, TrilinearMixesTheTwoNearestLevels) {
    const MipAtlas m = build_mip_atlas(random_image(64, 32, 4), TextureKind::kNormalMap, false);
    const Eigen::Vector2d uv(0.41, 0.83);
    const Eigen::Vector3d expect = 0.75 * sample_level(m, 2, uv) + 0.25 * sample_level(m, 3, uv);
    EXPECT_LT((sample_trilinear(m, uv, 2.25) - expect).norm(), 1e-12);  // same doubles, reordered
    EXPECT_EQ(sample_trilinear(m, uv, -1.0), sample_level(m, 0, uv));
    EXPECT_EQ(sample_trilinear(m, uv, 99.0), sample_level(m, 6, uv));
}

TEST(Mip, VmfBandFactors) {
    EXPECT_EQ(vmf_inv_kappa(1.0), 0.0);
    EXPECT_EQ(vmf_band_factor(2, 0.0), 1.0);  // an unfiltered normal leaves the shading alone
    EXPECT_EQ(vmf_band_factor(0, vmf_inv_kappa(0.0)), 1.0);
    EXPECT_EQ(vmf_band_factor(1, vmf_inv_kappa(0.0)), 0.0);
    // Band 1 of a vMF is coth(kappa) - 1/kappa exactly; exp(-1/kappa) is its large-kappa form:
    // at kappa = 50 they differ by O(1/kappa^2) = 4e-4.
    const double k = 50;
    EXPECT_NEAR(vmf_band_factor(1, 1 / k), 1 / std::tanh(k) - 1 / k, 1 / (k * k));
}

}  // namespace
}  // namespace inlight::render
