// btf/quantize.h: storing PCA components in 8 bits: this project's scale and offset per
// component, and the BTF thesis' packing (section 6.1) emulated so the two can be measured
// side by side.
//
// Ours: each column of L = [m | U Sigma] is stored as codes 0..255 with value = offset +
// scale * code (offset = the column's minimum, scale = its range / 255), so every component
// uses all 256 levels; R's V is kept in float32 (it is small: N x C per group).
// The thesis (section 6.1): U and V in [-1, 1] are mapped by f(x) = (x + 1) / 2 to 8 bits after
// scaling the matrix by factor(M) = 10^floor(-log10(max |M|)) (the largest power of ten that
// keeps the range [-1, 1]; the thesis' formula takes logs of min(M) and max(M), undefined for
// negative entries, so its stated intent is what is implemented), and Sigma, divided by both
// factors, is written as a four-digit integer a4a3a2a1 in units of 1/255 (8-bit data), two
// decimal digits per 8-bit channel; the mean image is an 8-bit image. `btf-pca compress --codec
// thesis` writes these codes as its files (btf/pca_run.h).
#pragma once

#include <cstdint>
#include <vector>

#include "btf/pca.h"

namespace inlight::btf {

/// One column quantised to 8 bits: value = offset + scale * code.
struct Quantized8 {
    std::vector<uint8_t> codes;
    float scale = 0;   ///< (max - min) / 255; 0 when the column is constant
    float offset = 0;  ///< the column's minimum
    float value(int64_t i) const { return offset + scale * codes[static_cast<size_t>(i)]; }
};

/// Quantises n values (finite; checked) with the column's own range: scale = range / 255, or
/// `min_step` when that is larger (a column of small range then uses fewer than 256 codes, which
/// PNG stores in fewer bytes). min_step >= 0 (checked).
Quantized8 quantize8(const float* values, int64_t n, float min_step = 0);

/// A group's model as a decoder sees it: mean, basis (U Sigma) and weights (V) after storage.
struct StoredGroup {
    Eigen::VectorXf mean;     ///< P
    Eigen::MatrixXf basis;    ///< P x C
    Eigen::MatrixXf weights;  ///< N x C
};

/// Ours: mean and each basis column through quantize8, V as float32 (unchanged).
StoredGroup store_ours(const GroupPca& pca);

/// A group as the thesis packs its first c components (file comment): the codes of its files
/// and the numbers beside them. factor(U) and factor(V) are one each for the group's matrices U
/// and V (the thesis scales "the matrix U or V"), so every component of a group shares them.
struct ThesisGroup {
    std::vector<uint8_t> mean_codes;            ///< P: the mean as an 8-bit image, round(255 m)
    std::vector<std::vector<uint8_t>> u_codes;  ///< per component, P codes round(255 f(factor_u u))
    std::vector<std::vector<uint8_t>> v_codes;  ///< per component, N codes round(255 f(factor_v v))
    /// Per component a4a3a2a1 = round(255 sigma / (factor_u factor_v)): four decimal digits in
    /// two 8-bit channels, and two more digits per further channel where four do not hold it
    /// (the thesis' "adapt this technique further in the similar manner").
    std::vector<int64_t> sigma_digits;
    double factor_u = 1, factor_v = 1;  ///< factor(U), factor(V)
    int sigma_overflows = 0;            ///< components whose digits need more than four (above 9999)

    /// The values a decoder reads, value = offset + scale * code: U Sigma's column c has
    /// scale 2 s / 255 and offset -s with s = sigma_digits[c] / 255 (so it is f^-1(code / 255) s:
    /// factor_u cancels against Sigma's division); V has scale 2 / 255 and offset -1 (factor_v
    /// stays in V, divided out of Sigma); the mean scale 1 / 255 and offset 0.
    float basis_scale(int c) const { return float(2.0 * double(sigma_digits[size_t(c)]) / (255.0 * 255.0)); }
    float basis_offset(int c) const { return float(-double(sigma_digits[size_t(c)]) / 255.0); }
    static constexpr float kWeightScale = 2.0f / 255.0f, kWeightOffset = -1.0f, kMeanScale = 1.0f / 255.0f;
    /// The model a decoder of these codes computes with (the formulas above, in float).
    StoredGroup decoded() const;
};

/// The thesis' packing of the first c components of `pca` (fitted to values in [0, 1]: the
/// 8-bit codes / 255). Precondition: 0 <= c <= pca.components() (checked).
ThesisGroup pack_thesis(const GroupPca& pca, int c);

/// factor(M) of the thesis for values of largest magnitude `max_abs`: 10^floor(-log10 max_abs),
/// at least 1 (1 when max_abs is 0).
double thesis_factor(double max_abs);

}  // namespace inlight::btf
