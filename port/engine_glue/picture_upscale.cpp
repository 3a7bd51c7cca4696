#include "port/engine_glue/picture_upscale.h"

#include <immintrin.h>

#include <algorithm>
#include <cstddef>

namespace glue {
namespace {

// Byte shuffle of four pixels: RGBA -> BGRA.
inline __m128i swapRedBlue(__m128i pixels) {
  const __m128i order = _mm_setr_epi8(2, 1, 0, 3, 6, 5, 4, 7, 10, 9, 8, 11, 14, 13, 12, 15);
  return _mm_shuffle_epi8(pixels, order);
}

// One output row's vertical pass: t = 3 * near + far per channel (at most 1020), for `width`
// pixels, written from t[4] on with the edge pixels repeated at t[0..3] and after the row.
void verticalPass(const uint8_t* near, const uint8_t* far, int width, uint16_t* t) {
  const size_t count = size_t(width) * 4;
  uint16_t* out = t + 4;
  size_t i = 0;
  const __m128i zero = _mm_setzero_si128();
  for (; i + 16 <= count; i += 16) {
    const __m128i a = _mm_loadu_si128(reinterpret_cast<const __m128i*>(near + i));
    const __m128i b = _mm_loadu_si128(reinterpret_cast<const __m128i*>(far + i));
    const __m128i aLo = _mm_unpacklo_epi8(a, zero), aHi = _mm_unpackhi_epi8(a, zero);
    const __m128i bLo = _mm_unpacklo_epi8(b, zero), bHi = _mm_unpackhi_epi8(b, zero);
    const __m128i lo = _mm_add_epi16(_mm_add_epi16(aLo, _mm_slli_epi16(aLo, 1)), bLo);
    const __m128i hi = _mm_add_epi16(_mm_add_epi16(aHi, _mm_slli_epi16(aHi, 1)), bHi);
    _mm_storeu_si128(reinterpret_cast<__m128i*>(out + i), lo);
    _mm_storeu_si128(reinterpret_cast<__m128i*>(out + i + 8), hi);
  }
  for (; i < count; ++i) out[i] = static_cast<uint16_t>(3 * near[i] + far[i]);
  for (int c = 0; c < 4; ++c) {
    t[c] = out[c];
    out[count + size_t(c)] = out[count - 4 + size_t(c)];
  }
}

// One output row's horizontal pass over the vertical sums `t` (see verticalPass): output pixels
// 2k and 2k+1 are (3 t[k] + t[k-1] + 8) / 16 and (3 t[k] + t[k+1] + 8) / 16, as BGRA.
void horizontalPass(const uint16_t* t, int width, uint8_t* bgra) {
  const __m128i eight = _mm_set1_epi16(8);
  int k = 0;
  for (; k + 2 <= width; k += 2) {
    const uint16_t* at = t + 4 * size_t(k);   // t pixel k + 1 holds source pixel k
    const __m128i left = _mm_loadu_si128(reinterpret_cast<const __m128i*>(at));
    const __m128i centre = _mm_loadu_si128(reinterpret_cast<const __m128i*>(at + 4));
    const __m128i right = _mm_loadu_si128(reinterpret_cast<const __m128i*>(at + 8));
    const __m128i thrice = _mm_add_epi16(_mm_add_epi16(centre, _mm_slli_epi16(centre, 1)), eight);
    const __m128i even = _mm_srli_epi16(_mm_add_epi16(thrice, left), 4);
    const __m128i odd = _mm_srli_epi16(_mm_add_epi16(thrice, right), 4);
    // even = [e(k), e(k+1)], odd = [o(k), o(k+1)] -> pixels e(k) o(k) e(k+1) o(k+1).
    const __m128i first = _mm_unpacklo_epi64(even, odd);
    const __m128i second = _mm_unpackhi_epi64(even, odd);
    _mm_storeu_si128(reinterpret_cast<__m128i*>(bgra + 8 * size_t(k)),
                     swapRedBlue(_mm_packus_epi16(first, second)));
  }
  for (; k < width; ++k) {
    const uint16_t* at = t + 4 * size_t(k);
    uint8_t* out = bgra + 8 * size_t(k);
    for (int c = 0; c < 4; ++c) {
      const int thrice = 3 * at[4 + c] + 8;
      const int d = c == 3 ? 3 : 2 - c;   // RGBA -> BGRA
      out[d] = static_cast<uint8_t>((thrice + at[c]) >> 4);
      out[4 + d] = static_cast<uint8_t>((thrice + at[8 + c]) >> 4);
    }
  }
}

}  // namespace

void copyRgbaToBgra(const uint8_t* rgba, int width, int height, uint8_t* bgra) {
  if (width <= 0 || height <= 0) return;
  const size_t count = size_t(width) * size_t(height) * 4;
  size_t i = 0;
  for (; i + 16 <= count; i += 16) {
    const __m128i pixels = _mm_loadu_si128(reinterpret_cast<const __m128i*>(rgba + i));
    _mm_storeu_si128(reinterpret_cast<__m128i*>(bgra + i), swapRedBlue(pixels));
  }
  for (; i < count; i += 4) {
    bgra[i] = rgba[i + 2];
    bgra[i + 1] = rgba[i + 1];
    bgra[i + 2] = rgba[i];
    bgra[i + 3] = rgba[i + 3];
  }
}

void upscale2xRgbaToBgra(const uint8_t* rgba, int width, int height, uint8_t* bgra,
                         std::vector<uint16_t>& scratch) {
  if (width <= 0 || height <= 0) return;
  const size_t rowValues = (size_t(width) + 2) * 4;
  if (scratch.size() < rowValues) scratch.resize(rowValues);
  const size_t sourceRow = size_t(width) * 4;
  const size_t outputRow = sourceRow * 2;
  for (int y = 0; y < 2 * height; ++y) {
    // Output row y samples at source row (y + 0.5) / 2 - 0.5: between row y/2 (weight 3/4) and
    // the row above (y even) or below (y odd), clamped at the edges.
    const int j = y >> 1;
    const int other = (y & 1) == 0 ? std::max(j - 1, 0) : std::min(j + 1, height - 1);
    verticalPass(rgba + size_t(j) * sourceRow, rgba + size_t(other) * sourceRow, width, scratch.data());
    horizontalPass(scratch.data(), width, bgra + size_t(y) * outputRow);
  }
}

}  // namespace glue
