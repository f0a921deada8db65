// Tests of core/bits.h against brute-force definitions (bit loops written out one bit at a time).
#include "core/bits.h"

#include <gtest/gtest.h>

namespace inlight::bits {
namespace {

uint32_t reverse_slow(uint32_t x) {
    uint32_t r = 0;
    for (int b = 0; b < 32; ++b) r |= ((x >> b) & 1u) << (31 - b);
    return r;
}

uint64_t morton_slow(uint32_t x, uint32_t y) {
    uint64_t r = 0;
    for (int b = 0; b < 32; ++b) {
        r |= static_cast<uint64_t>((x >> b) & 1u) << (2 * b);
        r |= static_cast<uint64_t>((y >> b) & 1u) << (2 * b + 1);
    }
    return r;
}

TEST(Bits, ReverseBitsMatchesTheBitLoop) {
    uint64_t s = 1;
    for (int i = 0; i < 10000; ++i) {
        s = mix64(s);
        const auto x = static_cast<uint32_t>(s);
        ASSERT_EQ(reverse_bits32(x), reverse_slow(x)) << x;
        ASSERT_EQ(reverse_bits32(reverse_bits32(x)), x);
    }
    EXPECT_EQ(reverse_bits32(1u), 0x80000000u);
    EXPECT_EQ(reverse_bits32(0u), 0u);
}

TEST(Bits, MortonInterleavesXToEvenAndYToOddBits) {
    uint64_t s = 2;
    for (int i = 0; i < 10000; ++i) {
        s = mix64(s);
        const auto x = static_cast<uint32_t>(s), y = static_cast<uint32_t>(s >> 32);
        ASSERT_EQ(morton2(x, y), morton_slow(x, y)) << x << " " << y;
    }
    // The 2x2 block at the origin is the codes 0..3 in Z order.
    EXPECT_EQ(morton2(0, 0), 0u);
    EXPECT_EQ(morton2(1, 0), 1u);
    EXPECT_EQ(morton2(0, 1), 2u);
    EXPECT_EQ(morton2(1, 1), 3u);
}

TEST(Bits, CeilLog2) {
    EXPECT_EQ(ceil_log2(0), 0);
    EXPECT_EQ(ceil_log2(1), 0);
    EXPECT_EQ(ceil_log2(2), 1);
    EXPECT_EQ(ceil_log2(3), 2);
    EXPECT_EQ(ceil_log2(1024), 10);
    EXPECT_EQ(ceil_log2(1025), 11);
}

}  // namespace
}  // namespace inlight::bits
