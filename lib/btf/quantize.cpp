#include "btf/quantize.h"

#include <algorithm>
#include <cmath>

#include "core/check.h"

namespace inlight::btf {

Quantized8 quantize8(const float* values, int64_t n, float min_step) {
    INLIGHT_CHECK(min_step >= 0 && std::isfinite(min_step)) << min_step;
    Quantized8 q;
    q.codes.resize(static_cast<size_t>(n));
    if (n == 0) return q;
    float lo = values[0], hi = values[0];
    for (int64_t i = 0; i < n; ++i) {
        INLIGHT_CHECK(std::isfinite(values[i])) << "value " << i;
        lo = std::min(lo, values[i]);
        hi = std::max(hi, values[i]);
    }
    q.offset = lo;
    q.scale = (hi - lo) / 255.0f;
    if (q.scale > 0) q.scale = std::max(q.scale, min_step);
    for (int64_t i = 0; i < n; ++i) {
        const float code = q.scale > 0 ? (values[i] - lo) / q.scale : 0.0f;
        q.codes[static_cast<size_t>(i)] = static_cast<uint8_t>(std::clamp(std::lround(code), 0L, 255L));
    }
    return q;
}

StoredGroup store_ours(const GroupPca& pca) {
    StoredGroup s;
    auto through = [](const float* v, int64_t n, float* out) {
        const Quantized8 q = quantize8(v, n);
        for (int64_t i = 0; i < n; ++i) out[i] = q.value(i);
    };
    s.mean.resize(pca.pixels);
    through(pca.mean.data(), pca.pixels, s.mean.data());
    s.basis.resize(pca.pixels, pca.components());
    for (int c = 0; c < pca.components(); ++c)
        through(pca.basis.col(c).data(), pca.pixels, s.basis.col(c).data());
    s.weights = pca.weights;
    return s;
}

double thesis_factor(double max_abs) {
    if (!(max_abs > 0)) return 1.0;
    return std::max(1.0, std::pow(10.0, std::floor(-std::log10(max_abs))));
}

ThesisGroup pack_thesis(const GroupPca& pca, int c) {
    INLIGHT_CHECK(c >= 0 && c <= pca.components()) << c;
    ThesisGroup t;
    const int64_t P = pca.pixels, N = pca.columns;
    t.mean_codes.resize(size_t(P));
    for (int64_t p = 0; p < P; ++p)
        t.mean_codes[size_t(p)] = static_cast<uint8_t>(std::clamp(std::lround(double(pca.mean[p]) * 255.0), 0L, 255L));
    // U = basis / sigma per column (the basis is U Sigma), V = the weights.
    std::vector<double> sigma(size_t(c), 0.0);
    double max_u = 0, max_v = 0;
    for (int i = 0; i < c; ++i) {
        sigma[size_t(i)] = pca.basis.col(i).cast<double>().norm();
        if (sigma[size_t(i)] > 0) max_u = std::max(max_u, double(pca.basis.col(i).cwiseAbs().maxCoeff()) / sigma[size_t(i)]);
        max_v = std::max(max_v, double(pca.weights.col(i).cwiseAbs().maxCoeff()));
    }
    t.factor_u = thesis_factor(max_u);
    t.factor_v = thesis_factor(max_v);
    auto code8 = [](double x) {  // f(x) = (x + 1) / 2 on 8 bits
        return static_cast<uint8_t>(std::clamp(std::round((x + 1.0) * 0.5 * 255.0), 0.0, 255.0));
    };
    for (int i = 0; i < c; ++i) {
        const double s = sigma[size_t(i)];
        // a4a3a2a1 in 1/255 units; more digits where four do not hold it (the thesis: "if the
        // value of Sigma exceeds the four digit number, then it is possible to adapt this
        // technique further in the similar manner"), counted.
        const double digits = std::round(s / (t.factor_u * t.factor_v) * 255.0);
        if (digits > 9999) ++t.sigma_overflows;
        t.sigma_digits.push_back(static_cast<int64_t>(digits));
        std::vector<uint8_t> u(static_cast<size_t>(P)), v(static_cast<size_t>(N));
        for (int64_t p = 0; p < P; ++p) u[size_t(p)] = code8(s > 0 ? t.factor_u * double(pca.basis(p, i)) / s : 0.0);
        for (int64_t j = 0; j < N; ++j) v[size_t(j)] = code8(t.factor_v * double(pca.weights(j, i)));
        t.u_codes.push_back(std::move(u));
        t.v_codes.push_back(std::move(v));
    }
    return t;
}

StoredGroup ThesisGroup::decoded() const {
    StoredGroup s;
    const int64_t P = int64_t(mean_codes.size());
    const int c = int(u_codes.size());
    s.mean.resize(P);
    for (int64_t p = 0; p < P; ++p) s.mean[p] = kMeanScale * mean_codes[size_t(p)];
    s.basis.resize(P, c);
    s.weights.resize(c > 0 ? int64_t(v_codes[0].size()) : 0, c);
    for (int i = 0; i < c; ++i) {
        const float scale = basis_scale(i), offset = basis_offset(i);
        for (int64_t p = 0; p < P; ++p) s.basis(p, i) = offset + scale * u_codes[size_t(i)][size_t(p)];
        for (int64_t j = 0; j < s.weights.rows(); ++j) s.weights(j, i) = kWeightOffset + kWeightScale * v_codes[size_t(i)][size_t(j)];
    }
    return s;
}

}  // namespace inlight::btf
