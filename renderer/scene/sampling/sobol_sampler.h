#pragma once
// Owen-scrambled Sobol sampler in the style of Burley 2020, "Practical Hash-based Owen
// Scrambling": a 4-dimensional Sobol sequence whose index is shuffled and whose values are
// nested-uniform scrambled with per-pixel, per-dimension-group hashes. Longer paths use a
// fresh 4D group per bounce (padding by independent scrambles).
#include <array>
#include <cstdint>

#include <glm/vec2.hpp>
#include <glm/vec4.hpp>

namespace pa::sampling {

/// 32-bit integer hash with good avalanche (xor-shift-multiply, "lowbias32" constants).
constexpr uint32_t hash32(uint32_t x) {
  x ^= x >> 16;
  x *= 0x7feb352du;
  x ^= x >> 15;
  x *= 0x846ca68bu;
  x ^= x >> 16;
  return x;
}

/// Order-dependent combination of two hashes.
constexpr uint32_t hashCombine(uint32_t seed, uint32_t value) {
  return hash32(seed ^ (value + 0x9e3779b9u + (seed << 6) + (seed >> 2)));
}

/// Maps 32 random bits to a float in [0, 1) (24 bits of mantissa, never 1).
constexpr float toUnitFloat(uint32_t bits) { return static_cast<float>(bits >> 8) * 0x1p-24f; }

/// Number of Sobol dimensions per group.
inline constexpr uint32_t kSobolDimensions = 4;

/// Sobol direction numbers (32 bits) for dimensions 0..3; dimension 0 is van der Corput,
/// dimensions 1..3 use the Joe-Kuo primitive polynomials (s, a, m) = (1,0,{1}), (2,1,{1,3}),
/// (3,1,{1,3,1}).
struct SobolDirections {
  std::array<std::array<uint32_t, 32>, kSobolDimensions> v{};
};

/// Builds the direction numbers with the Bratley-Fox recurrence.
constexpr SobolDirections makeSobolDirections() {
  struct Poly { uint32_t s, a; std::array<uint32_t, 3> m; };
  constexpr std::array<Poly, 3> polys{{{1, 0, {1, 0, 0}}, {2, 1, {1, 3, 0}}, {3, 1, {1, 3, 1}}}};
  SobolDirections d{};
  for (uint32_t i = 0; i < 32; ++i) d.v[0][i] = 1u << (31 - i);
  for (uint32_t dim = 1; dim < kSobolDimensions; ++dim) {
    const Poly& p = polys[dim - 1];
    auto& v = d.v[dim];
    for (uint32_t i = 0; i < p.s; ++i) v[i] = p.m[i] << (31 - i);
    for (uint32_t i = p.s; i < 32; ++i) {
      uint32_t x = v[i - p.s] ^ (v[i - p.s] >> p.s);
      for (uint32_t k = 1; k < p.s; ++k) {
        if ((p.a >> (p.s - 1 - k)) & 1u) x ^= v[i - k];
      }
      v[i] = x;
    }
  }
  return d;
}

/// The constant direction table.
inline constexpr SobolDirections kSobolDirections = makeSobolDirections();

/// Sobol points by index byte: bytes[dim][k][b] = XOR of the direction numbers selected by the
/// bits of byte value b at byte position k, so a point costs four lookups instead of 32 steps.
struct SobolByteTable {
  std::array<std::array<std::array<uint32_t, 256>, 4>, kSobolDimensions> bytes{};
};

/// Builds the byte table from the direction numbers.
constexpr SobolByteTable makeSobolByteTable() {
  SobolByteTable t{};
  for (uint32_t dim = 0; dim < kSobolDimensions; ++dim) {
    for (uint32_t k = 0; k < 4; ++k) {
      for (uint32_t b = 0; b < 256; ++b) {
        uint32_t x = 0;
        for (uint32_t bit = 0; bit < 8; ++bit) {
          if ((b >> bit) & 1u) x ^= kSobolDirections.v[dim][8 * k + bit];
        }
        t.bytes[dim][k][b] = x;
      }
    }
  }
  return t;
}

/// The constant byte table (16 KiB).
inline constexpr SobolByteTable kSobolBytes = makeSobolByteTable();

/// Unscrambled Sobol point `index` in dimension `dim` (< kSobolDimensions), as 32 bits.
constexpr uint32_t sobol(uint32_t index, uint32_t dim) {
  const auto& t = kSobolBytes.bytes[dim];
  return t[0][index & 0xffu] ^ t[1][(index >> 8) & 0xffu] ^ t[2][(index >> 16) & 0xffu] ^ t[3][index >> 24];
}

/// Reverses the bit order of a 32-bit word.
constexpr uint32_t reverseBits(uint32_t x) {
  x = ((x >> 1) & 0x55555555u) | ((x & 0x55555555u) << 1);
  x = ((x >> 2) & 0x33333333u) | ((x & 0x33333333u) << 2);
  x = ((x >> 4) & 0x0f0f0f0fu) | ((x & 0x0f0f0f0fu) << 4);
  x = ((x >> 8) & 0x00ff00ffu) | ((x & 0x00ff00ffu) << 8);
  return (x >> 16) | (x << 16);
}

/// Laine-Karras style hash: each output bit depends only on itself and lower input bits,
/// so applied to bit-reversed values it is a nested uniform (Owen) scramble.
constexpr uint32_t laineKarrasPermutation(uint32_t x, uint32_t seed) {
  x += seed;
  x ^= x * 0x6c50b47cu;
  x ^= x * 0xb82f1e52u;
  x ^= x * 0xc7afe638u;
  x ^= x * 0x8d22f6e6u;
  return x;
}

/// Owen scramble of a 32-bit fixed-point value in [0, 1).
constexpr uint32_t nestedUniformScramble(uint32_t x, uint32_t seed) {
  return reverseBits(laineKarrasPermutation(reverseBits(x), seed));
}

/// Sampler for one pixel sample: a pure function of (pixel seed, sample index, group).
class PixelSampler {
 public:
  /// pixelSeed identifies pixel and render seed; sampleIndex counts samples in the pixel
  /// across accumulated frames (frame * spp + sample).
  constexpr PixelSampler(uint32_t pixelSeed, uint32_t sampleIndex)
      : pixelSeed_(pixelSeed), sampleIndex_(sampleIndex) {}

  /// Four scrambled Sobol dimensions of dimension group `group` (each use site owns a group).
  glm::vec4 get4(uint32_t group) const {
    const uint32_t groupSeed = hashCombine(pixelSeed_, group);
    const uint32_t index = nestedUniformScramble(sampleIndex_, groupSeed);
    glm::vec4 out;
    for (uint32_t d = 0; d < kSobolDimensions; ++d) {
      const uint32_t dimSeed = hashCombine(groupSeed, d + 1);
      out[static_cast<int>(d)] = toUnitFloat(nestedUniformScramble(sobol(index, d), dimSeed));
    }
    return out;
  }

  /// 32 well-mixed random bits for group `group` (stochastic transparency, tie-breaking).
  uint32_t bits(uint32_t group) const {
    return hashCombine(hashCombine(pixelSeed_, group), sampleIndex_);
  }

 private:
  uint32_t pixelSeed_;
  uint32_t sampleIndex_;
};

}  // namespace pa::sampling
