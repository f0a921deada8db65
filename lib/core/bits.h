// core/bits.h: bit manipulation shared by the quasi-Monte Carlo code (render's Sobol sampler,
// brdf's Sobol-point bake): bit reversal, Morton (Z-order) interleaving and the integer hashes
// that scramble them.
//
// References: Warren, "Hacker's Delight" 2nd ed., sec. 7-1 (bit reversal by swapping halves),
// 7-2 (bit interleaving by magic masks); Steele et al. 2014 (SplitMix64 finaliser).
#pragma once

#include <cstdint>

namespace inlight::bits {

/// The 32 bits of x in reverse order (bit 0 becomes bit 31): the van der Corput radical inverse
/// in base 2 is reverse_bits32(i) * 2^-32.
constexpr uint32_t reverse_bits32(uint32_t x) {
    x = ((x >> 1) & 0x55555555u) | ((x & 0x55555555u) << 1);
    x = ((x >> 2) & 0x33333333u) | ((x & 0x33333333u) << 2);
    x = ((x >> 4) & 0x0F0F0F0Fu) | ((x & 0x0F0F0F0Fu) << 4);
    x = ((x >> 8) & 0x00FF00FFu) | ((x & 0x00FF00FFu) << 8);
    return (x >> 16) | (x << 16);
}

/// Spreads the low 32 bits of x to the even bit positions (bit k -> bit 2k).
constexpr uint64_t spread_bits32(uint64_t x) {
    x &= 0xFFFFFFFFull;
    x = (x | (x << 16)) & 0x0000FFFF0000FFFFull;
    x = (x | (x << 8)) & 0x00FF00FF00FF00FFull;
    x = (x | (x << 4)) & 0x0F0F0F0F0F0F0F0Full;
    x = (x | (x << 2)) & 0x3333333333333333ull;
    x = (x | (x << 1)) & 0x5555555555555555ull;
    return x;
}

/// Morton (Z-order) code of (x, y): x's bits at even positions, y's at odd ones, so pixels that
/// are close in the image are close in the code (4 pixels of a 2x2 block are 4 consecutive codes).
constexpr uint64_t morton2(uint32_t x, uint32_t y) {
    return spread_bits32(x) | (spread_bits32(y) << 1);
}

/// SplitMix64 finaliser: a bijective 64-bit mix (Steele et al. 2014).
constexpr uint64_t mix64(uint64_t x) {
    x += 0x9e3779b97f4a7c15ull;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
    return x ^ (x >> 31);
}

/// Smallest k with 2^k >= n (0 for n <= 1).
constexpr int ceil_log2(uint64_t n) {
    int k = 0;
    while (k < 64 && (uint64_t{1} << k) < n) ++k;
    return k;
}

}  // namespace inlight::bits
