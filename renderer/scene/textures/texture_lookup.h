#pragma once
// Texture's bilinear lookups in one level, inline: a see-through layer or an alpha test reads one
// texel quad per ray crossing, and a call returned the colour through the stack (a store-forwarding
// stall where the caller read it back). Included by texture.h.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>

#include <glm/common.hpp>

#if defined(__SSE4_1__)
#include <immintrin.h>
#endif

namespace pa {

namespace texture_detail {

/// The two texel indices along an axis of n texels that a bilinear lookup at integer i blends:
/// i and i + 1, wrapped or clamped to [0, n - 1]. With repeat, i lies in [-1, n - 1] (the lookup
/// wraps its coordinate into [0, 1] first), so wrapping needs no division.
inline std::array<uint32_t, 2> texelPair(int i, int n, bool repeat) {
  if (!repeat) return {uint32_t(std::clamp(i, 0, n - 1)), uint32_t(std::clamp(i + 1, 0, n - 1))};
  const int first = i < 0 ? i + n : (i >= n ? i - n : i);
  return {uint32_t(first), uint32_t(first + 1 == n ? 0 : first + 1)};
}

}  // namespace texture_detail

[[gnu::always_inline]] inline glm::vec2 Texture::wrapped(glm::vec2 uv) const {
  if (!std::isfinite(uv.x) || !std::isfinite(uv.y)) uv = {0.0f, 0.0f};
  // Keep coordinates in a range where float -> int conversion is exact and safe.
  if (wrap_ == TextureWrap::Repeat) return uv - glm::floor(uv);
  return glm::clamp(uv, glm::vec2(-1.0f), glm::vec2(2.0f));
}

template <bool Stored>
[[gnu::always_inline]] inline glm::vec4 Texture::sampleLevel(uint32_t levelIndex, glm::vec2 uv) const {
  const MipLevel& level = levels_[std::min<size_t>(levelIndex, levels_.size() - 1)];
  const bool repeat = wrap_ == TextureWrap::Repeat;
  const float px = uv.x * static_cast<float>(level.width) - 0.5f;
  const float py = uv.y * static_cast<float>(level.height) - 0.5f;
  const float fx0 = std::floor(px);
  const float fy0 = std::floor(py);
  const float fx = px - fx0;
  const float fy = py - fy0;
  const auto [x0, x1] = texture_detail::texelPair(static_cast<int>(fx0), static_cast<int>(level.width), repeat);
  const auto [y0, y1] = texture_detail::texelPair(static_cast<int>(fy0), static_cast<int>(level.height), repeat);
  const std::array<uint8_t, 4>* row0 = &level.texels[size_t{y0} * level.width];
  const std::array<uint8_t, 4>* row1 = &level.texels[size_t{y1} * level.width];
#if defined(__SSE4_1__)
  if constexpr (Stored) {   // the four texels widened and blended in one register each, scaled once
    const auto load = [](const std::array<uint8_t, 4>& t) {
      uint32_t bytes;
      std::memcpy(&bytes, t.data(), 4);
      return _mm_cvtepi32_ps(_mm_cvtepu8_epi32(_mm_cvtsi32_si128(static_cast<int>(bytes))));
    };
    const __m128 wx = _mm_set1_ps(fx), wx0 = _mm_set1_ps(1.0f - fx);
    const __m128 top = _mm_add_ps(_mm_mul_ps(load(row0[x0]), wx0), _mm_mul_ps(load(row0[x1]), wx));
    const __m128 bottom = _mm_add_ps(_mm_mul_ps(load(row1[x0]), wx0), _mm_mul_ps(load(row1[x1]), wx));
    const __m128 blend = _mm_add_ps(_mm_mul_ps(top, _mm_set1_ps(1.0f - fy)), _mm_mul_ps(bottom, _mm_set1_ps(fy)));
    glm::vec4 out;
    _mm_storeu_ps(&out.x, _mm_mul_ps(blend, _mm_set1_ps(1.0f / 255.0f)));
    return out;
  }
#endif
#if defined(__FMA__)
  if constexpr (!Stored) {
    // The four texels decoded into registers and blended there. The blend is the portable one
    // below as the compiler contracts it where FMA is available (b fx + a (1 - fx), ...), so
    // both give the same bits.
    const auto decoded = [this](const std::array<uint8_t, 4>& t) {
      return _mm_setr_ps(decode_[t[0]], decode_[t[1]], decode_[t[2]], decode_[256 + t[3]]);
    };
    const __m128 wx = _mm_set1_ps(fx), wx0 = _mm_set1_ps(1.0f - fx);
    const __m128 top = _mm_fmadd_ps(decoded(row0[x1]), wx, _mm_mul_ps(decoded(row0[x0]), wx0));
    const __m128 bottom = _mm_fmadd_ps(decoded(row1[x1]), wx, _mm_mul_ps(decoded(row1[x0]), wx0));
    const __m128 blend = _mm_fmadd_ps(bottom, _mm_set1_ps(fy), _mm_mul_ps(top, _mm_set1_ps(1.0f - fy)));
    glm::vec4 out;
    _mm_storeu_ps(&out.x, blend);
    return out;
  }
#endif
  const auto texel = [this](const std::array<uint8_t, 4>& t) { return Stored ? stored(t) : decode(t); };
  const glm::vec4 a = texel(row0[x0]);
  const glm::vec4 b = texel(row0[x1]);
  const glm::vec4 c = texel(row1[x0]);
  const glm::vec4 d = texel(row1[x1]);
  return (a * (1.0f - fx) + b * fx) * (1.0f - fy) + (c * (1.0f - fx) + d * fx) * fy;
}

inline glm::vec4 Texture::sample(glm::vec2 uv, float lod, TextureFilter filter) const {
  glm::vec4 out;
  sampleInto(uv, lod, filter, out);
  return out;
}

// Always inlined: a call's vec4 comes back in two halves that a caller multiplying it as one
// vector stores and reloads whole (a store-forwarding stall per lookup: over half of
// evaluateCrossings' own time in a plasma fight, docs/performance.md).
[[gnu::always_inline]] inline glm::vec4 Texture::sampleFull(glm::vec2 uv) const {
  return sampleLevel<false>(0, wrapped(uv));
}

[[gnu::always_inline]] inline glm::vec4 Texture::sampleFullStored(glm::vec2 uv) const {
  return sampleLevel<true>(0, wrapped(uv));
}

}  // namespace pa
