// core/sobol.h: the first two dimensions of the Sobol sequence as 32-bit fixed point, shared by
// render's Owen-scrambled sampler (render/sampler.h) and brdf's Sobol-point bake (brdf/bake.h).
//
// Sobol 1967: dimension 0 is the van der Corput sequence (bit reversal); dimension 1 has
// primitive polynomial x + 1, generator columns V_1 = 2^31, V_k = V_{k-1} xor (V_{k-1} >> 1)
// (the Pascal matrix mod 2). Together they form a (0,2)-sequence in base 2.
#pragma once

#include <cstdint>

namespace inlight::sobol {

/// Dimension `dim` (0 or 1, checked in Debug) of Sobol point `index`, as 32-bit fixed point:
/// the coordinate is the result * 2^-32, in [0, 1). Each bit of a generator column depends only
/// on the bits above it, so truncating the 64 columns of a 64-bit index to 32 bits is exact.
uint32_t sample_u32(uint64_t index, int dim);

}  // namespace inlight::sobol
