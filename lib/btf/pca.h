// btf/pca.h: PCA compression of a BTF per group of k neighbouring view directions (the BTF
// thesis, section 4.3: k = 1 is PCA RF, k = n_views one PCA for the whole BTF).
//
// A group's matrix A (P pixels x N = 3 * n_lights * views columns, layout in btf/dataset.h) is
// mean-centred per pixel, A = m 1^T + A_c, and A_c is approximated by its C leading principal
// components: A ~ L R with L = [m | U Sigma] (P x (C + 1)) and R = [1; V^T] ((C + 1) x N), the
// thesis' equation for L and R (section 4.3.2). U Sigma is computed as A_c V, the projection of
// the data on the chosen right singular vectors, so the residual of any C is exactly
// ||A_c||^2 - ||A_c V_C||^2 (V orthonormal), whatever method found V.
//
// Methods (PcaMethod): the eigendecomposition of the Gram matrix of the short side in double
// (A_c^T A_c when N <= P, A_c A_c^T otherwise) when that side is at most gram_max_side; above,
// the randomized SVD of Halko, Martinsson and Tropp (2011, Algorithms 4.4 and 5.1: Gaussian
// test matrix, q power iterations re-orthonormalised by QR, SVD of the small B = Q^T A_c).
// A full SVD (Eigen BDCSVD) is the accuracy oracle of the tests and the benchmark baseline.
//
// Products run over fixed row chunks combined in a fixed order, so results are bit-identical
// for any thread count. Values are linear float (linear_srgb); sums are in double.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "btf/dataset.h"

namespace inlight::btf {

enum class PcaMethod {
    kAuto,        ///< kGram when the short side <= gram_max_side, else kRandomized
    kGram,        ///< eigendecomposition of the short side's Gram matrix (double)
    kRandomized,  ///< Halko-Martinsson-Tropp randomized SVD
    kFullSvd,     ///< Eigen::BDCSVD of the whole centred matrix (double): oracle and baseline
};
std::string to_string(PcaMethod m);
/// "auto", "gram", "randomized", "full-svd". Throws UsageError naming the value otherwise.
PcaMethod pca_method_from_string(const std::string& name);

struct PcaOptions {
    int view_group_size = 3;  ///< k: neighbouring views per group (>= 1)
    ViewGrouping grouping = ViewGrouping::kNeighbours;  ///< which k views form a group (view_groups)
    int components = 8;       ///< C, or the most components the error budget may choose (>= 1)
    /// Error budget: the RMS error of the unquantised reconstruction per sample (linear_srgb
    /// units, over all pixels, lights, views and channels of a group); each group keeps the
    /// fewest components, at most `components`, that meet it. < 0: off (every group keeps
    /// `components`).
    double max_rmse = -1;
    PcaMethod method = PcaMethod::kAuto;
    /// kAuto: the largest short side solved through its Gram matrix. 512: at C = 8 on Bonn-size
    /// groups the Gram path is 1.7x faster than the randomized SVD at 243 columns and 1.7x
    /// slower at 729 (docs/benchmarks.md).
    int gram_max_side = 512;
    int oversampling = 10;     ///< randomized: extra test vectors p (HMT section 4.2)
    int power_iterations = 2;  ///< randomized: q (HMT Algorithm 4.4)
    uint64_t seed = 1;         ///< randomized: test matrices (each group mixes in its index)
    /// The norm of the fit. 0: least squares (the PCA). n > 0: the PCA's C components are then
    /// refitted towards the least absolute error (L1, the norm of the thesis' MAE) by n
    /// iterations of iteratively reweighted least squares (refit_l1). Needs the group in memory.
    int l1_iterations = 0;
    /// Out of core: a group of more than this many views is never held whole; every product
    /// the method needs is one pass over the BTF reading this many views at a time
    /// (fit_group_streamed). 0 = off (each group is read into memory).
    int stream_views = 0;
};

/// The PCA of one view group.
struct GroupPca {
    std::vector<int> views;  ///< the group's view indices, sorted
    PcaMethod method = PcaMethod::kGram;  ///< the method that ran (kAuto resolved)
    int pixels = 0;                       ///< P
    int columns = 0;                      ///< N = 3 * n_lights * views.size()
    Eigen::VectorXf mean;                 ///< m: per-pixel mean over the group's columns, P
    Eigen::MatrixXf basis;                ///< U Sigma = A_c V, P x C (the images of L after m)
    Eigen::MatrixXf weights;              ///< V, N x C (R's rows after the first are V^T)
    double total_energy = 0;  ///< ||A_c||_F^2 (squared linear units)
    /// residual_energy[c] = ||A_c - (U Sigma)_c V_c^T||_F^2 after the first c components,
    /// c = 0..C (residual_energy[0] = total_energy). Non-increasing for the PCA; >= 0 (after an
    /// L1 refit it is the refitted model's, which need not fall with every component).
    std::vector<double> residual_energy;

    int components() const { return static_cast<int>(basis.cols()); }
    /// Energy ||(U Sigma)_c||^2 = sigma_c^2 that component c (0-based) removes.
    double component_energy(int c) const { return residual_energy[c] - residual_energy[c + 1]; }
    /// RMS error per sample of the unquantised reconstruction with c components.
    double rmse(int c) const;
    /// m 1^T + (U Sigma)_c V_c^T with the first c components (P x N).
    /// Precondition: 0 <= c <= components() (checked).
    Eigen::MatrixXf reconstruct(int c) const;
};

/// Fits the PCA of one group's matrix `a` (P x N, from BtfSource::read_group), centring `a` in
/// place (on return a = A_c). C is min(options.components, P, N), then cut by the error budget.
/// `group_seed` seeds the randomized method's test matrix. With options.l1_iterations > 0 the
/// PCA is then refitted by refit_l1 (C stays the one the PCA and the error budget chose). Components beyond the data's rank
/// come out as zero columns of `basis` (never NaN). Throws Error if `a` holds NaN or Inf.
/// Precondition: options in range (checked).
GroupPca fit_group(Eigen::MatrixXf& a, const std::vector<int>& views, const PcaOptions& options,
                   uint64_t group_seed);

/// What refit_l1 did: the objectives over the group's samples, before and after (only with
/// `trace`; otherwise only delta is set).
struct L1Refit {
    double delta = 0;       ///< the IRLS floor: 0.1 x the PCA's RMS residual (model units)
    double sae_before = 0;  ///< sum of |residual| of the PCA
    double sae_after = 0;   ///< sum of |residual| of the refitted model
    /// sum of the Huber function of the residual (|r| - delta / 2 above delta, r^2 / (2 delta)
    /// below) after 0, 1, ... half-steps: the objective each half-step cannot raise.
    std::vector<double> huber;
};

/// Refits a group's model towards the least absolute error, the norm of the MAE figures:
/// `iterations` rounds of iteratively reweighted least squares with weights 1 / max(|r|, delta),
/// each round solving the rows of [dm | U Sigma] with V fixed, then the columns of V with the
/// rows fixed (a weighted least-squares problem per row and per column, C + 1 or C unknowns).
/// Each half-step minimises a quadratic majorant of the Huber objective (L1.huber), so that
/// objective never rises; as delta -> 0 it is the L1 norm. Starts from the PCA in `g` (fit_group's
/// result), with `a` the group centred by g.mean. Afterwards the product is put back in the
/// GroupPca form: V orthonormal (QR of V, then the eigenvectors of the small Gram matrix of the
/// rotated basis), components ordered by energy, the mean m + dm, `a` re-centred by it, and
/// residual_energy the refitted model's squared errors. Every row's and column's sums run in a
/// fixed order: the same bits for any thread count. A group the PCA fits exactly (residual
/// energy at most 1e-10 of the centred energy: float rounding) is unchanged. `trace`: also sum
/// the objectives of L1Refit (a pass over the group each; fit_group does not ask for them).
L1Refit refit_l1(Eigen::MatrixXf& a, GroupPca& g, int iterations, bool trace = false);

/// What an out-of-core fit did.
struct StreamStats {
    int passes = 0;            ///< passes over the group's images (each reads every image once)
    double read_time_s = 0;    ///< reading and decoding in all passes
    uint64_t block_bytes = 0;  ///< the largest block of views held at once (floats)
};

/// fit_group without holding the group: A (P x N) is read `options.stream_views` views at a time
/// (at least 1), once for the mean and once per product: 4 passes for the Gram path (short side
/// = pixels: A_c A_c^T accumulated block by block, then A_c^T U and A_c V), 4 + 2q for the
/// randomized SVD (q = power_iterations). Memory: one block of views plus the P x l and N x l
/// factors (l = C + oversampling) or, for the Gram path, the P x P Gram matrix. The arithmetic
/// is fit_group's: the mean and the centred blocks are the same floats, only the sums over
/// blocks of views run in another order, so the result equals fit_group's to double rounding
/// (then float storage). A group whose N <= P takes the Gram path over its columns and is read
/// whole (it is at most gram_max_side columns); kFullSvd is not available (checked).
/// Throws Error on NaN/Inf or from reading.
GroupPca fit_group_streamed(const BtfSource& source, const std::vector<int>& views, const PcaOptions& options,
                            uint64_t group_seed, StreamStats* stats = nullptr);

/// An upper estimate of the memory fit_group (block_columns >= n: the group held, its P x N
/// floats included) or fit_group_streamed (block_columns < n: one block of that many columns
/// held at a time) allocates for a group of `p` pixels x `n` columns with `threads` workers:
/// the data, the method's double factors and partial sums (kAuto resolved as fit_components
/// does), the per-worker temporary blocks and the results. Not the process's own base.
uint64_t fit_memory_bytes(int64_t p, int64_t n, int64_t block_columns, const PcaOptions& options, int threads);

/// What compress_btf hands to its sink for each group, then frees.
struct GroupFit {
    int index = 0;           ///< group number, in view_groups() order
    int count = 0;           ///< number of groups
    GroupPca pca;            ///< the fit
    /// A_c = A - m 1^T, P x N (the original is centred + mean); empty when the group was fitted
    /// out of core (PcaOptions::stream_views).
    Eigen::MatrixXf centred;
};

/// Totals of a compress_btf run.
struct CompressStats {
    int groups = 0;
    int64_t components = 0;       ///< sum of C over groups
    double total_energy = 0;      ///< sum over groups of ||A_c||^2
    double residual_energy = 0;   ///< sum over groups of the unquantised residual
    double read_time_s = 0;       ///< reading and decoding images
    double fit_time_s = 0;        ///< PCA
    double read_cpu_s = 0;        ///< CPU time of all the process's threads while reading (std::clock)
    double fit_cpu_s = 0;         ///< CPU time of all the process's threads while fitting
    int stream_passes = 0;        ///< passes over the images of groups fitted out of core
    int streamed_groups = 0;      ///< groups fitted out of core
    uint64_t peak_rss_bytes = 0;  ///< the process's peak resident memory after the run
};

/// Compresses `source` view group by view group (view_groups(views, k)): reads one group,
/// fits it, calls sink(fit) and frees it before reading the next, so memory holds one group
/// (plus what the sink keeps), or, with options.stream_views, one block of views of a larger
/// group. Groups run in order; the sink runs on the calling thread.
/// Throws Error from reading (naming the file) or fitting.
CompressStats compress_btf(const BtfSource& source, const PcaOptions& options,
                           const std::function<void(GroupFit&)>& sink);

/// A^T A (N x N, double) of a float matrix, summed over fixed row chunks in a fixed order.
Eigen::MatrixXd gram_of_columns(const Eigen::MatrixXf& a);

}  // namespace inlight::btf
