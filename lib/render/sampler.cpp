#include "render/sampler.h"

#include <algorithm>
#include <array>
#include <memory>

#include "core/bits.h"
#include "core/check.h"
#include "core/enum_names.h"
#include "core/error.h"
#include "core/sobol.h"

namespace inlight::render {
namespace {

/// The 24 permutations of the base-4 digits {0, 1, 2, 3}, in lexicographic order.
const std::array<std::array<uint8_t, 4>, 24>& digit_permutations() {
    static const auto table = [] {
        std::array<std::array<uint8_t, 4>, 24> t{};
        std::array<uint8_t, 4> p = {0, 1, 2, 3};
        for (auto& row : t) {
            row = p;
            std::next_permutation(p.begin(), p.end());
        }
        return t;
    }();
    return table;
}

/// Scramble seeds of dimension `dim` of a group: two independent 32-bit halves.
uint64_t dimension_seed(uint64_t group_seed, int dim) {
    return bits::mix64(group_seed ^ bits::mix64(static_cast<uint64_t>(dim) + 1));
}

constexpr double kU32ToUnit = 0x1p-32;  // [0, 2^32) -> [0, 1): never 1

}  // namespace

constexpr EnumName<SamplerKind> kSamplerNames[] = {{SamplerKind::kSobol, "sobol"},
                                                   {SamplerKind::kIndependent, "independent"}};

SamplerKind sampler_from_string(const std::string& name) {
    return enum_from_string(kSamplerNames, name, "sampler");
}

std::string to_string(SamplerKind kind) { return enum_to_string(kSamplerNames, kind); }

uint32_t owen_scramble(uint32_t v, uint32_t seed) {
    // Burley 2020, listing 3: a Laine-Karras permutation (each bit flipped by a hash of the
    // lower bits) applied to the reversed bits, i.e. each digit by a hash of the digits above.
    v = bits::reverse_bits32(v);
    v += seed;
    v ^= v * 0x6c50b47cu;
    v ^= v * 0xb82f1e52u;
    v ^= v * 0xc7afe638u;
    v ^= v * 0x8d22f6e6u;
    return bits::reverse_bits32(v);
}

uint32_t sobol_u32(uint64_t index, int dim) { return sobol::sample_u32(index, dim); }

Sampler::Sampler(SamplerKind kind, uint64_t seed, int width_px, int height_px, int max_spp,
                 int groups)
    : m_kind(kind), m_seed(seed), m_width(width_px), m_groups(kind == SamplerKind::kSobol ? groups : 1) {
    INLIGHT_CHECK_GE(width_px, 1);
    INLIGHT_CHECK_GE(height_px, 1);
    INLIGHT_CHECK_GE(max_spp, 1);
    INLIGHT_CHECK_GE(groups, 1);
    const int points = (max_spp + m_groups - 1) / m_groups;
    m_log2_points = bits::ceil_log2(static_cast<uint64_t>(points));
    const int log2_res = bits::ceil_log2(static_cast<uint64_t>(std::max(width_px, height_px)));
    m_base4_digits = log2_res + (m_log2_points + 1) / 2;
    INLIGHT_CHECK_LE(2 * log2_res + m_log2_points, 64) << "Morton index exceeds 64 bits";
}

Sampler::Stream Sampler::stream(int x, int y, int64_t sample) const {
    if (m_kind == SamplerKind::kIndependent) {
        const uint64_t pixel =
            static_cast<uint64_t>(y) * static_cast<uint64_t>(m_width) + static_cast<uint64_t>(x);
        return Stream(this, 0, m_seed, Rng(m_seed, pixel, static_cast<uint64_t>(sample)));
    }
    const auto group = static_cast<uint64_t>(sample % m_groups);
    const auto point = static_cast<uint64_t>(sample / m_groups);
    INLIGHT_CHECK_LT(point, uint64_t{1} << m_log2_points) << "sample beyond the sampler's max_spp";
    const uint64_t morton =
        (bits::morton2(static_cast<uint32_t>(x), static_cast<uint32_t>(y)) << m_log2_points) |
        point;
    const uint64_t group_seed = bits::mix64(m_seed ^ (0x632be59bd9b4e019ull * (group + 1)));
    return Stream(this, morton, group_seed, Rng());
}

uint64_t Sampler::Stream::sobol_index(int dim) const {
    // pbrt-v4 ZSobolSampler::GetSampleIndex: walk the base-4 digits of the Morton index from
    // the top and permute each by a hash of the digits above it and the dimension, so every
    // aligned block of pixels x points maps to an aligned block of Sobol indices.
    const auto& perms = digit_permutations();
    const int log2_points = m_sampler->m_log2_points;
    const bool odd = (log2_points & 1) != 0;
    const uint64_t dim_hash = bits::mix64(static_cast<uint64_t>(dim) ^ m_seed);
    // One multiply-xorshift per digit (the inputs already differ by a full 64-bit hash per
    // dimension and group); its top bits pick one of the 24 permutations.
    auto digit_hash = [dim_hash](uint64_t higher) {
        uint64_t h = (higher ^ dim_hash) * 0xd6e8feb86659fd93ull;
        h ^= h >> 32;
        return h * 0xd6e8feb86659fd93ull;
    };
    uint64_t index = 0;
    for (int i = m_sampler->m_base4_digits - 1; i >= (odd ? 1 : 0); --i) {
        const int shift = 2 * i - (odd ? 1 : 0);
        const auto digit = static_cast<int>((m_morton >> shift) & 3u);
        const uint64_t higher = shift + 2 < 64 ? m_morton >> (shift + 2) : 0;
        const auto p = static_cast<size_t>((digit_hash(higher) >> 40) % 24);
        index |= static_cast<uint64_t>(perms[p][static_cast<size_t>(digit)]) << shift;
    }
    if (odd) {  // the last digit is binary: flip it by a hash of the rest
        index |= (m_morton & 1u) ^ (digit_hash(m_morton >> 1) >> 63);
    }
    return index;
}

double Sampler::Stream::get1d(int dim) {
    if (m_sampler->m_kind == SamplerKind::kIndependent) return m_rng.uniform();
    const uint64_t index = sobol_index(dim);
    const auto seed = static_cast<uint32_t>(dimension_seed(m_seed, dim));
    return owen_scramble(sobol_u32(index, 0), seed) * kU32ToUnit;
}

Eigen::Vector2d Sampler::Stream::get2d(int dim) {
    if (m_sampler->m_kind == SamplerKind::kIndependent) return m_rng.uniform2();
    const uint64_t index = sobol_index(dim);
    const uint64_t seed = dimension_seed(m_seed, dim);
    return {owen_scramble(sobol_u32(index, 0), static_cast<uint32_t>(seed)) * kU32ToUnit,
            owen_scramble(sobol_u32(index, 1), static_cast<uint32_t>(seed >> 32)) * kU32ToUnit};
}

}  // namespace inlight::render
