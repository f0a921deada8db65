#include "btf/pca.h"

#include <gtest/gtest.h>

#include <Eigen/QR>
#include <cmath>
#include <fstream>
#include <numeric>
#include <random>

#include "btf/synthetic.h"
#include "core/parallel.h"
#include "testing/testing.h"

namespace inlight::btf {
namespace {

/// Energies are sums of squares of float32 data: each sample carries a relative rounding of
/// 2^-24, and `total - captured` cancels, so energies agree to ~1e-6 of the total energy.
constexpr double kEnergyTol = 1e-6;
/// Reconstructed values are float32 sums of at most a few dozen products of magnitude <= 1.
constexpr double kValueTol = 1e-5;

const PcaMethod kMethods[] = {PcaMethod::kGram, PcaMethod::kRandomized, PcaMethod::kFullSvd};

/// Columns orthonormal and orthogonal to the all-ones vector (so they have zero mean).
Eigen::MatrixXd random_orthonormal(int rows, int cols, std::mt19937_64& rng, bool zero_mean) {
    std::normal_distribution<double> normal;
    Eigen::MatrixXd x(rows, cols);
    for (Eigen::Index i = 0; i < x.size(); ++i) x.data()[i] = normal(rng);
    if (zero_mean) x.rowwise() -= x.colwise().mean();
    Eigen::HouseholderQR<Eigen::MatrixXd> qr(x);
    return qr.householderQ() * Eigen::MatrixXd::Identity(rows, cols);
}

/// A = m 1^T + U diag(sigma) V^T with V's columns of zero mean: the centred matrix's singular
/// values are exactly sigma and its row means are m.
struct Spectrum {
    Eigen::MatrixXf a;
    Eigen::VectorXd mean;
    std::vector<double> sigma;
    /// sum_{i >= c} sigma_i^2: the optimal residual of c components (Eckart-Young).
    double optimal_residual(int c) const {
        double s = 0;
        for (size_t i = static_cast<size_t>(c); i < sigma.size(); ++i) s += sigma[i] * sigma[i];
        return s;
    }
};

Spectrum make_spectrum(int p, int n, std::vector<double> sigma, uint64_t seed = 7) {
    std::mt19937_64 rng(seed);
    const int r = static_cast<int>(sigma.size());
    const Eigen::MatrixXd u = random_orthonormal(p, r, rng, false);
    const Eigen::MatrixXd v = random_orthonormal(n, r, rng, true);
    Spectrum s;
    s.sigma = std::move(sigma);
    s.mean = Eigen::VectorXd::LinSpaced(p, 0.2, 0.6);
    Eigen::MatrixXd a = u * Eigen::Map<const Eigen::VectorXd>(s.sigma.data(), r).asDiagonal() * v.transpose();
    a.colwise() += s.mean;
    s.a = a.cast<float>();
    return s;
}

std::vector<double> geometric(int r, double first, double ratio) {
    std::vector<double> s;
    for (int i = 0; i < r; ++i) s.push_back(first * std::pow(ratio, i));
    return s;
}

PcaOptions options(PcaMethod m, int components) {
    PcaOptions o;
    o.method = m;
    o.components = components;
    return o;
}

double max_abs(const Eigen::MatrixXf& x, const Eigen::MatrixXf& y) {
    return (x - y).cwiseAbs().maxCoeff();
}

// Every method, on both shapes (short side = columns, short side = pixels), finds the optimal
// residual of each C on a matrix of known spectrum, and the mean.
TEST(FitGroup, EveryMethodReachesTheKnownSpectrum) {
    for (auto [p, n] : {std::pair{300, 120}, std::pair{60, 400}}) {
        const Spectrum s = make_spectrum(p, n, geometric(20, 10.0, 0.6));
        for (PcaMethod m : kMethods) {
            SCOPED_TRACE(to_string(m) + " " + std::to_string(p) + "x" + std::to_string(n));
            Eigen::MatrixXf a = s.a;
            const GroupPca g = fit_group(a, {0}, options(m, 8), 1);
            ASSERT_EQ(g.components(), 8);
            EXPECT_EQ(g.method, m);
            EXPECT_LT((g.mean.cast<double>() - s.mean).cwiseAbs().maxCoeff(), kValueTol);
            const double total = s.optimal_residual(0);
            EXPECT_NEAR(g.total_energy, total, kEnergyTol * total);
            for (int c = 0; c <= 8; ++c)
                EXPECT_NEAR(g.residual_energy[c], s.optimal_residual(c), kEnergyTol * total) << c;
            // V orthonormal; reconstruction equals the residual it claims
            const Eigen::MatrixXf vtv = g.weights.transpose() * g.weights;
            EXPECT_LT(max_abs(vtv, Eigen::MatrixXf::Identity(8, 8)), kValueTol);
            const double err = (g.reconstruct(8) - s.a).cast<double>().squaredNorm();
            EXPECT_NEAR(err, s.optimal_residual(8), kEnergyTol * total);
        }
    }
}

// The randomized method finds its subspace with single-precision products (the range finder)
// and projects onto it in double. A sun-like first component 30,000x the next, over a spectrum
// falling to 0.09 of those, on sizes that are no multiple of the kernels' strips and panels:
// the residual after each c >= 1 components (0.1-2.8) must be the full SVD's of the same float
// data within 1e-6: the residual is total - captured at a total of 9e8, whose ulp in double is
// 1.2e-7, so a few ulps (measured: one).
TEST(FitGroup, RandomizedKeepsTheSmallComponentsBesideASun) {
    std::vector<double> sigma = {3.0e4};
    for (double x : geometric(12, 1.0, 0.8)) sigma.push_back(x);
    const Spectrum s = make_spectrum(4133, 277, sigma, 11);
    const int c = 8;
    Eigen::MatrixXf a = s.a;
    const GroupPca g = fit_group(a, {0}, options(PcaMethod::kRandomized, c), 1);
    a = s.a;
    const GroupPca full = fit_group(a, {0}, options(PcaMethod::kFullSvd, c), 1);
    ASSERT_EQ(g.components(), c);
    for (int i = 1; i <= c; ++i)
        EXPECT_NEAR(g.residual_energy[size_t(i)], full.residual_energy[size_t(i)], 1e-6)
            << i << " components; optimum of the exact data " << s.optimal_residual(i);
}

TEST(FitGroup, AutoPicksGramUpToTheLimitThenRandomized) {
    const Spectrum s = make_spectrum(200, 90, geometric(10, 1.0, 0.5));
    PcaOptions o = options(PcaMethod::kAuto, 4);
    o.gram_max_side = 90;
    Eigen::MatrixXf a = s.a;
    EXPECT_EQ(fit_group(a, {0}, o, 1).method, PcaMethod::kGram);
    o.gram_max_side = 89;
    a = s.a;
    EXPECT_EQ(fit_group(a, {0}, o, 1).method, PcaMethod::kRandomized);
}

// The analytic BTF of rank 4: mean-centring keeps the rank <= 4, so 4 components reproduce
// every image; the Gram path sees only float rounding beyond that.
TEST(FitGroup, LowRankBtfIsReproducedByItsRank) {
    AnalyticBtfOptions bo;
    bo.width = 16;
    bo.height = 16;
    bo.rank = 4;
    const AnalyticBtf btf(bo);
    for (std::vector<int> views : {std::vector<int>{40}, std::vector<int>{0, 1, 2}}) {
        Eigen::MatrixXf a, original;
        btf.read_group(views, original);
        a = original;
        const GroupPca g = fit_group(a, views, options(PcaMethod::kAuto, 6), 1);
        EXPECT_LT(g.residual_energy[4], 1e-10 * g.total_energy);  // float rounding only
        EXPECT_LT(max_abs(g.reconstruct(4), original), kValueTol);
    }
}

TEST(FitGroup, ConstantDataGivesZeroComponentsAndNoNaN) {
    for (PcaMethod m : kMethods) {
        SCOPED_TRACE(to_string(m));
        Eigen::MatrixXf a = Eigen::MatrixXf::Constant(50, 30, 0.37f);
        const GroupPca g = fit_group(a, {0}, options(m, 4), 1);
        EXPECT_EQ(g.total_energy, 0.0);
        for (double r : g.residual_energy) EXPECT_EQ(r, 0.0);
        EXPECT_TRUE(g.basis.allFinite() && g.weights.allFinite());
        EXPECT_EQ(g.basis.cwiseAbs().maxCoeff(), 0.0f);
        EXPECT_LT(max_abs(g.reconstruct(4), Eigen::MatrixXf::Constant(50, 30, 0.37f)), 1e-7);
    }
}

// More components than the rank (3) and than the short side allows: C is clamped to the short
// side, the extra components are (numerically) zero and finite, the fit is exact.
TEST(FitGroup, MoreComponentsThanRankOrSide) {
    for (auto [p, n] : {std::pair{40, 12}, std::pair{12, 40}}) {
        const Spectrum s = make_spectrum(p, n, {2.0, 1.0, 0.5});
        for (PcaMethod m : kMethods) {
            SCOPED_TRACE(to_string(m) + " " + std::to_string(p) + "x" + std::to_string(n));
            Eigen::MatrixXf a = s.a;
            const GroupPca g = fit_group(a, {0}, options(m, 64), 1);
            EXPECT_EQ(g.components(), 12);
            EXPECT_TRUE(g.basis.allFinite() && g.weights.allFinite());
            EXPECT_LT(g.residual_energy[3], kEnergyTol * g.total_energy);
            for (int c = 3; c < 12; ++c)
                EXPECT_LT(g.basis.col(c).norm(), 1e-3 * g.basis.col(0).norm()) << c;
            EXPECT_LT(max_abs(g.reconstruct(12), s.a), kValueTol);
        }
    }
}

// The budget keeps the fewest components that meet it: with sigma_i = 0.5^i the residual after
// c components is known, and a budget between those of 4 and 5 components must give 5.
TEST(FitGroup, ErrorBudgetKeepsTheFewestComponentsThatMeetIt) {
    const Spectrum s = make_spectrum(120, 80, geometric(16, 1.0, 0.5));
    const double samples = 120.0 * 80.0;
    const double between = std::sqrt(0.5 * (s.optimal_residual(4) + s.optimal_residual(5)) / samples);
    for (PcaMethod m : kMethods) {
        SCOPED_TRACE(to_string(m));
        PcaOptions o = options(m, 12);
        o.max_rmse = between;
        Eigen::MatrixXf a = s.a;
        GroupPca g = fit_group(a, {0}, o, 1);
        EXPECT_EQ(g.components(), 5);
        EXPECT_LE(g.rmse(5), between);
        o.max_rmse = 0;  // unreachable: all 12
        a = s.a;
        EXPECT_EQ(fit_group(a, {0}, o, 1).components(), 12);
        o.max_rmse = 10;  // the mean alone meets it
        a = s.a;
        g = fit_group(a, {0}, o, 1);
        EXPECT_EQ(g.components(), 0);
        EXPECT_LT((g.reconstruct(0).col(3).cast<double>() - s.mean).cwiseAbs().maxCoeff(), kValueTol);
    }
}

TEST(FitGroup, NonFiniteDataIsAnError) {
    Eigen::MatrixXf a = Eigen::MatrixXf::Constant(8, 6, 0.5f);
    a(3, 2) = std::nanf("");
    EXPECT_NE(testing::error_of([&] { fit_group(a, {0}, PcaOptions{}, 1); }).find("NaN"),
              std::string::npos);
}

TEST(FitGroup, SameBitsForAnyThreadCount) {
    const Spectrum s = make_spectrum(9000, 50, geometric(30, 1.0, 0.8));
    for (PcaMethod m : {PcaMethod::kGram, PcaMethod::kRandomized}) {
        parallel::set_thread_count(1);
        Eigen::MatrixXf a = s.a;
        const GroupPca one = fit_group(a, {0}, options(m, 6), 3);
        parallel::set_thread_count(2);
        a = s.a;
        const GroupPca two = fit_group(a, {0}, options(m, 6), 3);
        EXPECT_TRUE(one.basis == two.basis && one.weights == two.weights && one.mean == two.mean);
        EXPECT_EQ(one.residual_energy, two.residual_energy);
    }
    parallel::set_thread_count(0);
}

/// Rank-2 data plus a mean, with a share of its samples replaced by large outliers (+-3..6): the
/// case least absolute error is for. `clean` is the data before the outliers.
struct Corrupted {
    Eigen::MatrixXf a, clean;
    Eigen::Matrix<bool, Eigen::Dynamic, Eigen::Dynamic> outlier;
};
Corrupted make_corrupted(int p, int n, double share, uint64_t seed) {
    const Spectrum s = make_spectrum(p, n, {6.0, 3.0}, seed);
    Corrupted c{s.a, s.a, Eigen::Matrix<bool, Eigen::Dynamic, Eigen::Dynamic>::Constant(p, n, false)};
    std::mt19937_64 rng(seed + 1);
    std::uniform_real_distribution<double> u01;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < p; ++i)
            if (u01(rng) < share) {
                c.outlier(i, j) = true;
                c.a(i, j) += float((u01(rng) < 0.5 ? -1 : 1) * (3.0 + 3.0 * u01(rng)));
            }
    return c;
}

/// The model the group holds: m 1^T + (U Sigma) V^T.
Eigen::MatrixXf model_of(const GroupPca& g) { return g.reconstruct(g.components()); }

// Least absolute error recovers low-rank data under sparse gross outliers, which least squares
// spreads over every sample: 5% of the samples corrupted by 3-6 (the data's scale is ~0.5).
TEST(RefitL1, RecoversLowRankDataUnderSparseOutliers) {
    const Corrupted c = make_corrupted(300, 80, 0.05, 11);
    Eigen::MatrixXf a = c.a;
    GroupPca g = fit_group(a, {0}, options(PcaMethod::kGram, 2), 1);
    auto clean_error = [&](const GroupPca& fit) {
        const Eigen::MatrixXf m = model_of(fit);
        double worst = 0;
        for (int j = 0; j < c.a.cols(); ++j)
            for (int i = 0; i < c.a.rows(); ++i)
                if (!c.outlier(i, j)) worst = std::max(worst, double(std::abs(m(i, j) - c.clean(i, j))));
        return worst;
    };
    const double pca_error = clean_error(g);
    const L1Refit r = refit_l1(a, g, 30, /*trace=*/true);
    const double l1_error = clean_error(g);
    // Least squares leaves errors of the outliers' order on clean samples.
    EXPECT_GT(pca_error, 0.2);
    // Huber's estimate is pulled by each outlier's bounded influence (1) against the clean
    // samples' r / delta: a mean bias of about delta x share / (1 - share) = 0.005 here; the worst
    // of 22,800 clean samples is a few times that (rows and columns share the outliers' pull), so
    // 10x the mean bias (measured 0.027; the PCA's is 2.4).
    constexpr double kHuberBiasTol = 0.05;
    EXPECT_LT(l1_error, kHuberBiasTol) << "delta " << r.delta << " PCA " << pca_error;
    EXPECT_LT(r.sae_after, r.sae_before);
    // The outliers stay in the residual: the model does not chase them.
    EXPECT_LT(l1_error, pca_error / 20);
}

// Each half-step minimises a quadratic majorant of the Huber objective, so the objective never
// rises (up to the rounding of its sum over 24,000 samples, 1e-12 relative).
TEST(RefitL1, HuberObjectiveNeverRisesAndTheFormIsKept) {
    const Corrupted c = make_corrupted(400, 60, 0.1, 5);
    Eigen::MatrixXf a = c.a;
    // Dense Laplace-like noise on top, so every sample has a residual.
    std::mt19937_64 rng(3);
    std::exponential_distribution<double> expo(50.0);
    for (Eigen::Index i = 0; i < a.size(); ++i) a.data()[i] += float((i % 2 ? 1 : -1) * expo(rng));
    const Eigen::MatrixXf original = a;
    GroupPca g = fit_group(a, {0}, options(PcaMethod::kGram, 4), 1);
    const L1Refit r = refit_l1(a, g, 12, /*trace=*/true);
    ASSERT_EQ(r.huber.size(), 1u + 2u * 12u);
    constexpr double kSumRounding = 1e-12;
    for (size_t i = 1; i < r.huber.size(); ++i) EXPECT_LE(r.huber[i], r.huber[i - 1] * (1 + kSumRounding)) << i;
    EXPECT_LT(r.huber.back(), r.huber.front());
    // GroupPca form: V orthonormal, components by energy, a re-centred by the new mean.
    const Eigen::MatrixXd vtv = g.weights.cast<double>().transpose() * g.weights.cast<double>();
    EXPECT_LT((vtv - Eigen::MatrixXd::Identity(4, 4)).cwiseAbs().maxCoeff(), kValueTol);
    for (int i = 1; i < 4; ++i) EXPECT_GE(g.basis.col(i - 1).squaredNorm(), g.basis.col(i).squaredNorm());
    Eigen::MatrixXf back = a;
    back.colwise() += g.mean;
    EXPECT_LT(max_abs(back, original), kValueTol);
    // residual_energy is the refitted model's, component by component (brute force).
    for (int cc = 0; cc <= 4; ++cc) {
        const double brute = (original - g.reconstruct(cc)).cast<double>().squaredNorm();
        EXPECT_NEAR(g.residual_energy[size_t(cc)], brute, kEnergyTol * g.total_energy) << cc;
    }
    EXPECT_NEAR(r.sae_after, (original - model_of(g)).cast<double>().cwiseAbs().sum(), 1e-5 * r.sae_after);
}

// Data the PCA fits exactly has no residual to reweight: the fit is returned as it was.
TEST(RefitL1, ExactFitIsUnchanged) {
    const Spectrum s = make_spectrum(120, 40, {2.0, 1.0, 0.5});
    Eigen::MatrixXf a = s.a;
    PcaOptions o = options(PcaMethod::kGram, 6);
    GroupPca g = fit_group(a, {0}, o, 1);
    const GroupPca before = g;
    const L1Refit r = refit_l1(a, g, 5, /*trace=*/true);
    EXPECT_TRUE(r.huber.empty());
    EXPECT_TRUE(g.basis == before.basis && g.weights == before.weights && g.mean == before.mean);
}

TEST(RefitL1, SameBitsForAnyThreadCount) {
    const Corrupted c = make_corrupted(5000, 60, 0.05, 9);
    PcaOptions o = options(PcaMethod::kGram, 3);
    o.l1_iterations = 3;
    parallel::set_thread_count(1);
    Eigen::MatrixXf a = c.a;
    const GroupPca one = fit_group(a, {0}, o, 3);
    parallel::set_thread_count(2);
    Eigen::MatrixXf b = c.a;
    const GroupPca two = fit_group(b, {0}, o, 3);
    parallel::set_thread_count(0);
    EXPECT_TRUE(one.basis == two.basis && one.weights == two.weights && one.mean == two.mean && a == b);
    EXPECT_EQ(one.residual_energy, two.residual_energy);
}

// Streaming: one sink call per view group in order, each fit equal to fitting that group alone;
// 4 views in groups of 3 leave a group of one view (243 columns), fitted like any other.
TEST(CompressBtf, StreamsGroupsIncludingASingleView) {
    AnalyticBtfOptions bo;
    bo.width = 12;
    bo.height = 10;
    bo.rank = 3;
    bo.views = {{0, 0}, {15, 0}, {15, 60}, {60, 180}};
    const AnalyticBtf btf(bo);
    PcaOptions o = options(PcaMethod::kAuto, 5);
    o.view_group_size = 3;
    const auto groups = view_groups(bo.views, 3);
    ASSERT_EQ(groups.size(), 2u);
    int calls = 0;
    const CompressStats stats = compress_btf(btf, o, [&](GroupFit& fit) {
        EXPECT_EQ(fit.index, calls++);
        EXPECT_EQ(fit.count, 2);
        EXPECT_EQ(fit.pca.views, groups[static_cast<size_t>(fit.index)]);
        Eigen::MatrixXf a, original;
        btf.read_group(fit.pca.views, original);
        a = original;
        const GroupPca alone = fit_group(a, fit.pca.views, o, static_cast<uint64_t>(fit.index));
        EXPECT_TRUE(alone.basis == fit.pca.basis && alone.weights == fit.pca.weights);
        EXPECT_EQ(fit.centred.cols(), 243 * static_cast<int>(fit.pca.views.size()));
        EXPECT_LT(max_abs(fit.pca.reconstruct(3), original), kValueTol);  // rank 3
    });
    EXPECT_EQ(calls, 2);
    EXPECT_EQ(stats.groups, 2);
    EXPECT_EQ(stats.components, 10);
    EXPECT_GT(stats.peak_rss_bytes, 0u);
}

// Out of core: a group of all views read 2 views at a time (the last block holds one) equals
// the in-core fit of the same group: the mean to the bit (the same double additions in the same
// order) and the energies, components and reconstruction to kEnergyTol / kValueTol (only the
// sums over blocks of views run in another order: double rounding, ~1e-13 relative here, then
// float32 storage). Gram over the pixels (P = 120 < N = 168), randomized SVD, and Gram over the
// columns (N = 72 < P = 900: that small group is read whole). Memory: one block of 2 views.
TEST(FitGroupStreamed, EqualsTheInCoreFit) {
    struct Case {
        int width, height, views;
        PcaMethod method;
        int passes;  // over the images, besides the mean's: one per product the method needs
    };
    for (const Case& k : {Case{12, 10, 7, PcaMethod::kGram, 3}, Case{12, 10, 7, PcaMethod::kRandomized, 7},
                          Case{30, 30, 3, PcaMethod::kGram, 2}}) {
        SCOPED_TRACE(to_string(k.method) + " views " + std::to_string(k.views));
        AnalyticBtfOptions bo;
        bo.width = k.width;
        bo.height = k.height;
        bo.rank = 6;
        bo.scale = 4.0;
        bo.lights = {{0, 0}, {15, 0}, {15, 120}, {30, 60}, {30, 240}, {45, 0}, {60, 90}, {75, 300}};
        bo.views = {{0, 0}, {15, 60}, {30, 0}, {30, 120}, {45, 180}, {60, 270}, {75, 30}};
        bo.views.resize(static_cast<size_t>(k.views));
        const AnalyticBtf btf(bo);
        std::vector<int> all(static_cast<size_t>(k.views));
        std::iota(all.begin(), all.end(), 0);
        PcaOptions o = options(k.method, 5);
        o.stream_views = 2;
        StreamStats st;
        const GroupPca out = fit_group_streamed(btf, all, o, 4, &st);
        Eigen::MatrixXf a;
        btf.read_group(all, a);
        const Eigen::MatrixXf original = a;
        const GroupPca in = fit_group(a, all, o, 4);
        EXPECT_TRUE(out.mean == in.mean);
        EXPECT_EQ(out.method, in.method);
        ASSERT_EQ(out.components(), in.components());
        ASSERT_EQ(out.residual_energy.size(), in.residual_energy.size());
        for (size_t c = 0; c < in.residual_energy.size(); ++c)
            EXPECT_NEAR(out.residual_energy[c], in.residual_energy[c], kEnergyTol * in.total_energy) << c;
        EXPECT_LT(max_abs(out.weights, in.weights), kValueTol);
        EXPECT_LT(max_abs(out.reconstruct(5), in.reconstruct(5)), kValueTol);
        // a real fit: 5 of the 6 lobes leave less than half of the mean's worst error
        EXPECT_LT(max_abs(out.reconstruct(5), original), 0.5 * max_abs(out.reconstruct(0), original));
        EXPECT_EQ(st.passes, k.passes + 1);  // + the mean's pass
        const uint64_t block = uint64_t(k.width) * k.height * 3 * 8 * 2 * sizeof(float);
        EXPECT_EQ(st.block_bytes, block);
    }
}

// 8-bit saturation: highlights pushed past 1 clip in the PNG files, so the data read back is
// no longer of rank 4. The fit stays optimal (equal to the full-SVD oracle) and the budget
// takes more components than the unclipped BTF needs.
TEST(CompressBtf, EightBitSaturationStaysOptimalAndNeedsMoreComponents) {
    AnalyticBtfOptions bo;
    bo.width = 10;
    bo.height = 8;
    bo.rank = 4;
    bo.scale = 4.0;
    bo.lights = {{0, 0}, {15, 0}, {15, 120}, {30, 60}, {30, 240}, {45, 0}, {60, 90}, {75, 300}};
    bo.views = {{0, 0}, {30, 0}, {45, 180}};
    const AnalyticBtf btf(bo);
    const std::string dir = testing::temp_dir("btf_pca_saturation");
    UboWriteOptions wo;
    write_ubo2003(btf, dir + "/btf", wo);
    const std::string lights = dir + "/lights.txt", views = dir + "/views.txt";
    {
        std::ofstream l(lights), v(views);
        for (const auto& d : bo.lights) l << d.theta_deg << " " << d.phi_deg << "\n";
        for (const auto& d : bo.views) v << d.theta_deg << " " << d.phi_deg << "\n";
    }
    OpenOptions open;
    open.light_directions = lights;
    open.view_directions = views;
    const auto folder = FolderBtf::open(dir + "/btf", open);
    Eigen::MatrixXf clipped, exact;
    folder->read_group({0, 1, 2}, clipped);
    btf.read_group({0, 1, 2}, exact);
    ASSERT_EQ(clipped.maxCoeff(), 1.0f);  // saturated samples exist
    ASSERT_GT(exact.maxCoeff(), 1.1f);

    PcaOptions o = options(PcaMethod::kGram, 20);
    // above 8-bit rounding noise (~1e-3 rms in linear units), below what 4 components leave of the
    // clipped data (0.02 rms here)
    o.max_rmse = 1e-2;
    Eigen::MatrixXf a = exact;
    const int unclipped_c = fit_group(a, {0, 1, 2}, o, 1).components();
    a = clipped;
    const GroupPca g = fit_group(a, {0, 1, 2}, o, 1);
    EXPECT_LE(unclipped_c, 4);
    EXPECT_GT(g.components(), 4);  // more than the unclipped rank
    EXPECT_LE(g.rmse(g.components()), o.max_rmse);
    a = clipped;
    const GroupPca oracle = fit_group(a, {0, 1, 2}, options(PcaMethod::kFullSvd, 20), 1);
    for (int c = 0; c <= g.components(); ++c)
        EXPECT_NEAR(g.residual_energy[c], oracle.residual_energy[c], kEnergyTol * g.total_energy);
}

// The Gram kernel against sums in long double (64-bit mantissa, 2^11 times finer than double):
// every product of two floats is exact in double, so each entry carries only the rounding of
// its additions: at most P additions per path (lane sums of P/4 terms, 3 lane adds, one add per
// chunk and per partial), each within u = 2^-53 of the running sum, so |error| <= (P + 8) u
// sum_k |a_ki a_kj| (Higham, recursive summation). Sizes not multiples of the 4-column tile, the
// 4-row lane or the 256-row chunk exercise the padding.
TEST(GramOfColumns, WithinTheSummationBoundOfLongDoubleSums) {
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<float> uni(-1.0f, 1.0f);
    for (auto [p, n] : {std::pair{1031, 37}, std::pair{5, 3}, std::pair{2600, 244}}) {
        Eigen::MatrixXf a(p, n);
        for (Eigen::Index i = 0; i < a.size(); ++i) a.data()[i] = uni(rng);
        const Eigen::MatrixXd g = gram_of_columns(a);
        const double u = std::ldexp(1.0, -53);
        double worst = 0;  // error over its bound
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                long double exact = 0, mag = 0;
                for (int k = 0; k < p; ++k) {
                    exact += (long double)a(k, i) * a(k, j);
                    mag += std::fabs((long double)a(k, i) * a(k, j));
                }
                const double bound = double(p + 8) * u * double(mag);
                worst = std::max(worst, double(std::fabs((long double)g(i, j) - exact)) / bound);
                ASSERT_EQ(g(i, j), g(j, i));
            }
        EXPECT_LE(worst, 1.0) << p << "x" << n;
    }
}

// The benchmark's case at a small size: one view group (k = 1: 81 lights x 3 = 243 columns) of
// the analytic BTF with highlights clipped at 1 (not of low rank), C = 8. The Gram path reaches
// the full SVD's (optimal) residual at every c, so the RMSE is equal, to kEnergyTol of the total.
TEST(FitGroup, GramEqualsTheFullSvdOnAClippedBonnGroup) {
    AnalyticBtfOptions bo;
    bo.width = bo.height = 40;  // 1600 pixels > 243 columns: the Gram path over columns
    bo.rank = 6;
    bo.scale = 4.0;
    const AnalyticBtf btf(bo);
    Eigen::MatrixXf a0;
    btf.read_group({0}, a0);
    a0 = a0.cwiseMin(1.0f);
    ASSERT_EQ(a0.cols(), 243);
    Eigen::MatrixXf a = a0;
    const GroupPca gram = fit_group(a, {0}, options(PcaMethod::kGram, 8), 1);
    a = a0;
    const GroupPca svd = fit_group(a, {0}, options(PcaMethod::kFullSvd, 8), 1);
    ASSERT_EQ(gram.components(), 8);
    ASSERT_GT(svd.residual_energy[8], 1e-4 * svd.total_energy);  // clipping leaves a real residual at C = 8
    for (int c = 0; c <= 8; ++c)
        EXPECT_NEAR(gram.residual_energy[c], svd.residual_energy[c], kEnergyTol * svd.total_energy) << c;
    EXPECT_NEAR(gram.rmse(8), svd.rmse(8), std::sqrt(kEnergyTol * svd.total_energy / (1600.0 * 243)));
}

}  // namespace
}  // namespace inlight::btf
