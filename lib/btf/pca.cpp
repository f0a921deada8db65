#include "btf/pca.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/QR>
#include <Eigen/SVD>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <ctime>
#include <functional>
#include <numeric>
#include <random>

#include "core/check.h"
#include "core/enum_names.h"
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

/// The Gram kernel of gram_of_columns: columns in tiles of kGramTile, rows in chunks of
/// kGramChunkRows converted to double once, each tile pair's dot products in kGramLanes lanes
/// (lane l sums rows r = l mod kGramLanes in order), the lanes then added in order. A product
/// of two floats is exact in double, so a fused multiply-add rounds as a multiply then an add
/// does: the same bits with and without FMA, on any vector width the compiler picks.
constexpr int64_t kGramTile = 4;
constexpr int64_t kGramLanes = 4;
constexpr int64_t kGramChunkRows = 256;  // 256 x 243 doubles = 486 KiB: the chunk stays in L2
typedef double Lanes __attribute__((vector_size(kGramLanes * sizeof(double))));

/// The kernel of times(): y(r, c) = sum over j in order of double(a(r, j)) x(j, c), each row on
/// its own (a lane per row), rows [r0, r1) of a strip of kTimesRows; no fused multiply-add
/// (neither target has it), so every target gives the same bits.
constexpr int64_t kTimesRows = 16;
/// Rows of A copied into a contiguous panel before sketch_times walks them (a multiple of its
/// strips). times() reads in place: its one product per group (U Sigma = A V) measured no
/// faster from a panel.
constexpr int64_t kPanelRows = 64;
typedef float Floats __attribute__((vector_size(kGramLanes * sizeof(float))));

inline __attribute__((always_inline)) void times_body(const float* a, int64_t lda, int64_t r0, int64_t r1, int64_t n,
                                                      const double* x, int64_t l, double* y, int64_t ldy) {
    constexpr int kStrips = kTimesRows / kGramLanes;
    int64_t r = r0;
    for (; r + kTimesRows <= r1; r += kTimesRows) {
        for (int64_t c0 = 0; c0 < l; c0 += 2) {
            const bool two = c0 + 1 < l;
            Lanes acc[kStrips][2];
            for (auto& s : acc) s[0] = s[1] = Lanes{0, 0, 0, 0};
            const double* x0 = x + c0 * n;
            const double* x1 = two ? x0 + n : x0;
            for (int64_t j = 0; j < n; ++j) {
                const float* col = a + j * lda + r;
                const double s0 = x0[j], s1 = x1[j];
                const Lanes b0 = {s0, s0, s0, s0}, b1 = {s1, s1, s1, s1};
                for (int k = 0; k < kStrips; ++k) {
                    Floats f;
                    std::memcpy(&f, col + k * kGramLanes, sizeof f);
                    const Lanes v = __builtin_convertvector(f, Lanes);
                    const Lanes p0 = v * b0, p1 = v * b1;
                    acc[k][0] = acc[k][0] + p0;
                    acc[k][1] = acc[k][1] + p1;
                }
            }
            for (int k = 0; k < kStrips; ++k)
                for (int i = 0; i < kGramLanes; ++i) {
                    y[c0 * ldy + r + k * kGramLanes + i] = acc[k][0][i];
                    if (two) y[(c0 + 1) * ldy + r + k * kGramLanes + i] = acc[k][1][i];
                }
        }
    }
    for (; r < r1; ++r)  // the last rows, one at a time in the same order
        for (int64_t c = 0; c < l; ++c) {
            double acc = 0;
            for (int64_t j = 0; j < n; ++j) {
                const double p = double(a[j * lda + r]) * x[c * n + j];
                acc = acc + p;
            }
            y[c * ldy + r] = acc;
        }
}

#if defined(__x86_64__) && defined(__GNUC__)
__attribute__((target("avx2"))) void times_avx2(const float* a, int64_t lda, int64_t r0, int64_t r1, int64_t n,
                                                const double* x, int64_t l, double* y, int64_t ldy) {
    times_body(a, lda, r0, r1, n, x, l, y, ldy);
}
#endif

/// A X: P x N float times N x l double, each row's sum over the columns in order.
Eigen::MatrixXd times(const Eigen::MatrixXf& a, const Eigen::MatrixXd& x) {
    INLIGHT_CHECK_EQ(a.cols(), x.rows());
    Eigen::MatrixXd y(a.rows(), x.cols());
#if defined(__x86_64__) && defined(__GNUC__)
    static const bool avx2 = __builtin_cpu_supports("avx2");
#else
    constexpr bool avx2 = false;
#endif
    parallel::for_chunks(a.rows(), 4096, [&](int64_t b, int64_t e) {
#if defined(__x86_64__) && defined(__GNUC__)
        if (avx2) return times_avx2(a.data(), a.rows(), b, e, a.cols(), x.data(), x.cols(), y.data(), y.rows());
#endif
        times_body(a.data(), a.rows(), b, e, a.cols(), x.data(), x.cols(), y.data(), y.rows());
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

/// The range finder's products in single precision (randomized method, HMT Algorithm 4.4): they
/// only choose the subspace, and a float rounding of ~1e-6 of the values moves it by as much,
/// far below the sketch's own error; the products that give the components (B^T = A^T Q and
/// U Sigma = A V) stay in double. Vectors of 8 floats, with fused multiply-adds where the CPU
/// has them; each sum over the same terms in the same order for any thread count.
typedef float Floats8 __attribute__((vector_size(8 * sizeof(float))));
constexpr int64_t kSketchStrips = 2;  // 16 rows of A X per walk across the columns
constexpr int64_t kSketchCols = 6;    // columns of X per walk: 12 accumulators and 3 more registers
                                      // (AVX2 has 16; measured best of 4x3, 4x2, 3x4, 2x4, 2x6)

/// y(r, c) += sum over j in order of a(r, j) x(j, c), rows [r0, r1), each sum carried on from
/// y's value (so a product split into blocks of columns, out of core, gives the same bits).
inline __attribute__((always_inline)) void sketch_times_body(const float* a, int64_t lda, int64_t r0, int64_t r1, int64_t n,
                                                             const float* x, int64_t ldx, int64_t l, float* y, int64_t ldy) {
    constexpr int64_t kRows = kSketchStrips * 8;
    int64_t r = r0;
    for (; r + kRows <= r1; r += kRows) {
        for (int64_t c0 = 0; c0 < l; c0 += kSketchCols) {
            const int64_t nc = std::min(kSketchCols, l - c0);
            const float* xc[kSketchCols];
            for (int64_t q = 0; q < kSketchCols; ++q) xc[q] = x + std::min(c0 + q, l - 1) * ldx;
            Floats8 acc[kSketchStrips][kSketchCols];
            for (int64_t q = 0; q < kSketchCols; ++q)
                for (int64_t k = 0; k < kSketchStrips; ++k)
                    std::memcpy(&acc[k][q], y + std::min(c0 + q, l - 1) * ldy + r + 8 * k, sizeof(Floats8));
            for (int64_t j = 0; j < n; ++j) {
                const float* col = a + j * lda + r;
                Floats8 v[kSketchStrips];
                for (int64_t k = 0; k < kSketchStrips; ++k) std::memcpy(&v[k], col + 8 * k, sizeof(Floats8));
                for (int64_t q = 0; q < kSketchCols; ++q) {
                    const float s = xc[q][j];
                    const Floats8 b = {s, s, s, s, s, s, s, s};
                    for (int64_t k = 0; k < kSketchStrips; ++k) acc[k][q] += v[k] * b;
                }
            }
            for (int64_t q = 0; q < nc; ++q)
                for (int64_t k = 0; k < kSketchStrips; ++k) std::memcpy(y + (c0 + q) * ldy + r + 8 * k, &acc[k][q], sizeof(Floats8));
        }
    }
    for (; r < r1; ++r)  // the last rows, one at a time
        for (int64_t c = 0; c < l; ++c) {
            float acc = y[c * ldy + r];
            for (int64_t j = 0; j < n; ++j) acc += a[j * lda + r] * x[c * ldx + j];
            y[c * ldy + r] = acc;
        }
}

/// out(j, c) = sum over rows [r0, r1) of a(r, j) y(r, c), in 8 lanes (lane i: rows r0 + i mod 8,
/// in order), the lanes then added in order; the rows past the last 8 one at a time.
inline __attribute__((always_inline)) void sketch_times_transposed_body(const float* a, int64_t lda, int64_t r0, int64_t r1,
                                                                        int64_t n, const float* y, int64_t ldy, int64_t l,
                                                                        double* out) {
    constexpr int64_t kCols = 6;  // columns of Y per pass
    const int64_t whole = r0 + (r1 - r0) / 8 * 8;
    for (int64_t j = 0; j < n; ++j) {
        const float* col = a + j * lda;
        for (int64_t c0 = 0; c0 < l; c0 += kCols) {
            const int64_t nc = std::min(kCols, l - c0);
            Floats8 acc[kCols] = {};
            const float* yc[kCols];
            for (int64_t q = 0; q < kCols; ++q) yc[q] = y + std::min(c0 + q, l - 1) * ldy;
            for (int64_t r = r0; r < whole; r += 8) {
                Floats8 v;
                std::memcpy(&v, col + r, sizeof v);
                for (int64_t q = 0; q < kCols; ++q) {
                    Floats8 w;
                    std::memcpy(&w, yc[q] + r, sizeof w);
                    acc[q] += v * w;
                }
            }
            for (int64_t q = 0; q < nc; ++q) {
                float sum = acc[q][0];
                for (int i = 1; i < 8; ++i) sum += acc[q][i];
                for (int64_t r = whole; r < r1; ++r) sum += col[r] * yc[q][r];
                out[(c0 + q) * n + j] += double(sum);
            }
        }
    }
}

#if defined(__x86_64__) && defined(__GNUC__)
__attribute__((target("avx2,fma"))) void sketch_times_avx2(const float* a, int64_t lda, int64_t r0, int64_t r1, int64_t n,
                                                           const float* x, int64_t ldx, int64_t l, float* y, int64_t ldy) {
    sketch_times_body(a, lda, r0, r1, n, x, ldx, l, y, ldy);
}
__attribute__((target("avx2,fma"))) void sketch_times_transposed_avx2(const float* a, int64_t lda, int64_t r0, int64_t r1,
                                                                      int64_t n, const float* y, int64_t ldy, int64_t l,
                                                                      double* out) {
    sketch_times_transposed_body(a, lda, r0, r1, n, y, ldy, l, out);
}
bool has_avx2_fma() {
    static const bool yes = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
    return yes;
}
#else
bool has_avx2_fma() { return false; }
#endif

/// y += A X in float (the range finder's), rows in fixed chunks; x: n x l with column stride
/// ldx (a block of rows of a larger X, out of core).
void sketch_times_add(const Eigen::MatrixXf& a, const float* x, int64_t ldx, int64_t l, Eigen::MatrixXf& y) {
    INLIGHT_CHECK(y.rows() == a.rows() && y.cols() == l);
    // The kernel walks a strip of rows across all N columns once per kSketchCols columns of X:
    // read in place, the columns lie a whole column apart (a power of two at Bonn size), so
    // they compete for the same cache sets and pages, and the strip came from memory on every
    // walk. Copied first into a panel of kPanelRows contiguous rows, it stays in L2.
    const int64_t n = a.cols();
    parallel::for_chunks(a.rows(), 4096, [&](int64_t b, int64_t e) {
        std::vector<float> panel(static_cast<size_t>(kPanelRows * n));
        for (int64_t r = b; r < e; r += kPanelRows) {
            const int64_t rows = std::min(kPanelRows, e - r);
            for (int64_t j = 0; j < n; ++j)
                std::memcpy(panel.data() + j * kPanelRows, a.data() + j * a.rows() + r, size_t(rows) * sizeof(float));
#if defined(__x86_64__) && defined(__GNUC__)
            if (has_avx2_fma()) {
                sketch_times_avx2(panel.data(), kPanelRows, 0, rows, n, x, ldx, l, y.data() + r, y.rows());
                continue;
            }
#endif
            sketch_times_body(panel.data(), kPanelRows, 0, rows, n, x, ldx, l, y.data() + r, y.rows());
        }
    });
}

Eigen::MatrixXd sketch_times(const Eigen::MatrixXf& a, const Eigen::MatrixXd& x) {
    INLIGHT_CHECK_EQ(a.cols(), x.rows());
    const Eigen::MatrixXf xf = x.cast<float>();
    Eigen::MatrixXf y = Eigen::MatrixXf::Zero(a.rows(), x.cols());
    sketch_times_add(a, xf.data(), xf.rows(), xf.cols(), y);
    return y.cast<double>();
}

/// A^T Y in float per block of rows (the range finder's), the blocks summed in double.
Eigen::MatrixXd sketch_times_transposed(const Eigen::MatrixXf& a, const Eigen::MatrixXd& y) {
    INLIGHT_CHECK_EQ(a.rows(), y.rows());
    const Eigen::MatrixXf yf = y.cast<float>();
    constexpr int64_t kRows = 1024;  // a block's rows of A (4 KiB a column) and of Y in L2
    return sum_over(a.rows(), kRows, a.cols(), y.cols(), [&](Eigen::MatrixXd& acc, int64_t i, int64_t n) {
#if defined(__x86_64__) && defined(__GNUC__)
        if (has_avx2_fma())
            return sketch_times_transposed_avx2(a.data(), a.rows(), i, i + n, a.cols(), yf.data(), yf.rows(), yf.cols(), acc.data());
#endif
        sketch_times_transposed_body(a.data(), a.rows(), i, i + n, a.cols(), yf.data(), yf.rows(), yf.cols(), acc.data());
    });
}

/// g (n_pad x n_pad, column-major, lower tiles) += X^T X for X: rows x n_pad column-major
/// (rows a multiple of kGramLanes).
inline __attribute__((always_inline)) void gram_chunk_body(const double* x, int64_t rows, int64_t n_pad, double* g) {
    for (int64_t j0 = 0; j0 < n_pad; j0 += kGramTile) {
        for (int64_t i0 = j0; i0 < n_pad; i0 += kGramTile) {
            Lanes acc[kGramTile][kGramTile];
            for (auto& row : acc)
                for (auto& v : row) v = Lanes{0, 0, 0, 0};
            const double* xi = x + i0 * rows;
            const double* xj = x + j0 * rows;
            for (int64_t r = 0; r < rows; r += kGramLanes) {
                Lanes vi[kGramTile], vj[kGramTile];
                for (int t = 0; t < kGramTile; ++t) {
                    std::memcpy(&vi[t], xi + t * rows + r, sizeof(Lanes));
                    std::memcpy(&vj[t], xj + t * rows + r, sizeof(Lanes));
                }
                for (int a = 0; a < kGramTile; ++a)
                    for (int b = 0; b < kGramTile; ++b) acc[a][b] += vi[a] * vj[b];
            }
            for (int a = 0; a < kGramTile; ++a)
                for (int b = 0; b < kGramTile; ++b) {
                    double sum = acc[a][b][0];
                    for (int l = 1; l < kGramLanes; ++l) sum += acc[a][b][l];
                    g[(j0 + b) * n_pad + (i0 + a)] += sum;
                }
        }
    }
}

#if defined(__x86_64__) && defined(__GNUC__)
__attribute__((target("avx512f,avx512vl,fma"))) void gram_chunk_avx512(const double* x, int64_t rows, int64_t n_pad, double* g) {
    gram_chunk_body(x, rows, n_pad, g);  // 32 vector registers: the 16 accumulators stay in them
}
__attribute__((target("avx2,fma"))) void gram_chunk_avx2(const double* x, int64_t rows, int64_t n_pad, double* g) {
    gram_chunk_body(x, rows, n_pad, g);
}
#endif

void gram_chunk(const double* x, int64_t rows, int64_t n_pad, double* g) {
#if defined(__x86_64__) && defined(__GNUC__)
    static const int level = __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") ? 2
                             : __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") ? 1 : 0;
    if (level == 2) return gram_chunk_avx512(x, rows, n_pad, g);
    if (level == 1) return gram_chunk_avx2(x, rows, n_pad, g);
#endif
    gram_chunk_body(x, rows, n_pad, g);
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

/// An orthonormal basis of Y's columns (P x l); orthonormal also when Y is rank-deficient or
/// zero. CholeskyQR2 (Fukaya et al. 2014: Q = Y R^-1 with R from the Cholesky factor of Y^T Y,
/// twice), whose products run on every core, where it is accurate: while Y's condition number
/// stays below ~1e6 (each R's diagonal within 1e-6 of its largest; the method holds to ~1e8),
/// the second pass leaves Q orthonormal to rounding, and its R must be the identity within
/// 1e-3. Otherwise (a rank-deficient sketch, low-rank data) the thin Householder Q, which runs
/// on one core: at Bonn size, k = 3, it made a group's fit 1.2-1.5x slower.
Eigen::MatrixXd orthonormal(const Eigen::MatrixXd& y) {
    auto householder = [&] {
        Eigen::HouseholderQR<Eigen::MatrixXd> qr(y);
        return Eigen::MatrixXd(qr.householderQ() * Eigen::MatrixXd::Identity(y.rows(), y.cols()));
    };
    constexpr int64_t kRows = 4096;
    Eigen::MatrixXd q = y;
    for (int pass = 0; pass < 2; ++pass) {
        const Eigen::MatrixXd g = sum_over(q.rows(), kRows, q.cols(), q.cols(), [&](Eigen::MatrixXd& acc, int64_t i, int64_t n) {
            acc.noalias() += q.middleRows(i, n).transpose() * q.middleRows(i, n);
        });
        const Eigen::LLT<Eigen::MatrixXd> llt(g);
        if (llt.info() != Eigen::Success) return householder();
        const Eigen::MatrixXd r = llt.matrixU();
        const Eigen::VectorXd d = r.diagonal().cwiseAbs();
        if (!(d.minCoeff() > 1e-6 * d.maxCoeff()) || !std::isfinite(d.maxCoeff())) return householder();
        // The second pass's R is the identity to the first pass's loss of orthogonality.
        if (pass == 1 && !((d.array() - 1.0).abs().maxCoeff() < 1e-3)) return householder();
        parallel::for_chunks(q.rows(), kRows, [&](int64_t b, int64_t e) {
            auto rows = q.middleRows(b, e - b);
            r.triangularView<Eigen::Upper>().solveInPlace<Eigen::OnTheRight>(rows);
        });
    }
    return q;
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
    /// The range finder's A_c X and A_c^T Y, where single precision suffices (sketch_times).
    virtual Eigen::MatrixXd sketch(const Eigen::MatrixXd& x) const = 0;
    virtual Eigen::MatrixXd sketch_transposed(const Eigen::MatrixXd& y) const = 0;
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
    Eigen::MatrixXd sketch(const Eigen::MatrixXd& x) const override { return btf::sketch_times(m_a, x); }
    Eigen::MatrixXd sketch_transposed(const Eigen::MatrixXd& y) const override { return btf::sketch_times_transposed(m_a, y); }

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
            Eigen::MatrixXd q = orthonormal(a.sketch(omega));
            for (int it = 0; it < o.power_iterations; ++it)
                q = orthonormal(a.sketch(orthonormal(a.sketch_transposed(q))));
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
                  o.power_iterations >= 0 && std::isfinite(o.max_rmse) && o.stream_views >= 0 &&
                  o.l1_iterations >= 0)
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
    // The range finder's products give the in-core bits: each sum of A X carries on across the
    // blocks of columns in the same order, and each entry of A^T Y lies within one block.
    Eigen::MatrixXd sketch(const Eigen::MatrixXd& x) const override {
        const Eigen::MatrixXf xf = x.cast<float>();
        Eigen::MatrixXf y = Eigen::MatrixXf::Zero(rows(), x.cols());
        pass(true, [&](int64_t j0, const Eigen::MatrixXf& blk) { sketch_times_add(blk, xf.data() + j0, xf.rows(), xf.cols(), y); });
        return y.cast<double>();
    }
    Eigen::MatrixXd sketch_transposed(const Eigen::MatrixXd& y) const override {
        Eigen::MatrixXd z(cols(), y.cols());
        pass(true, [&](int64_t j0, const Eigen::MatrixXf& blk) { z.middleRows(j0, blk.cols()) = btf::sketch_times_transposed(blk, y); });
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

constexpr EnumName<PcaMethod> kPcaMethodNames[] = {
    {PcaMethod::kAuto, "auto"},
    {PcaMethod::kGram, "gram"},
    {PcaMethod::kRandomized, "randomized"},
    {PcaMethod::kFullSvd, "full-svd"},
};

std::string to_string(PcaMethod m) { return enum_to_string(kPcaMethodNames, m); }

PcaMethod pca_method_from_string(const std::string& name) {
    return enum_from_string(kPcaMethodNames, name, "PCA method");
}

Eigen::MatrixXd gram_of_columns(const Eigen::MatrixXf& a) {
    const int64_t n = a.cols(), n_pad = (n + kGramTile - 1) / kGramTile * kGramTile;
    std::vector<double> partial;  // kPartials lower-triangular tile sums, n_pad x n_pad each
    const int64_t parts = std::max<int64_t>(1, std::min(kPartials, a.rows()));
    const int64_t per = (a.rows() + parts - 1) / parts;
    partial.assign(static_cast<size_t>(parts * n_pad * n_pad), 0.0);
    parallel::for_chunks(parts, 1, [&](int64_t b, int64_t e) {
        std::vector<double> chunk(static_cast<size_t>(kGramChunkRows * n_pad));
        for (int64_t part = b; part < e; ++part) {
            double* g = partial.data() + part * n_pad * n_pad;
            const int64_t end = std::min(a.rows(), (part + 1) * per);
            for (int64_t r0 = part * per; r0 < end; r0 += kGramChunkRows) {
                // The chunk's rows converted once, column-major, zero-padded to whole tiles and
                // to a multiple of the vector width (zeros add nothing, exactly).
                const int64_t rows = std::min(kGramChunkRows, end - r0);
                const int64_t rows_pad = (rows + kGramLanes - 1) / kGramLanes * kGramLanes;
                for (int64_t j = 0; j < n_pad; ++j) {
                    double* col = chunk.data() + j * rows_pad;
                    int64_t i = 0;
                    if (j < n)
                        for (const float* src = a.col(j).data() + r0; i < rows; ++i) col[i] = src[i];
                    for (; i < rows_pad; ++i) col[i] = 0.0;
                }
                gram_chunk(chunk.data(), rows_pad, n_pad, g);
            }
        }
    });
    Eigen::MatrixXd total(n, n);
    for (int64_t j = 0; j < n; ++j)
        for (int64_t i = j; i < n; ++i) {
            double x = 0;
            for (int64_t part = 0; part < parts; ++part) x += partial[static_cast<size_t>(part * n_pad * n_pad + j * n_pad + i)];
            total(i, j) = total(j, i) = x;
        }
    return total;
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
    if (o.l1_iterations > 0) refit_l1(a, g, o.l1_iterations);
    return g;
}

L1Refit refit_l1(Eigen::MatrixXf& a, GroupPca& g, int iterations, bool trace) {
    INLIGHT_CHECK(iterations >= 0 && a.rows() == g.pixels && a.cols() == g.columns) << iterations;
    const int64_t p = a.rows(), n = a.cols(), grain = block_rows(n);
    const int c = g.components(), k = c + 1;
    // The model of the centred group: a ~ dm 1^T + B V^T, rows of u = [dm | B] and of v = [1 | V].
    Eigen::MatrixXd u(p, k), v(n, k);
    u.col(0).setZero();
    u.rightCols(c) = g.basis.cast<double>();
    v.col(0).setOnes();
    v.rightCols(c) = g.weights.cast<double>();
    // Sums of f(residual) over all samples, row chunks combined in order.
    auto sum_all = [&](const auto& f) {
        return parallel::reduce(
            p, grain, 0.0,
            [&](int64_t b, int64_t e) {
                const Eigen::MatrixXd r = a.middleRows(b, e - b).cast<double>() - u.middleRows(b, e - b) * v.transpose();
                return r.unaryExpr(f).sum();
            },
            [](double x, double y) { return x + y; });
    };
    L1Refit out;
    const double samples = double(p) * double(n);
    out.delta = 0.1 * std::sqrt(std::max(g.residual_energy.back(), 0.0) / samples);
    const double delta = out.delta;
    auto huber = [delta](double r) {
        const double x = std::abs(r);
        return x >= delta ? x - 0.5 * delta : 0.5 * x * x / delta;
    };
    auto sae = [](double r) { return std::abs(r); };
    if (trace) out.sae_before = out.sae_after = sum_all(sae);
    // An exact fit (residual at float rounding of the data: 1e-5 relative, squared) has nothing
    // to reweight.
    if (!(g.residual_energy.back() > 1e-10 * g.total_energy) || !(delta > 0) || iterations == 0) return out;
    if (trace) out.huber.push_back(sum_all(huber));
    auto weight = [delta](double r) { return 1.0 / std::max(std::abs(r), delta); };
    // Solves (m + ridge) x = rhs; keeps `x` when the system is singular (no weight on it).
    auto solve = [](Eigen::MatrixXd& m, const Eigen::VectorXd& rhs, auto x) {
        const double ridge = 1e-12 * std::max(m.trace(), 1e-300) / double(m.rows());
        m.diagonal().array() += ridge;
        const Eigen::LDLT<Eigen::MatrixXd> ldlt(m.selfadjointView<Eigen::Lower>());
        if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().array() > 0).all()) return;
        const Eigen::VectorXd sol = ldlt.solve(rhs);
        if (sol.allFinite()) x = sol.transpose();
    };
    for (int it = 0; it < iterations; ++it) {
        // Rows of [dm | B], V fixed: (V^T W_i V) u_i = V^T W_i a_i, W_i the row's weights; the
        // products as sqrt(W_i) V blocks (one row per task: same bits for any thread count).
        parallel::for_chunks(p, std::max<int64_t>(1, grain / 8), [&](int64_t b, int64_t e) {
            Eigen::MatrixXd vw(n, k), m(k, k);
            Eigen::VectorXd ai(n), w(n);
            for (int64_t i = b; i < e; ++i) {
                ai = a.row(i).transpose().cast<double>();
                w = (ai - v * u.row(i).transpose()).unaryExpr(weight);
                vw = w.cwiseSqrt().asDiagonal() * v;
                m.setZero();
                m.selfadjointView<Eigen::Lower>().rankUpdate(vw.transpose());
                solve(m, v.transpose() * w.cwiseProduct(ai), u.row(i));
            }
        });
        if (trace) out.huber.push_back(sum_all(huber));
        if (c == 0) continue;
        // Columns of V, rows fixed: (B^T W_j B) v_j = B^T W_j (a_j - dm).
        parallel::for_chunks(n, 1, [&](int64_t b, int64_t e) {
            Eigen::MatrixXd bw(p, c), m(c, c);
            Eigen::VectorXd aj(p), w(p);
            for (int64_t j = b; j < e; ++j) {
                aj = a.col(j).cast<double>() - u.col(0);
                w = (aj - u.rightCols(c) * v.row(j).tail(c).transpose()).unaryExpr(weight);
                bw = w.cwiseSqrt().asDiagonal() * u.rightCols(c);
                m.setZero();
                m.selfadjointView<Eigen::Lower>().rankUpdate(bw.transpose());
                solve(m, u.rightCols(c).transpose() * w.cwiseProduct(aj), v.row(j).tail(c));
            }
        });
        if (trace) out.huber.push_back(sum_all(huber));
    }
    if (trace) out.sae_after = sum_all(sae);

    // Back to the GroupPca form. B V^T = B R^T Q^T (V = Q R) = (B R^T W) (Q W)^T with W the
    // eigenvectors of (B R^T)^T (B R^T), largest first: V orthonormal, columns by energy.
    if (c > 0) {
        const Eigen::HouseholderQR<Eigen::MatrixXd> qr(v.rightCols(c));
        const Eigen::MatrixXd q = qr.householderQ() * Eigen::MatrixXd::Identity(n, c);
        const Eigen::MatrixXd r = qr.matrixQR().topRows(c).triangularView<Eigen::Upper>();
        const Eigen::MatrixXd br = u.rightCols(c) * r.transpose();
        const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(br.transpose() * br);
        const Eigen::MatrixXd w = eig.eigenvectors().rowwise().reverse();
        g.basis = (br * w).cast<float>();
        g.weights = (q * w).cast<float>();
    }
    const Eigen::VectorXf dm = u.col(0).cast<float>();
    g.mean += dm;
    parallel::for_chunks(p, grain, [&](int64_t b, int64_t e) {
        for (int64_t j = 0; j < n; ++j) a.col(j).segment(b, e - b) -= dm.segment(b, e - b);
    });
    // residual_energy[i + 1] = residual_energy[i] - (2 b_i^T A_c v_i - |b_i|^2) (V orthonormal).
    g.total_energy = centred_energy(a, grain);
    g.residual_energy.assign(1, g.total_energy);
    if (c > 0) {
        const Eigen::MatrixXd av = times(a, g.weights.cast<double>());
        for (int i = 0; i < c; ++i) {
            const Eigen::VectorXd bi = g.basis.col(i).cast<double>();
            g.residual_energy.push_back(std::max(0.0, g.residual_energy.back() - (2 * bi.dot(av.col(i)) - bi.squaredNorm())));
        }
    }
    return out;
}

GroupPca fit_group_streamed(const BtfSource& source, const std::vector<int>& views, const PcaOptions& o,
                            uint64_t group_seed, StreamStats* stats) {
    check_options(o);
    INLIGHT_CHECK(!views.empty() && source.shape().pixel_count() >= 1);
    if (o.l1_iterations > 0) throw Error("PCA: the L1 refit needs the group in memory, not streamed");
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
    const auto groups = view_groups(source.shape().views, options.view_group_size, options.grouping);
    CompressStats stats;
    stats.groups = static_cast<int>(groups.size());
    // One group's matrix, reused: allocated afresh per group (a few hundred MiB at Bonn size),
    // its pages were faulted in again for every group, a tenth of a run's time in the kernel.
    Eigen::MatrixXf buffer;
    for (size_t gi = 0; gi < groups.size(); ++gi) {
        GroupFit fit;
        fit.index = static_cast<int>(gi);
        fit.count = stats.groups;
        auto t0 = Clock::now();
        const std::clock_t c0 = std::clock();
        auto cpu_since = [](std::clock_t c) { return double(std::clock() - c) / CLOCKS_PER_SEC; };
        if (options.stream_views > 0 && groups[gi].size() > static_cast<size_t>(options.stream_views)) {
            buffer = Eigen::MatrixXf();  // a streamed group's memory plan holds no whole group
            StreamStats st;
            fit.pca = fit_group_streamed(source, groups[gi], options, gi, &st);
            stats.read_time_s += st.read_time_s;
            stats.fit_time_s += std::chrono::duration<double>(Clock::now() - t0).count() - st.read_time_s;
            stats.fit_cpu_s += cpu_since(c0);  // reading and fitting interleave: counted as fitting
            stats.stream_passes += st.passes;
            ++stats.streamed_groups;
        } else {
            fit.centred.swap(buffer);
            source.read_group(groups[gi], fit.centred);
            auto t1 = Clock::now();
            const std::clock_t c1 = std::clock();
            fit.pca = fit_group(fit.centred, groups[gi], options, gi);
            auto t2 = Clock::now();
            stats.read_time_s += std::chrono::duration<double>(t1 - t0).count();
            stats.fit_time_s += std::chrono::duration<double>(t2 - t1).count();
            stats.read_cpu_s += double(c1 - c0) / CLOCKS_PER_SEC;
            stats.fit_cpu_s += cpu_since(c1);
        }
        stats.components += fit.pca.components();
        stats.total_energy += fit.pca.total_energy;
        stats.residual_energy += fit.pca.residual_energy.back();
        sink(fit);
        if (fit.centred.size() > buffer.size()) buffer.swap(fit.centred);
    }
    stats.peak_rss_bytes = peak_rss_bytes();
    return stats;
}

}  // namespace inlight::btf
