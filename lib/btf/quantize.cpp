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

StoredGroup store_thesis(const GroupPca& pca, int c, int* sigma_overflows,
                         std::vector<std::vector<uint8_t>>* u_codes) {
    INLIGHT_CHECK(c >= 0 && c <= pca.components()) << c;
    StoredGroup s;
    int overflows = 0;
    // The mean as an 8-bit image of the data's codes.
    s.mean = pca.mean.unaryExpr([](float v) { return std::clamp(std::round(v * 255.0f), 0.0f, 255.0f) / 255.0f; });
    s.basis.resize(pca.pixels, c);
    s.weights.resize(pca.columns, c);
    auto code8 = [](double x) { return std::clamp(std::round((x + 1.0) * 0.5 * 255.0), 0.0, 255.0); };
    auto to8 = [&](double x) { return code8(x) / 255.0 * 2.0 - 1.0; };  // f(x) = (x + 1) / 2
    if (u_codes) u_codes->assign(static_cast<size_t>(c), std::vector<uint8_t>(static_cast<size_t>(pca.pixels)));
    for (int i = 0; i < c; ++i) {
        const double sigma = pca.basis.col(i).cast<double>().norm();
        const Eigen::VectorXd u = sigma > 0 ? Eigen::VectorXd(pca.basis.col(i).cast<double>() / sigma)
                                            : Eigen::VectorXd::Zero(pca.pixels);
        const Eigen::VectorXd v = pca.weights.col(i).cast<double>();
        const double fu = thesis_factor(u.cwiseAbs().maxCoeff());
        const double fv = thesis_factor(v.cwiseAbs().maxCoeff());
        double digits = std::round(sigma / (fu * fv) * 255.0);  // a4a3a2a1 in 1/255 units
        if (digits > 9999) {
            ++overflows;
            digits = 9999;
        }
        const double stored_sigma = digits / 255.0;
        for (int p = 0; p < pca.pixels; ++p) {
            s.basis(p, i) = static_cast<float>(to8(fu * u[p]) * stored_sigma);
            if (u_codes) (*u_codes)[static_cast<size_t>(i)][static_cast<size_t>(p)] = static_cast<uint8_t>(code8(fu * u[p]));
        }
        for (int j = 0; j < pca.columns; ++j) s.weights(j, i) = static_cast<float>(to8(fv * v[j]));
    }
    if (sigma_overflows) *sigma_overflows = overflows;
    return s;
}

}  // namespace inlight::btf
