#include "btf/pca.h"

#include <Eigen/Eigenvalues>
#include <Eigen/QR>
#include <Eigen/SVD>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
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
/// Doubles per temporary block converted from float (256 Ki = 2 MiB per worker: the GEMMs on it
/// block for the cache themselves, and the budget of --max-memory-mib counts it per worker).
constexpr int64_t kBlockElements = int64_t(1) << 18;

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

/// The centred matrix A_c of a group, seen only through the products the methods need: held in
/// memory (InCore) or streamed from the BTF a block of views at a time (Streamed).
class CentredOp {
  public:
    virtual ~CentredOp() = default;
    virtual int64_t rows() const = 0;
    virtual int64_t cols() const = 0;
    virtual Eigen::MatrixXd times(const Eigen::MatrixXd& x) const = 0;             ///< A_c X
    virtual Eigen::MatrixXd times_transposed(const Eigen::MatrixXd& y) const = 0;  ///< A_c^T Y
    virtual Eigen::MatrixXd gram_rows() const = 0;                                 ///< A_c A_c^T
    virtual Eigen::MatrixXd gram_columns() const = 0;                              ///< A_c^T A_c
    virtual const Eigen::MatrixXf* dense() const { return nullptr; }  ///< the matrix, if held
};

class InCore : public CentredOp {
  public:
    explicit InCore(const Eigen::MatrixXf& a) : m_a(a) {}
    int64_t rows() const override { return m_a.rows(); }
    int64_t cols() const override { return m_a.cols(); }
    Eigen::MatrixXd times(const Eigen::MatrixXd& x) const override { return btf::times(m_a, x); }
    Eigen::MatrixXd times_transposed(const Eigen::MatrixXd& y) const override { return btf::times_transposed(m_a, y); }
    Eigen::MatrixXd gram_rows() const override { return btf::gram_of_rows(m_a); }
    Eigen::MatrixXd gram_columns() const override { return gram_of_columns(m_a); }
    const Eigen::MatrixXf* dense() const override { return &m_a; }

  private:
    const Eigen::MatrixXf& m_a;
};

/// Right singular vectors V (N x c) of the centred matrix by each method.
Eigen::MatrixXd right_vectors(const CentredOp& a, PcaMethod method, int c, const PcaOptions& o, uint64_t seed) {
    const int64_t p = a.rows(), n = a.cols();
    switch (method) {
        case PcaMethod::kGram:
            if (n <= p) return leading_eigenvectors(a.gram_columns(), c);
            {   // short side is the pixels: V = A^T U, normalised; zero where A^T u vanishes
                Eigen::MatrixXd v = a.times_transposed(leading_eigenvectors(a.gram_rows(), c));
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
            Eigen::MatrixXd q = orthonormal(a.times(omega));
            for (int it = 0; it < o.power_iterations; ++it)
                q = orthonormal(a.times(orthonormal(a.times_transposed(q))));
            const Eigen::MatrixXd bt = a.times_transposed(q);  // B^T = A^T Q = V S U_B^T
            Eigen::BDCSVD<Eigen::MatrixXd> svd(bt, Eigen::ComputeThinU);
            return svd.matrixU().leftCols(c);
        }
        case PcaMethod::kFullSvd: {
            INLIGHT_CHECK(a.dense() != nullptr) << "the full SVD needs the group in memory";
            const Eigen::MatrixXd ad = a.dense()->cast<double>();
            Eigen::BDCSVD<Eigen::MatrixXd> svd(ad, Eigen::ComputeThinV);
            return svd.matrixV().leftCols(c);
        }
        case PcaMethod::kAuto:
            break;
    }
    INLIGHT_CHECK(false) << "unresolved PCA method";
    return {};
}

void check_options(const PcaOptions& o) {
    INLIGHT_CHECK(o.components >= 1 && o.gram_max_side >= 1 && o.oversampling >= 0 &&
                  o.power_iterations >= 0 && std::isfinite(o.max_rmse) && o.stream_views >= 0)
        << "PCA options out of range";
}

/// The components of a centred group whose mean `g` already holds: V by the method, U Sigma =
/// A_c V, ordered by energy and cut by the error budget. `total_energy` (||A_c||^2) is asked
/// after the products, so a streamed group sums it during its first pass.
void fit_components(GroupPca& g, const CentredOp& a, const PcaOptions& o, uint64_t group_seed,
                    const std::function<double()>& total_energy) {
    const int64_t p = a.rows(), n = a.cols();
    const int c = static_cast<int>(std::min<int64_t>(o.components, std::min(p, n)));
    g.method = o.method;
    if (g.method == PcaMethod::kAuto)
        g.method = std::min(p, n) <= o.gram_max_side ? PcaMethod::kGram : PcaMethod::kRandomized;
    const Eigen::MatrixXd v = right_vectors(a, g.method, c, o, group_seed);
    const Eigen::MatrixXd l = a.times(v);  // U Sigma = A_c V
    g.total_energy = total_energy();

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
}

/// Adds column j of `a` (rows [b, e)) into `sum` in double: the mean's sums, the same additions
/// in the same order in and out of core.
void add_columns(Eigen::VectorXd& sum, const Eigen::MatrixXf& a, int64_t b, int64_t e) {
    for (int64_t j = 0; j < a.cols(); ++j) sum.segment(b, e - b) += a.col(j).segment(b, e - b).cast<double>();
}

double centred_energy(const Eigen::MatrixXf& a, int64_t grain) {
    return parallel::reduce(
        a.rows(), grain, 0.0,
        [&](int64_t b, int64_t e) {
            double s = 0;
            for (int64_t j = 0; j < a.cols(); ++j) s += a.col(j).segment(b, e - b).cast<double>().squaredNorm();
            return s;
        },
        [](double x, double y) { return x + y; });
}

/// A_c streamed from a BtfSource: every product is one pass over the group's views, read
/// `block_views` at a time and centred in float exactly as fit_group centres in place.
class Streamed : public CentredOp {
  public:
    Streamed(const BtfSource& source, const std::vector<int>& views, int block_views, StreamStats& stats)
        : m_source(source), m_views(views), m_block(std::max(1, block_views)), m_stats(stats),
          m_cols_per_view(source.shape().group_columns(1)) {}
    int64_t rows() const override { return m_source.shape().pixel_count(); }
    int64_t cols() const override { return m_cols_per_view * static_cast<int64_t>(m_views.size()); }

    /// fn(first column, block of A_c) for each block of views in order; `centre` = false gives
    /// the raw block (the mean's pass).
    template <typename Fn>
    void pass(bool centre, Fn fn) const {
        using Clock = std::chrono::steady_clock;
        ++m_stats.passes;
        Eigen::MatrixXf blk;
        for (size_t v0 = 0; v0 < m_views.size(); v0 += static_cast<size_t>(m_block)) {
            const std::vector<int> part(m_views.begin() + static_cast<std::ptrdiff_t>(v0),
                                        m_views.begin() + static_cast<std::ptrdiff_t>(std::min(m_views.size(), v0 + size_t(m_block))));
            const auto t0 = Clock::now();
            m_source.read_group(part, blk);
            m_stats.read_time_s += std::chrono::duration<double>(Clock::now() - t0).count();
            m_stats.block_bytes = std::max<uint64_t>(m_stats.block_bytes, uint64_t(blk.size()) * sizeof(float));
            if (centre)
                parallel::for_chunks(blk.rows(), block_rows(blk.cols()), [&](int64_t b, int64_t e) {
                    for (int64_t j = 0; j < blk.cols(); ++j) blk.col(j).segment(b, e - b) -= m_mean.segment(b, e - b);
                });
            if (centre && !m_have_energy) m_energy += centred_energy(blk, block_rows(blk.cols()));
            fn(static_cast<int64_t>(v0) * m_cols_per_view, blk);
        }
        if (centre) m_have_energy = true;
    }
    void set_mean(Eigen::VectorXf mean) { m_mean = std::move(mean); }
    /// ||A_c||^2, summed over the blocks of the first centred pass.
    double energy() const {
        if (!m_have_energy) pass(true, [](int64_t, const Eigen::MatrixXf&) {});
        return m_energy;
    }

    Eigen::MatrixXd times(const Eigen::MatrixXd& x) const override {
        Eigen::MatrixXd y = Eigen::MatrixXd::Zero(rows(), x.cols());
        pass(true, [&](int64_t j0, const Eigen::MatrixXf& blk) { y += btf::times(blk, x.middleRows(j0, blk.cols())); });
        return y;
    }
    Eigen::MatrixXd times_transposed(const Eigen::MatrixXd& y) const override {
        Eigen::MatrixXd z(cols(), y.cols());
        pass(true, [&](int64_t j0, const Eigen::MatrixXf& blk) { z.middleRows(j0, blk.cols()) = btf::times_transposed(blk, y); });
        return z;
    }
    Eigen::MatrixXd gram_rows() const override {
        Eigen::MatrixXd g = Eigen::MatrixXd::Zero(rows(), rows());
        pass(true, [&](int64_t, const Eigen::MatrixXf& blk) { g += btf::gram_of_rows(blk); });
        return g;
    }
    Eigen::MatrixXd gram_columns() const override {  // N x N: only asked when N <= P
        Eigen::MatrixXd g(cols(), cols());
        Eigen::MatrixXf a(rows(), cols());
        pass(true, [&](int64_t j0, const Eigen::MatrixXf& blk) { a.middleCols(j0, blk.cols()) = blk; });
        g = gram_of_columns(a);
        return g;
    }

  private:
    const BtfSource& m_source;
    const std::vector<int>& m_views;
    int m_block;
    StreamStats& m_stats;
    int64_t m_cols_per_view;
    Eigen::VectorXf m_mean;
    mutable double m_energy = 0;
    mutable bool m_have_energy = false;
};

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

uint64_t fit_memory_bytes(int64_t p, int64_t n, int64_t block_columns, const PcaOptions& o, int threads) {
    check_options(o);
    const uint64_t P = uint64_t(std::max<int64_t>(p, 1)), N = uint64_t(std::max<int64_t>(n, 1));
    const uint64_t c = std::min<uint64_t>(uint64_t(o.components), std::min(P, N));
    const uint64_t workers = uint64_t(std::max(threads, 1));
    const bool streamed = block_columns < n;
    const uint64_t held = streamed ? uint64_t(std::max<int64_t>(block_columns, 1)) : N;  // columns in memory
    PcaMethod method = o.method;
    if (method == PcaMethod::kAuto) method = std::min(P, N) <= uint64_t(o.gram_max_side) ? PcaMethod::kGram : PcaMethod::kRandomized;
    // Temporary double blocks converted from float, one per worker (times, sum_over).
    const uint64_t conversion = workers * 8 * uint64_t(std::min<int64_t>(kBlockElements, 4096 * int64_t(std::max(N, P))));
    uint64_t bytes = 4 * P * held + conversion;
    uint64_t factors = 8 * (P + N) * c * 2;  // V, A_c V
    switch (method) {
        case PcaMethod::kGram:
            if (N <= P) {
                factors += 8 * N * N * (kPartials + 4);  // partials, total, eigenvectors, solver
                if (streamed) bytes += 4 * P * N;         // this path reads the group whole
            } else {
                factors += 8 * P * P * (kPartials + 4) + 8 * N * c * kPartials;
            }
            break;
        case PcaMethod::kRandomized: {
            const uint64_t l = std::min<uint64_t>(c + uint64_t(o.oversampling), std::min(P, N));
            factors += 8 * (P * l * 3 + N * l * (kPartials + 4));  // Q, Y, A Q; Omega, partials, B^T, its SVD
            break;
        }
        case PcaMethod::kFullSvd:
            factors += 8 * P * N * 3 + 8 * N * N;  // the double copy, U, work; V
            break;
        case PcaMethod::kAuto:
            break;
    }
    // Results: mean, basis (P x C), weights (N x C) in float.
    return bytes + factors + 4 * (P + P * c + N * c);
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
    check_options(o);
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
        add_columns(mean, a, b, e);
        mean.segment(b, e - b) /= double(n);
        if (!mean.segment(b, e - b).allFinite()) finite = false;
        const Eigen::VectorXf mf = mean.segment(b, e - b).cast<float>();
        for (int64_t j = 0; j < n; ++j) a.col(j).segment(b, e - b) -= mf;
    });
    if (!finite) throw Error("PCA: the BTF's images hold NaN or Inf");
    g.mean = mean.cast<float>();
    fit_components(g, InCore(a), o, group_seed, [&] { return centred_energy(a, grain); });
    return g;
}

GroupPca fit_group_streamed(const BtfSource& source, const std::vector<int>& views, const PcaOptions& o,
                            uint64_t group_seed, StreamStats* stats) {
    check_options(o);
    INLIGHT_CHECK(!views.empty() && source.shape().pixel_count() >= 1);
    StreamStats local;
    StreamStats& st = stats ? *stats : local;
    Streamed a(source, views, o.stream_views, st);
    GroupPca g;
    g.views = views;
    g.pixels = static_cast<int>(a.rows());
    g.columns = static_cast<int>(a.cols());
    const int64_t p = a.rows(), n = a.cols();
    // The mean's pass: the same double additions, column by column in order, as fit_group's.
    Eigen::VectorXd sum = Eigen::VectorXd::Zero(p);
    a.pass(false, [&](int64_t, const Eigen::MatrixXf& blk) {
        parallel::for_chunks(p, block_rows(blk.cols()), [&](int64_t b, int64_t e) { add_columns(sum, blk, b, e); });
    });
    const Eigen::VectorXd mean = sum / double(n);
    if (!mean.allFinite()) throw Error("PCA: the BTF's images hold NaN or Inf");
    g.mean = mean.cast<float>();
    a.set_mean(g.mean);
    fit_components(g, a, o, group_seed, [&] { return a.energy(); });
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
        if (options.stream_views > 0 && groups[gi].size() > static_cast<size_t>(options.stream_views)) {
            StreamStats st;
            fit.pca = fit_group_streamed(source, groups[gi], options, gi, &st);
            stats.read_time_s += st.read_time_s;
            stats.fit_time_s += std::chrono::duration<double>(Clock::now() - t0).count() - st.read_time_s;
            stats.stream_passes += st.passes;
            ++stats.streamed_groups;
        } else {
            source.read_group(groups[gi], fit.centred);
            auto t1 = Clock::now();
            fit.pca = fit_group(fit.centred, groups[gi], options, gi);
            auto t2 = Clock::now();
            stats.read_time_s += std::chrono::duration<double>(t1 - t0).count();
            stats.fit_time_s += std::chrono::duration<double>(t2 - t1).count();
        }
        stats.components += fit.pca.components();
        stats.total_energy += fit.pca.total_energy;
        stats.residual_energy += fit.pca.residual_energy.back();
        sink(fit);
    }
    stats.peak_rss_bytes = peak_rss_bytes();
    return stats;
}

}  // namespace inlight::btf
