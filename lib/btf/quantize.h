// btf/quantize.h: storing PCA components in 8 bits: this project's scale and offset per
// component, and the BTF thesis' packing (section 6.1) emulated so the two can be measured
// side by side.
//
// Ours: each column of L = [m | U Sigma] is stored as codes 0..255 with value = offset +
// scale * code (offset = the column's minimum, scale = its range / 255), so every component
// uses all 256 levels; R's V is kept in float32 (it is small: N x C per group).
// The thesis: U and V in [-1, 1] are mapped by f(x) = (x + 1) / 2 to 8 bits after scaling by
// factor(M) = 10^floor(-log10(max |M|)) (the largest power of ten that keeps the range), and
// Sigma, divided by both factors, is written as a four-digit integer a4a3a2a1 in units of
// 1/255 (8-bit data), two decimal digits per 8-bit channel; the mean image is an 8-bit image.
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

/// The thesis' packing of the first c components (file comment). `sigma_overflows` counts
/// singular values above 9999 / 255 after scaling, which four digits cannot hold (clamped).
/// `u_codes`, when given, receives each component's 8-bit U codes (P each), for sizing its PNG.
StoredGroup store_thesis(const GroupPca& pca, int c, int* sigma_overflows = nullptr,
                         std::vector<std::vector<uint8_t>>* u_codes = nullptr);

/// factor(M) of the thesis for values of largest magnitude `max_abs`: 10^floor(-log10 max_abs),
/// at least 1 (1 when max_abs is 0).
double thesis_factor(double max_abs);

}  // namespace inlight::btf
