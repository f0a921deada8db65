#include "btf/pca.h"

#include <Eigen/Eigenvalues>
#include <Eigen/QR>
#include <Eigen/SVD>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <random>

#include "core/check.h"
#include "core/error.h"
#include "core/memory.h"
#include "core/parallel.h"

namespace inlight::btf {
namespace {

/// Fixed partial sums of the reductions over rows: the parallelism of A^T X and of the Gram
/// matrix, independent of the thread count so the sums are bit-identical.
constexpr int64_t kPartials = 4;
/// Doubles per temporary block converted from float (4 Mi = 32 MiB per worker).
constexpr int64_t kBlockElements = int64_t(1) << 22;

int64_t block_rows(int64_t cols) { return std::clamp<int64_t>(kBlockElements / std::max<int64_t>(cols, 1), 16, 4096); }

uint64_t splitmix64(uint64_t x) {
    x += 0x9E3779B97F4A7C15ull;
    x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
    x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
    return x ^ (x >> 31);
}

/// Sum over `parts` fixed slices of [0, n), each walked in blocks of `block`:
/// fn(partial, begin, count) adds a block's share into its slice's partial (r x c).
template <typename Fn>
Eigen::MatrixXd sum_over(int64_t n, int64_t block, Eigen::Index r, Eigen::Index c, Fn fn) {
    const int64_t parts = std::max<int64_t>(1, std::min(kPartials, n));
    const int64_t per = (n + parts - 1) / parts;
    std::vector<Eigen::MatrixXd> partial(static_cast<size_t>(parts));
    parallel::for_chunks(parts, 1, [&](int64_t b, int64_t e) {
        for (int64_t p = b; p < e; ++p) {
            Eigen::MatrixXd& acc = partial[static_cast<size_t>(p)];
            acc.setZero(r, c);
            const int64_t end = std::min(n, (p + 1) * per);
            for (int64_t i = p * per; i < end; i += block) fn(acc, i, std::min(block, end - i));
        }
    });
    Eigen::MatrixXd total = std::move(partial[0]);
    for (size_t p = 1; p < partial.size(); ++p) total += partial[p];
    return total;
}

/// A X: P x N float times N x l double, row block by row block.
Eigen::MatrixXd times(const Eigen::MatrixXf& a, const Eigen::MatrixXd& x) {
    Eigen::MatrixXd y(a.rows(), x.cols());
    parallel::for_chunks(a.rows(), block_rows(a.cols()), [&](int64_t b, int64_t e) {
        const Eigen::MatrixXd blk = a.middleRows(b, e - b).cast<double>();
        y.middleRows(b, e - b).noalias() = blk * x;
    });
    return y;
}

/// A^T Y: N x l, summed over row blocks.
Eigen::MatrixXd times_transposed(const Eigen::MatrixXf& a, const Eigen::MatrixXd& y) {
    return sum_over(a.rows(), block_rows(a.cols()), a.cols(), y.cols(),
                    [&](Eigen::MatrixXd& acc, int64_t i, int64_t n) {
                        const Eigen::MatrixXd blk = a.middleRows(i, n).cast<double>();
                        acc.noalias() += blk.transpose() * y.middleRows(i, n);
                    });
}

/// A A^T (P x P, double), summed over column blocks.
Eigen::MatrixXd gram_of_rows(const Eigen::MatrixXf& a) {
    const int64_t cols_per_block = std::clamp<int64_t>(kBlockElements / std::max<int64_t>(a.rows(), 1), 16, 4096);
    Eigen::MatrixXd g = sum_over(a.cols(), cols_per_block, a.rows(), a.rows(),
                                 [&](Eigen::MatrixXd& acc, int64_t j, int64_t n) {
                                     const Eigen::MatrixXd blk = a.middleCols(j, n).cast<double>();
                                     acc.selfadjointView<Eigen::Lower>().rankUpdate(blk);
                                 });
    g.triangularView<Eigen::StrictlyUpper>() = g.transpose();
    return g;
}

/// An orthonormal basis of Y's columns (thin Householder Q, P x l); orthonormal also when Y is
/// rank-deficient or zero.
Eigen::MatrixXd orthonormal(const Eigen::MatrixXd& y) {
    Eigen::HouseholderQR<Eigen::MatrixXd> qr(y);
    return qr.householderQ() * Eigen::MatrixXd::Identity(y.rows(), y.cols());
}

/// The leading `c` eigenvectors of a symmetric matrix, largest eigenvalue first.
Eigen::MatrixXd leading_eigenvectors(const Eigen::MatrixXd& g, int c) {
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(g);
    if (es.info() != Eigen::Success) throw Error("PCA: the Gram matrix's eigensolver did not converge");
    return es.eigenvectors().rightCols(c).rowwise().reverse();
}

/// Right singular vectors V (N x c) of the centred matrix by each method.
Eigen::MatrixXd right_vectors(const Eigen::MatrixXf& a, PcaMethod method, int c,
                              const PcaOptions& o, uint64_t seed) {
    const int64_t p = a.rows(), n = a.cols();
    switch (method) {
        case PcaMethod::kGram:
            if (n <= p) return leading_eigenvectors(gram_of_columns(a), c);
            {   // short side is the pixels: V = A^T U, normalised; zero where A^T u vanishes
                Eigen::MatrixXd v = times_transposed(a, leading_eigenvectors(gram_of_rows(a), c));
                const double largest = v.colwise().norm().maxCoeff();
                for (int i = 0; i < c; ++i) {
                    const double norm = v.col(i).norm();
                    // below float resolution of the largest component: a null direction
                    if (norm <= largest * 1e-6 || norm == 0) v.col(i).setZero();
                    else v.col(i) /= norm;
                }
                return v;
            }
        case PcaMethod::kRandomized: {
            const int l = static_cast<int>(std::min<int64_t>(c + o.oversampling, std::min(p, n)));
            std::mt19937_64 rng(splitmix64(o.seed ^ splitmix64(seed)));
            std::normal_distribution<double> normal;
            Eigen::MatrixXd omega(n, l);
            for (Eigen::Index j = 0; j < omega.cols(); ++j)
                for (Eigen::Index i = 0; i < omega.rows(); ++i) omega(i, j) = normal(rng);
            Eigen::MatrixXd q = orthonormal(times(a, omega));
            for (int it = 0; it < o.power_iterations; ++it)
                q = orthonormal(times(a, orthonormal(times_transposed(a, q))));
            const Eigen::MatrixXd bt = times_transposed(a, q);  // B^T = A^T Q = V S U_B^T
            Eigen::BDCSVD<Eigen::MatrixXd> svd(bt, Eigen::ComputeThinU);
            return svd.matrixU().leftCols(c);
        }
        case PcaMethod::kFullSvd: {
            const Eigen::MatrixXd ad = a.cast<double>();
            Eigen::BDCSVD<Eigen::MatrixXd> svd(ad, Eigen::ComputeThinV);
            return svd.matrixV().leftCols(c);
        }
        case PcaMethod::kAuto:
            break;
    }
    INLIGHT_CHECK(false) << "unresolved PCA method";
    return {};
}

}  // namespace

std::string to_string(PcaMethod m) {
    switch (m) {
        case PcaMethod::kAuto: return "auto";
        case PcaMethod::kGram: return "gram";
        case PcaMethod::kRandomized: return "randomized";
        case PcaMethod::kFullSvd: return "full-svd";
    }
    return "?";
}

PcaMethod pca_method_from_string(const std::string& name) {
    for (PcaMethod m : {PcaMethod::kAuto, PcaMethod::kGram, PcaMethod::kRandomized, PcaMethod::kFullSvd})
        if (to_string(m) == name) return m;
    throw UsageError("unknown PCA method '" + name + "' (auto, gram, randomized, full-svd)");
}

Eigen::MatrixXd gram_of_columns(const Eigen::MatrixXf& a) {
    Eigen::MatrixXd g = sum_over(a.rows(), block_rows(a.cols()), a.cols(), a.cols(),
                                 [&](Eigen::MatrixXd& acc, int64_t i, int64_t n) {
                                     const Eigen::MatrixXd blk = a.middleRows(i, n).cast<double>();
                                     acc.selfadjointView<Eigen::Lower>().rankUpdate(blk.transpose());
                                 });
    g.triangularView<Eigen::StrictlyUpper>() = g.transpose();
    return g;
}

double GroupPca::rmse(int c) const {
    INLIGHT_CHECK(c >= 0 && c < static_cast<int>(residual_energy.size())) << c;
    const double samples = double(pixels) * columns;
    return samples > 0 ? std::sqrt(residual_energy[static_cast<size_t>(c)] / samples) : 0.0;
}

Eigen::MatrixXf GroupPca::reconstruct(int c) const {
    INLIGHT_CHECK(c >= 0 && c <= components()) << c << " of " << components();
    Eigen::MatrixXf out(pixels, columns);
    out.noalias() = basis.leftCols(c) * weights.leftCols(c).transpose();
    out.colwise() += mean;
    return out;
}

GroupPca fit_group(Eigen::MatrixXf& a, const std::vector<int>& views, const PcaOptions& o,
                   uint64_t group_seed) {
    INLIGHT_CHECK(o.components >= 1 && o.gram_max_side >= 1 && o.oversampling >= 0 &&
                  o.power_iterations >= 0 && std::isfinite(o.max_rmse))
        << "PCA options out of range";
    INLIGHT_CHECK(a.rows() >= 1 && a.cols() >= 1) << a.rows() << "x" << a.cols();
    GroupPca g;
    g.views = views;
    g.pixels = static_cast<int>(a.rows());
    g.columns = static_cast<int>(a.cols());
    const int64_t p = a.rows(), n = a.cols(), grain = block_rows(n);

    // m = per-pixel mean over the columns (double sums), then A_c = A - m 1^T in place.
    Eigen::VectorXd mean = Eigen::VectorXd::Zero(p);
    bool finite = true;
    parallel::for_chunks(p, grain, [&](int64_t b, int64_t e) {
        for (int64_t j = 0; j < n; ++j) mean.segment(b, e - b) += a.col(j).segment(b, e - b).cast<double>();
        mean.segment(b, e - b) /= double(n);
        if (!mean.segment(b, e - b).allFinite()) finite = false;
        const Eigen::VectorXf mf = mean.segment(b, e - b).cast<float>();
        for (int64_t j = 0; j < n; ++j) a.col(j).segment(b, e - b) -= mf;
    });
    if (!finite) throw Error("PCA: the BTF's images hold NaN or Inf");
    g.mean = mean.cast<float>();
    g.total_energy = parallel::reduce(
        p, grain, 0.0,
        [&](int64_t b, int64_t e) {
            double s = 0;
            for (int64_t j = 0; j < n; ++j) s += a.col(j).segment(b, e - b).cast<double>().squaredNorm();
            return s;
        },
        [](double x, double y) { return x + y; });

    const int c = static_cast<int>(std::min<int64_t>(o.components, std::min(p, n)));
    g.method = o.method;
    if (g.method == PcaMethod::kAuto)
        g.method = std::min(p, n) <= o.gram_max_side ? PcaMethod::kGram : PcaMethod::kRandomized;
    const Eigen::MatrixXd v = right_vectors(a, g.method, c, o, group_seed);
    const Eigen::MatrixXd l = times(a, v);  // U Sigma = A_c V

    // Order by the energy each component removes (randomized vectors come nearly sorted).
    std::vector<int> order(static_cast<size_t>(c));
    std::iota(order.begin(), order.end(), 0);
    const Eigen::VectorXd energy = l.colwise().squaredNorm().transpose();
    std::stable_sort(order.begin(), order.end(), [&](int x, int y) { return energy[x] > energy[y]; });
    g.residual_energy.assign(1, g.total_energy);
    for (int i = 0; i < c; ++i)
        g.residual_energy.push_back(std::max(0.0, g.residual_energy.back() - energy[order[static_cast<size_t>(i)]]));

    int keep = c;
    if (o.max_rmse >= 0) {
        const double target = o.max_rmse * o.max_rmse * double(p) * double(n);
        keep = 0;
        while (keep < c && g.residual_energy[static_cast<size_t>(keep)] > target) ++keep;
    }
    g.residual_energy.resize(static_cast<size_t>(keep) + 1);
    g.basis.resize(p, keep);
    g.weights.resize(n, keep);
    for (int i = 0; i < keep; ++i) {
        g.basis.col(i) = l.col(order[static_cast<size_t>(i)]).cast<float>();
        g.weights.col(i) = v.col(order[static_cast<size_t>(i)]).cast<float>();
    }
    return g;
}

CompressStats compress_btf(const BtfSource& source, const PcaOptions& options,
                           const std::function<void(GroupFit&)>& sink) {
    INLIGHT_CHECK_GE(options.view_group_size, 1);
    using Clock = std::chrono::steady_clock;
    const auto groups = view_groups(source.shape().views, options.view_group_size);
    CompressStats stats;
    stats.groups = static_cast<int>(groups.size());
    for (size_t gi = 0; gi < groups.size(); ++gi) {
        GroupFit fit;
        fit.index = static_cast<int>(gi);
        fit.count = stats.groups;
        auto t0 = Clock::now();
        source.read_group(groups[gi], fit.centred);
        auto t1 = Clock::now();
        fit.pca = fit_group(fit.centred, groups[gi], options, gi);
        auto t2 = Clock::now();
        stats.read_time_s += std::chrono::duration<double>(t1 - t0).count();
        stats.fit_time_s += std::chrono::duration<double>(t2 - t1).count();
        stats.components += fit.pca.components();
        stats.total_energy += fit.pca.total_energy;
        stats.residual_energy += fit.pca.residual_energy.back();
        sink(fit);
    }
    stats.peak_rss_bytes = peak_rss_bytes();
    return stats;
}

}  // namespace inlight::btf
