#pragma once
// Lanes of floats (or ints) in one value, for the TAAU resolve's output pixels a step: GCC / Clang
// vector extensions. Eight lanes (one AVX register) where the module is built for AVX
// (PATHARENA_ISA x86-64-v3), four (one SSE register) otherwise: without AVX, eight-lane values
// are split into halves through memory (a resolve 3x slower than with four lanes). Only plain
// IEEE operations (no approximations): a lane computes what the same scalar expression would, up
// to the multiply-adds the compiler fuses.
#include <cstdint>
#include <cstring>

#include <immintrin.h>

// These types never cross a library boundary: the note that their argument-passing ABI depends
// on the ISA does not apply.
#pragma GCC diagnostic ignored "-Wpsabi"

namespace pa::taau::lanes {

#if defined(__AVX__)
/// Lanes per value.
inline constexpr int kCount = 8;
#else
/// Lanes per value.
inline constexpr int kCount = 4;
#endif

/// kCount floats.
typedef float F __attribute__((vector_size(4 * kCount)));
/// kCount 32-bit ints; also the result of comparing two F or I (-1: true, 0: false).
typedef int32_t I __attribute__((vector_size(4 * kCount)));

#if defined(__AVX__)
/// 0, 1, ..., kCount - 1.
inline constexpr I kIota = {0, 1, 2, 3, 4, 5, 6, 7};
#else
/// 0, 1, ..., kCount - 1.
inline constexpr I kIota = {0, 1, 2, 3};
#endif

/// Every lane `v`.
inline F splat(float v) {
  F r;
  for (int i = 0; i < kCount; ++i) r[i] = v;
  return r;
}
/// Every lane `v`.
inline I splat(int32_t v) {
  I r;
  for (int i = 0; i < kCount; ++i) r[i] = v;
  return r;
}

/// kCount consecutive values from p (any alignment).
inline F load(const float* p) {
  F v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
/// kCount consecutive values from p (any alignment).
inline I load(const int32_t* p) {
  I v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
/// kCount consecutive values to p (any alignment).
inline void store(float* p, F v) { std::memcpy(p, &v, sizeof v); }
/// kCount consecutive values to p (any alignment).
inline void store(int32_t* p, I v) { std::memcpy(p, &v, sizeof v); }

/// Per lane, mask ? a : b (mask lanes -1 or 0).
inline F select(I mask, F a, F b) { return mask != 0 ? a : b; }
/// Per lane, mask ? a : b (mask lanes -1 or 0).
inline I select(I mask, I a, I b) { return mask != 0 ? a : b; }
/// Per lane, the smaller (b where either is NaN, as std::min(b, a) would give): a < b ? a : b,
/// which is MINPS (GCC compiles the vector form to a comparison and a blend).
inline F min(F a, F b) {
#if defined(__AVX__)
  return reinterpret_cast<F>(_mm256_min_ps(reinterpret_cast<__m256>(a), reinterpret_cast<__m256>(b)));
#else
  return reinterpret_cast<F>(_mm_min_ps(reinterpret_cast<__m128>(a), reinterpret_cast<__m128>(b)));
#endif
}
/// Per lane, the larger (b where either is NaN): a > b ? a : b, which is MAXPS.
inline F max(F a, F b) {
#if defined(__AVX__)
  return reinterpret_cast<F>(_mm256_max_ps(reinterpret_cast<__m256>(a), reinterpret_cast<__m256>(b)));
#else
  return reinterpret_cast<F>(_mm_max_ps(reinterpret_cast<__m128>(a), reinterpret_cast<__m128>(b)));
#endif
}
/// Per lane, the smaller.
inline I min(I a, I b) { return a < b ? a : b; }
/// Per lane, the larger.
inline I max(I a, I b) { return a > b ? a : b; }
/// Per lane, v clamped to [lo, hi] (as std::clamp).
inline F clamp(F v, F lo, F hi) { return v < lo ? lo : (hi < v ? hi : v); }
/// Per lane, v clamped to [lo, hi] (as std::clamp).
inline I clamp(I v, I lo, I hi) { return v < lo ? lo : (hi < v ? hi : v); }
/// Per lane, |v|.
inline F abs(F v) { return select(v < 0.0f, -v, v); }
/// Per lane, -1 where v is finite (neither infinite nor NaN).
inline I finite(F v) { return (v - v) == 0.0f; }

/// Per lane, float to int rounding toward zero (as static_cast<int>; the lanes must be in range).
inline I truncate(F v) { return __builtin_convertvector(v, I); }
/// Per lane, int to float.
inline F toFloat(I v) { return __builtin_convertvector(v, F); }
/// Per lane, floor as an int (as static_cast<int>(std::floor(v)); the lanes must be in range).
inline I floorToInt(F v) {
  const I t = truncate(v);
  return t + (toFloat(t) > v);   // -1 where truncation rounded up
}

/// Per lane, the correctly rounded square root (as std::sqrt).
inline F sqrt(F v) {
#if defined(__AVX__)
  return __builtin_ia32_sqrtps256(v);
#elif defined(__SSE__)
  return __builtin_ia32_sqrtps(v);
#else
  F r;
  for (int i = 0; i < kCount; ++i) r[i] = __builtin_sqrtf(v[i]);
  return r;
#endif
}

/// True when any lane of the mask is set.
inline bool any(I mask) {
#if defined(__AVX__)
  return __builtin_ia32_movmskps256(__builtin_bit_cast(F, mask)) != 0;
#elif defined(__SSE__)
  return __builtin_ia32_movmskps(__builtin_bit_cast(F, mask)) != 0;
#else
  int32_t m = 0;
  for (int i = 0; i < kCount; ++i) m |= mask[i];
  return m != 0;
#endif
}
/// True when every lane of the mask is set.
inline bool all(I mask) {
#if defined(__AVX__)
  return __builtin_ia32_movmskps256(__builtin_bit_cast(F, mask)) == 0xff;
#elif defined(__SSE__)
  return __builtin_ia32_movmskps(__builtin_bit_cast(F, mask)) == 0xf;
#else
  int32_t m = -1;
  for (int i = 0; i < kCount; ++i) m &= mask[i];
  return m != 0;
#endif
}

/// Per lane, base[index].
inline F gather(const float* base, I index) {
  F r;
  for (int i = 0; i < kCount; ++i) r[i] = base[index[i]];
  return r;
}
/// Per lane, base[index].
inline I gather(const int32_t* base, I index) {
  I r;
  for (int i = 0; i < kCount; ++i) r[i] = base[index[i]];
  return r;
}

/// Per lane, p[offset] for offsets in [0, kCount): one load and a permutation.
inline F permute1(const float* p, I offset) { return __builtin_shuffle(load(p), offset); }
/// Per lane, p[offset] for offsets in [0, kCount): one load and a permutation.
inline I permute1(const int32_t* p, I offset) { return __builtin_shuffle(load(p), offset); }
/// Per lane, p[offset] for offsets in [0, 2 kCount): two loads and a permutation (p[0 .. 2 kCount - 1] readable).
inline F permute(const float* p, I offset) { return __builtin_shuffle(load(p), load(p + kCount), offset); }
/// Per lane, p[offset] for offsets in [0, 2 kCount): two loads and a permutation (p[0 .. 2 kCount - 1] readable).
inline I permute(const int32_t* p, I offset) { return __builtin_shuffle(load(p), load(p + kCount), offset); }

}  // namespace pa::taau::lanes
