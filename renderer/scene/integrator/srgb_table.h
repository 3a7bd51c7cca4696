#pragma once
// sRGB decoding by table, inline: srgbToLinear at k / kSrgbTableSteps, linearly interpolated
// (largest difference from srgbToLinear over [0, 1] 4.8e-7, tested; one 8-bit display step is
// 3e-4 or more in linear values). Two gathers instead of a chain of about twenty dependent
// operations; inline because a lightmap sample decodes two colours once, and a call returned
// them through memory that the caller read back narrower (a store-forwarding stall per sample).
#include <array>
#include <cstddef>
#include <utility>

#include <glm/vec3.hpp>

#if defined(__AVX2__)
#include <immintrin.h>
#endif

namespace pa {

/// Steps of the decode table over [0, 1].
inline constexpr int kSrgbTableSteps = 1024;
/// srgbToLinear(k / kSrgbTableSteps) for k = 0..kSrgbTableSteps (display_composite.cpp).
extern const std::array<float, kSrgbTableSteps + 1> kSrgbDecodeTable;

/// tableSrgbToLinear (display_composite.h) of each channel of two colours, in one pass.
inline std::pair<glm::vec3, glm::vec3> decodeTwo(const glm::vec3& a, const glm::vec3& b) {
#if defined(__AVX2__)
  __m256 c = _mm256_setr_ps(a.x, a.y, a.z, b.x, b.y, b.z, 0.0f, 0.0f);
  // Clamped to [0, 1], NaN to 0 (max with a NaN first operand returns the second).
  c = _mm256_min_ps(_mm256_max_ps(c, _mm256_setzero_ps()), _mm256_set1_ps(1.0f));
  const __m256 s = _mm256_mul_ps(c, _mm256_set1_ps(float(kSrgbTableSteps)));
  const __m256i i = _mm256_min_epi32(_mm256_cvttps_epi32(s), _mm256_set1_epi32(kSrgbTableSteps - 1));
  const __m256 f = _mm256_sub_ps(s, _mm256_cvtepi32_ps(i));
  const __m256 lo = _mm256_i32gather_ps(kSrgbDecodeTable.data(), i, 4);
  const __m256 hi = _mm256_i32gather_ps(kSrgbDecodeTable.data() + 1, i, 4);
  alignas(32) float d[8];
  _mm256_store_ps(d, _mm256_add_ps(lo, _mm256_mul_ps(f, _mm256_sub_ps(hi, lo))));
  return {{d[0], d[1], d[2]}, {d[3], d[4], d[5]}};
#else
  const auto one = [](float v) {
    v = v > 0.0f ? v : 0.0f;   // NaN becomes 0
    v = v < 1.0f ? v : 1.0f;
    const float s = v * float(kSrgbTableSteps);
    int i = static_cast<int>(s);
    i = i < kSrgbTableSteps - 1 ? i : kSrgbTableSteps - 1;
    const float f = s - static_cast<float>(i);
    const float lo = kSrgbDecodeTable[size_t(i)], hi = kSrgbDecodeTable[size_t(i) + 1];
    return lo + f * (hi - lo);
  };
  return {{one(a.x), one(a.y), one(a.z)}, {one(b.x), one(b.y), one(b.z)}};
#endif
}

}  // namespace pa
