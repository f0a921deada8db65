#include "render/sampling.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/check.h"
#include "core/conventions.h"

namespace inlight::render {

Rng::Rng(uint64_t seed, uint64_t pixel, uint64_t sample) {
    const uint64_t h = mix64(mix64(mix64(seed) ^ pixel) ^ (sample * 0xd1342543de82ef95ull));
    m_inc = (mix64(h ^ 0x5851f42d4c957f2dull) << 1u) | 1u;
    m_state = 0;
    next_u32();
    m_state += h;
    next_u32();
}

uint32_t Rng::next_u32() {
    const uint64_t old = m_state;
    m_state = old * 6364136223846793005ull + m_inc;
    const auto xorshifted = static_cast<uint32_t>(((old >> 18u) ^ old) >> 27u);
    const auto rot = static_cast<uint32_t>(old >> 59u);
    return (xorshifted >> rot) | (xorshifted << ((~rot + 1u) & 31u));
}

Distribution1D::Distribution1D(std::vector<double> weights) : m_weights(std::move(weights)) {
    const size_t n = m_weights.size();
    m_cdf.assign(n + 1, 0.0);
    for (size_t i = 0; i < n; ++i) {
        INLIGHT_CHECK(std::isfinite(m_weights[i]) && m_weights[i] >= 0)
            << "weight " << i << " = " << m_weights[i];
        m_cdf[i + 1] = m_cdf[i] + m_weights[i];
    }
    m_total = m_cdf[n];
    if (m_total > 0) {
        for (auto& c : m_cdf) c /= m_total;
        // The last bin with positive weight ends at exactly 1, so u < 1 never selects a
        // zero-weight bin at the end.
        for (size_t i = n; i > 0; --i) {
            m_cdf[i] = 1.0;
            if (m_weights[i - 1] > 0) break;
        }
    }
}

int Distribution1D::sample(double u, double* u_remapped) const {
    INLIGHT_DCHECK(m_total > 0);
    // Largest i with cdf[i] <= u; zero-width bins are skipped because their cdf[i + 1] equals
    // cdf[i] <= u.
    const auto it = std::upper_bound(m_cdf.begin(), m_cdf.end(), u);
    int i = static_cast<int>(it - m_cdf.begin()) - 1;
    i = std::clamp(i, 0, size() - 1);
    if (u_remapped) {
        const double width = m_cdf[static_cast<size_t>(i) + 1] - m_cdf[static_cast<size_t>(i)];
        double r = width > 0 ? (u - m_cdf[static_cast<size_t>(i)]) / width : 0.5;
        *u_remapped = std::clamp(r, 0.0, std::nextafter(1.0, 0.0));
    }
    return i;
}

Distribution2D::Distribution2D(const std::vector<double>& weights, int cols, int rows)
    : m_cols(cols) {
    INLIGHT_CHECK_EQ(weights.size(), static_cast<size_t>(cols) * rows);
    std::vector<double> row_totals(static_cast<size_t>(rows));
    m_cond.reserve(static_cast<size_t>(rows));
    for (int r = 0; r < rows; ++r) {
        const auto begin = weights.begin() + static_cast<std::ptrdiff_t>(r) * cols;
        m_cond.emplace_back(std::vector<double>(begin, begin + cols));
        row_totals[static_cast<size_t>(r)] = m_cond.back().total();
    }
    m_rows = Distribution1D(std::move(row_totals));
}

void Distribution2D::sample(const Eigen::Vector2d& u, int* col, int* row,
                            Eigen::Vector2d* u_in_cell) const {
    double ur = 0, uc = 0;
    *row = m_rows.sample(u[1], &ur);
    *col = m_cond[static_cast<size_t>(*row)].sample(u[0], &uc);
    if (u_in_cell) *u_in_cell = {uc, ur};
}

double Distribution2D::pmf(int col, int row) const {
    return m_rows.pmf(row) * m_cond[static_cast<size_t>(row)].pmf(col);
}

Eigen::Vector3d sample_cosine_hemisphere(const Eigen::Vector2d& u) {
    const double r = std::sqrt(u[0]);
    const double phi = 2.0 * kPi * u[1];
    return {r * std::cos(phi), r * std::sin(phi), std::sqrt(std::max(0.0, 1.0 - u[0]))};
}

Eigen::Vector3d sample_uniform_sphere(const Eigen::Vector2d& u) {
    const double z = 1.0 - 2.0 * u[0];
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    const double phi = 2.0 * kPi * u[1];
    return {r * std::cos(phi), r * std::sin(phi), z};
}

double gamma_q(double a, double x) {
    INLIGHT_CHECK(a > 0 && x >= 0) << "a = " << a << ", x = " << x;
    if (x == 0) return 1.0;
    const double log_prefix = -x + a * std::log(x) - std::lgamma(a);
    if (x < a + 1.0) {
        // Series for P(a, x) (Numerical Recipes 6.2.5).
        double term = 1.0 / a, sum = term;
        for (int n = 1; n < 10000; ++n) {
            term *= x / (a + n);
            sum += term;
            if (std::abs(term) < std::abs(sum) * 1e-16) break;
        }
        return std::clamp(1.0 - sum * std::exp(log_prefix), 0.0, 1.0);
    }
    // Continued fraction for Q(a, x) by the modified Lentz method (NR 6.2.7).
    const double tiny = 1e-300;
    double b = x + 1.0 - a, c = 1.0 / tiny, d = 1.0 / b, h = d;
    for (int i = 1; i < 10000; ++i) {
        const double an = -i * (i - a);
        b += 2.0;
        d = an * d + b;
        if (std::abs(d) < tiny) d = tiny;
        c = b + an / c;
        if (std::abs(c) < tiny) c = tiny;
        d = 1.0 / d;
        const double delta = d * c;
        h *= delta;
        if (std::abs(delta - 1.0) < 1e-16) break;
    }
    return std::clamp(std::exp(log_prefix) * h, 0.0, 1.0);
}

double chi2_survival(double x, int dof) {
    INLIGHT_CHECK_GT(dof, 0);
    return gamma_q(0.5 * dof, 0.5 * std::max(0.0, x));
}

Chi2Result chi2_test(const std::vector<double>& observed, const std::vector<double>& expected,
                     double min_expected) {
    INLIGHT_CHECK_EQ(observed.size(), expected.size());
    Chi2Result r;
    double pooled_obs = 0, pooled_exp = 0;
    int bins = 0;
    for (size_t i = 0; i < observed.size(); ++i) {
        if (expected[i] <= 0 && observed[i] > 0) {
            r.statistic = std::numeric_limits<double>::infinity();
            r.p_value = 0;
            r.dof = 1;
            return r;
        }
        if (expected[i] < min_expected) {
            pooled_obs += observed[i];
            pooled_exp += expected[i];
            ++r.pooled_bins;
            continue;
        }
        const double diff = observed[i] - expected[i];
        r.statistic += diff * diff / expected[i];
        ++bins;
    }
    if (pooled_exp > 0) {
        const double diff = pooled_obs - pooled_exp;
        r.statistic += diff * diff / pooled_exp;
        ++bins;
    } else if (pooled_obs > 0) {
        r.statistic = std::numeric_limits<double>::infinity();
    }
    r.dof = std::max(1, bins - 1);
    r.p_value = std::isfinite(r.statistic) ? chi2_survival(r.statistic, r.dof) : 0.0;
    return r;
}

}  // namespace inlight::render
