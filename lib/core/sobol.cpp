#include "core/sobol.h"

#include <array>
#include <memory>

#include "core/bits.h"
#include "core/check.h"

namespace inlight::sobol {
namespace {

/// Dimension 1 by bytes of the index: table[b][v] is the xor of the generator columns of the set
/// bits of v placed at byte b.
using ByteTable = std::array<std::array<uint32_t, 256>, 8>;
const ByteTable& dim1_bytes() {
    static const auto table = [] {
        std::array<uint32_t, 64> cols{};
        uint32_t v = 1u << 31;
        for (auto& c : cols) {
            c = v;
            v ^= v >> 1;
        }
        auto t = std::make_unique<ByteTable>();
        for (size_t b = 0; b < 8; ++b) {
            for (size_t x = 0; x < 256; ++x) {
                uint32_t r = 0;
                for (size_t k = 0; k < 8; ++k) {
                    if ((x >> k) & 1u) r ^= cols[b * 8 + k];
                }
                (*t)[b][x] = r;
            }
        }
        return t;
    }();
    return *table;
}

}  // namespace

uint32_t sample_u32(uint64_t index, int dim) {
    INLIGHT_DCHECK(dim == 0 || dim == 1);
    if (dim == 0) return bits::reverse_bits32(static_cast<uint32_t>(index));
    const ByteTable& t = dim1_bytes();
    uint32_t r = 0;
    for (size_t b = 0; index; ++b, index >>= 8) r ^= t[b][index & 0xFFu];
    return r;
}

}  // namespace inlight::sobol
