// render/sampler.h: the numbers a path consumes, either independent (PCG32 per sample) or
// Owen-scrambled Sobol points laid out over the image in Morton order (pbrt-v4's ZSobolSampler),
// with a fixed dimension per use and bounce so a path's dimensions stay stable across bounces.
//
// References: Sobol 1967 (the (0,2)-sequence: dimension 0 = van der Corput, dimension 1 from the
// primitive polynomial x + 1); Owen 1995 (nested uniform scrambling); Burley 2020, "Practical
// Hash-based Owen Scrambling", JCGT 9(4), listing 3 (Laine-Karras style hash on reversed bits);
// Ahmed and Wonka 2020, "Screen-Space Blue-Noise Diffusion of Monte Carlo Sampling Error via
// Hierarchical Ordering of Pixels" (Morton-ordered pixel blocks with randomly permuted base-4
// digits, as pbrt-v4 sec. 8.7.7 ZSobolSampler implements); Owen 1997 / L'Ecuyer and Lemieux 2002
// (independent randomisations give an unbiased variance estimate of a randomised QMC mean).
//
// Noise estimate: one Owen-scrambled sequence is a single randomisation, so its samples are not
// independent and their sample variance over-states the error of their mean. The Sobol sampler
// therefore splits a pixel's samples round-robin into `groups` independently scrambled
// sequences (sample s belongs to group s % groups and is point s / groups of it): the group means
// are independent and unbiased, and their spread gives an honest standard error.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>

#include "render/sampling.h"

namespace inlight::render {

enum class SamplerKind {
    kSobol,        ///< Owen-scrambled Sobol (0,2)-sequence in Morton pixel order (the default)
    kIndependent,  ///< independent uniforms from PCG32, one stream per (seed, pixel, sample)
};
/// "sobol" | "independent"; throws UsageError otherwise.
SamplerKind sampler_from_string(const std::string& name);
std::string to_string(SamplerKind kind);

/// The dimension layout of a path: dimension 0 places the sample in the pixel; bounce b
/// (0-based) owns dimensions kFirstBounceDim + b * kDimsPerBounce + {kLightDim, kBsdfDim,
/// kLobeDim, kRouletteDim}. The same use gets the same dimension whatever happened before.
struct PathDims {
    static constexpr int kPixelDim = 0;
    static constexpr int kFirstBounceDim = 1;
    static constexpr int kDimsPerBounce = 4;
    static constexpr int kLightDim = 0;     ///< 2D: environment sample
    static constexpr int kBsdfDim = 1;      ///< 2D: BSDF direction
    static constexpr int kLobeDim = 2;      ///< 1D: BSDF lobe choice
    static constexpr int kRouletteDim = 3;  ///< 1D: Russian roulette
    static constexpr int bounce(int b, int use) {
        return kFirstBounceDim + b * kDimsPerBounce + use;
    }
};

class Sampler {
  public:
    /// A sampler for a width_px x height_px image whose pixels take at most max_spp samples
    /// (sample indices 0 .. max_spp - 1). `groups` (>= 1, Sobol only) independent scrambles
    /// carry the noise estimate; the independent sampler has one group.
    /// Preconditions: width_px, height_px, max_spp, groups >= 1 (checked).
    Sampler(SamplerKind kind, uint64_t seed, int width_px, int height_px, int max_spp,
            int groups);

    /// The numbers of sample `sample` of pixel (x, y): a pure function of (seed, x, y, sample,
    /// dimension), so paths can run in any order on any thread.
    class Stream {
      public:
        /// A uniform in [0, 1) for dimension `dim` (>= 0).
        double get1d(int dim);
        /// A point in [0, 1)^2 for dimension `dim` (>= 0); the two coordinates are Sobol
        /// dimensions 0 and 1, so the pixel's points form a (0, m, 2)-net.
        Eigen::Vector2d get2d(int dim);

      private:
        friend class Sampler;
        Stream(const Sampler* s, uint64_t morton, uint64_t seed, Rng rng)
            : m_sampler(s), m_morton(morton), m_seed(seed), m_rng(rng) {}
        uint64_t sobol_index(int dim) const;
        const Sampler* m_sampler;
        uint64_t m_morton;  ///< (pixel Morton code << log2 points) | point index in its group
        uint64_t m_seed;    ///< the group's seed
        Rng m_rng;          ///< the independent sampler's stream
    };
    Stream stream(int x, int y, int64_t sample) const;

    SamplerKind kind() const { return m_kind; }
    /// Independent scramble groups (1 for the independent sampler).
    int groups() const { return m_groups; }
    /// The group of sample index `sample`: sample % groups().
    int group_of(int64_t sample) const { return static_cast<int>(sample % m_groups); }

  private:
    SamplerKind m_kind;
    uint64_t m_seed;
    int m_width, m_groups;
    int m_log2_points;  ///< log2 of the per-group points per pixel, rounded up
    int m_base4_digits;
};

/// Owen scrambling of a 32-bit fixed-point coordinate by a seed (Burley 2020): each output bit
/// is flipped by a hash of the bits above it, so nets stay nets. Exposed for tests.
uint32_t owen_scramble(uint32_t v, uint32_t seed);
/// Sobol dimension `dim` (0 or 1) of point `index`, as 32-bit fixed point. Exposed for tests.
uint32_t sobol_u32(uint64_t index, int dim);

}  // namespace inlight::render
