#pragma once
// Owen-scrambled Sobol sampler in the style of Burley 2020, "Practical Hash-based Owen
// Scrambling": a 4-dimensional Sobol sequence whose index is shuffled and whose values are
// nested-uniform scrambled with per-pixel, per-dimension-group hashes. Longer paths use a
// fresh 4D group per bounce (padding by independent scrambles).
#include <array>
#include <cstdint>

#include <glm/vec2.hpp>
#include <glm/vec4.hpp>

#if defined(__SSE4_1__)
#include <immintrin.h>
#endif

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

/// Reverses the bit order of a 32-bit word.
constexpr uint32_t reverseBits(uint32_t x) {
  x = ((x >> 1) & 0x55555555u) | ((x & 0x55555555u) << 1);
  x = ((x >> 2) & 0x33333333u) | ((x & 0x33333333u) << 2);
  x = ((x >> 4) & 0x0f0f0f0fu) | ((x & 0x0f0f0f0fu) << 4);
  x = ((x >> 8) & 0x00ff00ffu) | ((x & 0x00ff00ffu) << 8);
  return (x >> 16) | (x << 16);
}

/// A linear (over XOR) map of 32-bit words by input byte: bytes[dim][k][b] = XOR of
/// column(dim, 8k + i) over the set bits i of byte value b, so that the map of a word is the XOR
/// of its four bytes' entries: four lookups instead of 32 steps.
struct SobolByteTable {
  std::array<std::array<std::array<uint32_t, 256>, 4>, kSobolDimensions> bytes{};

  /// The entries of one dimension's map of word `x`.
  constexpr uint32_t map(uint32_t x, uint32_t dim) const {
    const auto& t = bytes[dim];
    return t[0][x & 0xffu] ^ t[1][(x >> 8) & 0xffu] ^ t[2][(x >> 16) & 0xffu] ^ t[3][x >> 24];
  }
};

/// Builds the byte table of the map whose input bit i selects column(dim, i).
template <class Column>
constexpr SobolByteTable makeSobolByteTable(Column column) {
  SobolByteTable t{};
  for (uint32_t dim = 0; dim < kSobolDimensions; ++dim) {
    for (uint32_t k = 0; k < 4; ++k) {
      for (uint32_t b = 0; b < 256; ++b) {
        uint32_t x = 0;
        for (uint32_t bit = 0; bit < 8; ++bit) {
          if ((b >> bit) & 1u) x ^= column(dim, 8 * k + bit);
        }
        t.bytes[dim][k][b] = x;
      }
    }
  }
  return t;
}

/// Sobol points by index byte (16 KiB): index bit i selects direction number i.
inline constexpr SobolByteTable kSobolBytes =
    makeSobolByteTable([](uint32_t dim, uint32_t i) { return kSobolDirections.v[dim][i]; });

/// Sobol points of a bit-reversed index, bit-reversed (16 KiB): bit i of y = reverseBits(index)
/// is index bit 31 - i. Bit reversal is linear over XOR as Sobol points are, so
/// reverseBits(sobol(reverseBits(y), dim)) is this table's map of y: a scrambled point (reverse,
/// scramble, reverse) then reverses its bits once instead of three times.
inline constexpr SobolByteTable kSobolReversedBytes =
    makeSobolByteTable([](uint32_t dim, uint32_t i) { return reverseBits(kSobolDirections.v[dim][31 - i]); });

/// Unscrambled Sobol point `index` in dimension `dim` (< kSobolDimensions), as 32 bits.
constexpr uint32_t sobol(uint32_t index, uint32_t dim) { return kSobolBytes.map(index, dim); }

/// reverseBits(sobol(reverseBits(y), dim)).
constexpr uint32_t reversedSobolOfReversed(uint32_t y, uint32_t dim) { return kSobolReversedBytes.map(y, dim); }

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
    // As get4Reference: the scrambled index in reversed bit order (y) picks the reversed Sobol
    // point straight from kSobolReversedBytes, and only the scrambled point is reversed back.
    const uint32_t groupSeed = hashCombine(pixelSeed_, group);
    const uint32_t y = laineKarrasPermutation(reverseBits(sampleIndex_), groupSeed);
#if defined(__SSE4_1__)
    // The four dimensions in the four lanes, the same integer steps as the scalar loop below.
    const auto point = [y](uint32_t d) { return reversedSobolOfReversed(y, d); };
    const __m128i points = _mm_setr_epi32(static_cast<int>(point(0)), static_cast<int>(point(1)),
                                          static_cast<int>(point(2)), static_cast<int>(point(3)));
    const auto times = [](__m128i x, uint32_t c) { return _mm_mullo_epi32(x, _mm_set1_epi32(static_cast<int>(c))); };
    // hashCombine(groupSeed, d + 1) for d = 0..3.
    const uint32_t mix = 0x9e3779b9u + (groupSeed << 6) + (groupSeed >> 2);
    __m128i seeds = _mm_xor_si128(_mm_set1_epi32(static_cast<int>(groupSeed)),
                                  _mm_add_epi32(_mm_setr_epi32(1, 2, 3, 4), _mm_set1_epi32(static_cast<int>(mix))));
    seeds = _mm_xor_si128(seeds, _mm_srli_epi32(seeds, 16));
    seeds = times(seeds, 0x7feb352du);
    seeds = _mm_xor_si128(seeds, _mm_srli_epi32(seeds, 15));
    seeds = times(seeds, 0x846ca68bu);
    seeds = _mm_xor_si128(seeds, _mm_srli_epi32(seeds, 16));
    // laineKarrasPermutation(point, seed).
    __m128i x = _mm_add_epi32(points, seeds);
    x = _mm_xor_si128(x, times(x, 0x6c50b47cu));
    x = _mm_xor_si128(x, times(x, 0xb82f1e52u));
    x = _mm_xor_si128(x, times(x, 0xc7afe638u));
    x = _mm_xor_si128(x, times(x, 0x8d22f6e6u));
    // reverseBits: each nibble reversed by table, the nibbles of a byte swapped, the bytes of a lane.
    const __m128i nibbleReversed = _mm_setr_epi8(0, 8, 4, 12, 2, 10, 6, 14, 1, 9, 5, 13, 3, 11, 7, 15);
    const __m128i lowNibbles = _mm_set1_epi8(0x0f);
    const __m128i low = _mm_shuffle_epi8(nibbleReversed, _mm_and_si128(x, lowNibbles));
    const __m128i high = _mm_shuffle_epi8(nibbleReversed, _mm_and_si128(_mm_srli_epi16(x, 4), lowNibbles));
    x = _mm_or_si128(_mm_slli_epi16(low, 4), high);   // no bit crosses a byte: low < 16
    x = _mm_shuffle_epi8(x, _mm_setr_epi8(3, 2, 1, 0, 7, 6, 5, 4, 11, 10, 9, 8, 15, 14, 13, 12));
    // toUnitFloat: the top 24 bits, exactly representable.
    const __m128 unit = _mm_mul_ps(_mm_cvtepi32_ps(_mm_srli_epi32(x, 8)), _mm_set1_ps(0x1p-24f));
    glm::vec4 out;
    _mm_storeu_ps(&out.x, unit);
    return out;
#else
    glm::vec4 out;
    for (uint32_t d = 0; d < kSobolDimensions; ++d) {
      const uint32_t dimSeed = hashCombine(groupSeed, d + 1);
      out[static_cast<int>(d)] =
          toUnitFloat(reverseBits(laineKarrasPermutation(reversedSobolOfReversed(y, d), dimSeed)));
    }
    return out;
#endif
  }

  /// get4 spelled out as defined: the scrambled index, its Sobol point, the point scrambled.
  glm::vec4 get4Reference(uint32_t group) const {
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
