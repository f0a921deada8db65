// Tests of core/sobol.h against the definition (generator columns applied one bit at a time) and
// the (0,2)-sequence property.
#include "core/sobol.h"

#include <gtest/gtest.h>

#include <set>

namespace inlight::sobol {
namespace {

TEST(Sobol, DimensionOneIsThePascalMatrixModTwo) {
    // Generator column k has bit (31 - r) set iff binom(k, r) is odd, i.e. (r & k) == r (Lucas).
    for (uint64_t i : {0ull, 1ull, 2ull, 3ull, 7ull, 12345ull, 0xdeadbeefull, 0x123456789abcull}) {
        uint32_t expect = 0;
        for (int k = 0; k < 64; ++k) {
            if (!((i >> k) & 1u)) continue;
            for (int r = 0; r < 32 && r <= k; ++r) {
                if ((r & k) == r) expect ^= 1u << (31 - r);
            }
        }
        EXPECT_EQ(sample_u32(i, 1), expect) << i;
    }
}

TEST(Sobol, DimensionZeroIsVanDerCorput) {
    EXPECT_EQ(sample_u32(5, 0), 0xA0000000u);  // 0.101b
    EXPECT_EQ(sample_u32(1ull << 32, 0), 0u);   // only the low 32 bits reach 32-bit precision
}

TEST(Sobol, FirstPointsAreA02Net) {
    // The first 2^m points: every elementary box of area 2^-m (2^a x 2^(m-a) cells) holds one.
    for (int m : {1, 4, 7}) {
        for (int a = 0; a <= m; ++a) {
            std::set<uint64_t> cells;
            for (uint64_t i = 0; i < (1ull << m); ++i) {
                const uint64_t x = uint64_t{sample_u32(i, 0)} >> (32 - a);
                const uint64_t y = uint64_t{sample_u32(i, 1)} >> (32 - (m - a));
                cells.insert((x << 32) | y);
            }
            EXPECT_EQ(cells.size(), 1ull << m) << "m " << m << " a " << a;
        }
    }
}

}  // namespace
}  // namespace inlight::sobol
