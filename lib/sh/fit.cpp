#include "sh/fit.h"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <limits>
#include <vector>

#include "core/check.h"
#include "core/error.h"
#include "core/parallel.h"

namespace inlight::sh {
namespace {

constexpr int64_t kGrain = 16384;  // samples per chunk; fixed so sums do not depend on threads

}  // namespace

Eigen::MatrixXd project(int sh_bands, const SampleSet& samples) {
    const int n = count(sh_bands);
    const int channels = samples.channels();
    using Acc = Eigen::MatrixXd;
    return parallel::reduce(
        samples.size(), kGrain, Acc(Acc::Zero(n, channels)),
        [&](int64_t begin, int64_t end) {
            Acc acc = Acc::Zero(n, channels);
            std::vector<double> y(static_cast<size_t>(n)), f(static_cast<size_t>(channels));
            Eigen::Vector3d dir;
            double w;
            for (int64_t i = begin; i < end; ++i) {
                if (!samples.sample(i, dir, w, f.data())) continue;
                eval(sh_bands, dir, y.data());
                for (int c = 0; c < channels; ++c) {
                    const double wf = w * f[static_cast<size_t>(c)];
                    for (int k = 0; k < n; ++k) acc(k, c) += wf * y[static_cast<size_t>(k)];
                }
            }
            return acc;
        },
        [](Acc a, const Acc& b) { return Acc(a + b); });
}

std::vector<FitResult> fit_least_squares_path(int sh_bands, const SampleSet& samples,
                                              const std::vector<double>& lambdas) {
    const int n = count(sh_bands);
    const int channels = samples.channels();
    struct Normal {
        Eigen::MatrixXd gram, rhs;
        double weight = 0, ff = 0;
        int64_t used = 0;
    };
    Normal zero{Eigen::MatrixXd::Zero(n, n), Eigen::MatrixXd::Zero(n, channels)};
    const Normal normal = parallel::reduce(
        samples.size(), kGrain, zero,
        [&](int64_t begin, int64_t end) {
            Normal acc = zero;
            Eigen::VectorXd y(n);
            std::vector<double> f(static_cast<size_t>(channels));
            Eigen::Vector3d dir;
            double w;
            for (int64_t i = begin; i < end; ++i) {
                if (!samples.sample(i, dir, w, f.data())) continue;
                eval(sh_bands, dir, y.data());
                acc.gram.selfadjointView<Eigen::Lower>().rankUpdate(y, w);
                for (int c = 0; c < channels; ++c) {
                    acc.rhs.col(c) += (w * f[static_cast<size_t>(c)]) * y;
                    acc.ff += w * f[static_cast<size_t>(c)] * f[static_cast<size_t>(c)];
                }
                acc.weight += w;
                ++acc.used;
            }
            return acc;
        },
        [](Normal a, const Normal& b) {
            a.gram += b.gram;
            a.rhs += b.rhs;
            a.weight += b.weight;
            a.ff += b.ff;
            a.used += b.used;
            return a;
        });
    if (normal.used == 0) throw Error("SH least-squares fit: no observed sample");

    Eigen::MatrixXd gram = normal.gram.selfadjointView<Eigen::Lower>();
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> plain(gram, Eigen::EigenvaluesOnly);
    const double ev_max = plain.eigenvalues().maxCoeff();
    const double ev_min = plain.eigenvalues().minCoeff();

    FitResult base;
    base.samples_used = normal.used;
    base.observed_solid_angle_sr = normal.weight;
    base.gram_condition = ev_min > 0 ? ev_max / ev_min : std::numeric_limits<double>::infinity();

    std::vector<FitResult> results;
    for (const double lambda : lambdas) {
        FitResult result = base;
        result.lambda = lambda;

        Eigen::MatrixXd a = gram;
        for (int l = 0; l < sh_bands; ++l) {
            const double penalty = lambda * ev_max * double(l) * (l + 1) * double(l) * (l + 1);
            for (int m = -l; m <= l; ++m) a(index(l, m), index(l, m)) += penalty;
        }
        Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(a);
        const Eigen::VectorXd ev = eig.eigenvalues();
        if (ev.minCoeff() <= ev.maxCoeff() * 1e-14) {
            results.push_back(result);  // singular: coeffs left empty
            continue;
        }
        result.regularised_condition = ev.maxCoeff() / ev.minCoeff();
        const Eigen::MatrixXd& v = eig.eigenvectors();
        result.coeffs = v * (ev.cwiseInverse().asDiagonal() * (v.transpose() * normal.rhs));

        // Weighted residual from the normal equations: sum w (y.c - f)^2 = c'Gc - 2 c'b + sum w
        // f^2.
        double r2 = normal.ff;
        for (int c = 0; c < channels; ++c) {
            const Eigen::VectorXd col = result.coeffs.col(c);
            r2 += col.dot(gram * col) - 2.0 * col.dot(normal.rhs.col(c));
        }
        result.weighted_residual_rms = std::sqrt(std::max(0.0, r2) / (normal.weight * channels));
        results.push_back(result);
    }
    return results;
}

FitResult fit_least_squares(int sh_bands, const SampleSet& samples, const FitOptions& options) {
    FitResult result = fit_least_squares_path(sh_bands, samples, {options.lambda}).front();
    if (result.coeffs.size() == 0) {
        throw Error(str("SH least-squares fit: the observed directions do not determine ",
                        count(sh_bands), " coefficients; use fewer bands or lambda > 0"));
    }
    return result;
}

}  // namespace inlight::sh
