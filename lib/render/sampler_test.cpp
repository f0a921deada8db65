// Tests of render/sampler.h: Sobol dimension 1 against its closed form (Pascal matrix mod 2, by
// Lucas' theorem), the (0,m,2)-net property of each pixel's points and of aligned pixel blocks
// (what Owen scrambling and the Morton digit permutation must preserve), uniformity and
// independence of dimensions, and the randomised-QMC error on a smooth integrand.
#include "render/sampler.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace inlight::render {
namespace {

/// True when every elementary interval of volume 2^-m (all 2^a x 2^(m-a) cell shapes) holds
/// exactly one of the 2^m points.
bool is_02_net(const std::vector<Eigen::Vector2d>& pts, int m) {
    if (pts.size() != (size_t{1} << m)) return false;
    for (int a = 0; a <= m; ++a) {
        const int nx = 1 << a, ny = 1 << (m - a);
        std::vector<int> count(static_cast<size_t>(nx) * ny, 0);
        for (const auto& p : pts) {
            const int cx = static_cast<int>(p[0] * nx), cy = static_cast<int>(p[1] * ny);
            if (++count[static_cast<size_t>(cy) * nx + cx] > 1) return false;
        }
    }
    return true;
}

TEST(Sampler, EachPixelsPointsAreA02Net) {
    // m even and odd (the odd case ends in a binary digit), one and four scramble groups: the
    // points of one group of one pixel in one dimension are a (0,m,2)-net.
    for (int groups : {1, 4}) {
        for (int m : {4, 5, 8}) {
            const Sampler s(SamplerKind::kSobol, 7, 37, 21, groups << m, groups);
            for (int dim : {0, 1, 6, 13}) {
                for (int g = 0; g < groups; ++g) {
                    std::vector<Eigen::Vector2d> pts;
                    for (int k = 0; k < (1 << m); ++k)
                        pts.push_back(s.stream(19, 11, k * groups + g).get2d(dim));
                    EXPECT_TRUE(is_02_net(pts, m))
                        << "groups " << groups << " m " << m << " dim " << dim << " group " << g;
                }
            }
        }
    }
}

TEST(Sampler, PowerOfFourPrefixOfALargerRunIsANet) {
    // Progressive rendering uses prefixes: the first 16 of 256 points are a (0,4,2)-net.
    const Sampler s(SamplerKind::kSobol, 3, 8, 8, 256, 1);
    std::vector<Eigen::Vector2d> pts;
    for (int k = 0; k < 16; ++k) pts.push_back(s.stream(5, 2, k).get2d(3));
    EXPECT_TRUE(is_02_net(pts, 4));
}

TEST(Sampler, AlignedPixelBlocksTogetherFormALargerNet) {
    // Morton order: a 2x2 (4x4) aligned pixel block's 2^m points each are a (0, m+2 (m+4), 2)-net.
    for (int m : {3, 4}) {
        const Sampler s(SamplerKind::kSobol, 11, 64, 64, 1 << m, 1);
        for (int block : {2, 4}) {
            std::vector<Eigen::Vector2d> pts;
            for (int y = 8; y < 8 + block; ++y) {
                for (int x = 12; x < 12 + block; ++x) {
                    for (int k = 0; k < (1 << m); ++k) pts.push_back(s.stream(x, y, k).get2d(5));
                }
            }
            EXPECT_TRUE(is_02_net(pts, m + (block == 2 ? 2 : 4))) << "m " << m << " block " << block;
        }
    }
}

/// Pearson chi-square statistic of counts against a uniform expectation.
double chi2_uniform(const std::vector<double>& counts) {
    double total = 0;
    for (double c : counts) total += c;
    const double e = total / static_cast<double>(counts.size());
    double x = 0;
    for (double c : counts) x += (c - e) * (c - e) / e;
    return x;
}

TEST(Sampler, DimensionsAreUniformAndIndependent) {
    // Over all pixels of a 64x64 image x 4 samples: each 1D dimension fills 16 bins evenly and
    // pairs of dimensions (including the pixel dimension against a bounce dimension) fill an
    // 8x8 grid evenly. A false alarm needs p < 1e-4 (a fixed seed: the test is deterministic);
    // a dimension reused or correlated would concentrate the pairs on a curve (p ~ 0).
    constexpr double kMinP = 1e-4;
    const Sampler s(SamplerKind::kSobol, 5, 64, 64, 16, 4);
    const int pairs[][2] = {{0, 1}, {1, 5}, {2, 3}, {4, 12}};
    for (const auto& pr : pairs) {
        std::vector<double> hist1(16, 0), hist2(64, 0);
        for (int y = 0; y < 64; ++y) {
            for (int x = 0; x < 64; ++x) {
                for (int k = 0; k < 4; ++k) {
                    Sampler::Stream u = s.stream(x, y, k);
                    const double a = u.get1d(pr[0]), b = u.get2d(pr[1])[1];
                    ASSERT_TRUE(a >= 0 && a < 1 && b >= 0 && b < 1);
                    hist1[static_cast<size_t>(a * 16)] += 1;
                    hist2[static_cast<size_t>(a * 8) * 8 + static_cast<size_t>(b * 8)] += 1;
                }
            }
        }
        EXPECT_GT(chi2_survival(chi2_uniform(hist1), 15), kMinP) << pr[0];
        EXPECT_GT(chi2_survival(chi2_uniform(hist2), 63), kMinP) << pr[0] << "," << pr[1];
    }
}

TEST(Sampler, SmoothIntegrandConvergesFasterThanMonteCarlo) {
    // f(u, v) = exp(u) * cos(v): integral (e - 1) sin(1). Independent samples have RMS error
    // sigma / sqrt(n); Owen-scrambled nets have O(n^-1.5) for smooth f (Owen 1997), ~60x smaller
    // at n = 256. Over 256 pixels the RMS error must be below 1/8 of sigma / sqrt(n) (the
    // independent sampler must not: it sits at ~1 within the 256-pixel noise of ~5%).
    const double exact = (std::exp(1.0) - 1.0) * std::sin(1.0);
    const double sigma = std::sqrt((std::exp(2.0) - 1.0) / 2.0 * (0.5 + std::sin(2.0) / 4.0) -
                                   exact * exact);
    constexpr int kSpp = 256;
    for (SamplerKind kind : {SamplerKind::kSobol, SamplerKind::kIndependent}) {
        const Sampler s(kind, 9, 16, 16, kSpp, 1);
        double mse = 0;
        for (int y = 0; y < 16; ++y) {
            for (int x = 0; x < 16; ++x) {
                double sum = 0;
                for (int k = 0; k < kSpp; ++k) {
                    const Eigen::Vector2d p = s.stream(x, y, k).get2d(PathDims::bounce(1, 1));
                    sum += std::exp(p[0]) * std::cos(p[1]);
                }
                const double e = sum / kSpp - exact;
                mse += e * e / 256.0;
            }
        }
        const double ratio = std::sqrt(mse) / (sigma / std::sqrt(kSpp));
        if (kind == SamplerKind::kSobol) {
            EXPECT_LT(ratio, 1.0 / 8.0);
        } else {
            EXPECT_GT(ratio, 0.7);  // 256 pixels: 1 +- 0.05; 0.7 is 6 sigma
        }
    }
}

TEST(Sampler, IndependentSamplerIsThePcgStreamOfItsSample) {
    const Sampler s(SamplerKind::kIndependent, 4, 10, 10, 8, 4);
    EXPECT_EQ(s.groups(), 1);
    Sampler::Stream u = s.stream(3, 2, 5);
    Rng rng(4, 2 * 10 + 3, 5);
    EXPECT_EQ(u.get2d(0), rng.uniform2());
    EXPECT_EQ(u.get1d(9), rng.uniform());
}

TEST(Sampler, NamesRoundTrip) {
    EXPECT_EQ(sampler_from_string("sobol"), SamplerKind::kSobol);
    EXPECT_EQ(to_string(sampler_from_string("independent")), "independent");
    EXPECT_THROW(sampler_from_string("halton"), std::exception);
}

}  // namespace
}  // namespace inlight::render
