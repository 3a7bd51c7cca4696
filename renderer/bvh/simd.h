#pragma once
// Minimal SIMD wrapper for the BVH kernels' baseline lanes: 8-wide floats (the AVX-512 lanes
// are in simd_avx512.h).
// With AVX2 (the x86-64-v3 build target) vfloat8 is one __m256. Without it (the x86-64-v2
// fallback, SSE4.2) vfloat8 is emulated with two __m128 halves, so the same kernels compile
// and give bit-identical results, only slower. Only what the kernels need is provided.
#include <algorithm>
#include <bit>
#include <cstdint>
#include <limits>

#include <immintrin.h>

#if !defined(__SSE4_1__)
#error "pa_bvh needs at least SSE4.1 (x86-64-v2)"
#endif

namespace pa::simd {

#if defined(__AVX2__)
/// 8 floats (AVX2).
struct vfloat8 {
  __m256 v;
  vfloat8() = default;
  vfloat8(__m256 x) : v(x) {}
  explicit vfloat8(float x) : v(_mm256_set1_ps(x)) {}
  static vfloat8 load(const float* p) { return _mm256_load_ps(p); }
  friend vfloat8 operator+(vfloat8 a, vfloat8 b) { return _mm256_add_ps(a.v, b.v); }
  friend vfloat8 operator-(vfloat8 a, vfloat8 b) { return _mm256_sub_ps(a.v, b.v); }
  friend vfloat8 operator*(vfloat8 a, vfloat8 b) { return _mm256_mul_ps(a.v, b.v); }
  friend vfloat8 operator/(vfloat8 a, vfloat8 b) { return _mm256_div_ps(a.v, b.v); }
  friend vfloat8 operator&(vfloat8 a, vfloat8 b) { return _mm256_and_ps(a.v, b.v); }
  friend vfloat8 operator|(vfloat8 a, vfloat8 b) { return _mm256_or_ps(a.v, b.v); }
  friend vfloat8 operator<(vfloat8 a, vfloat8 b) { return _mm256_cmp_ps(a.v, b.v, _CMP_LT_OQ); }
  friend vfloat8 operator<=(vfloat8 a, vfloat8 b) { return _mm256_cmp_ps(a.v, b.v, _CMP_LE_OQ); }
  friend vfloat8 operator>(vfloat8 a, vfloat8 b) { return _mm256_cmp_ps(a.v, b.v, _CMP_GT_OQ); }
  friend vfloat8 operator>=(vfloat8 a, vfloat8 b) { return _mm256_cmp_ps(a.v, b.v, _CMP_GE_OQ); }
  friend vfloat8 operator==(vfloat8 a, vfloat8 b) { return _mm256_cmp_ps(a.v, b.v, _CMP_EQ_OQ); }
  friend vfloat8 operator!=(vfloat8 a, vfloat8 b) { return _mm256_cmp_ps(a.v, b.v, _CMP_NEQ_UQ); }
  /// One bit per lane.
  int mask() const { return _mm256_movemask_ps(v); }
  void store(float* p) const { _mm256_store_ps(p, v); }
};
/// max(a, b) per lane; where a is NaN the result is b (x86 maxps semantics).
inline vfloat8 maxKeep(vfloat8 a, vfloat8 b) { return _mm256_max_ps(a.v, b.v); }
/// min(a, b) per lane; where a is NaN the result is b.
inline vfloat8 minKeep(vfloat8 a, vfloat8 b) { return _mm256_min_ps(a.v, b.v); }
#else
/// 8 floats emulated with two SSE halves (x86-64-v2 fallback).
struct vfloat8 {
  __m128 lo, hi;
  vfloat8() = default;
  vfloat8(__m128 l, __m128 h) : lo(l), hi(h) {}
  explicit vfloat8(float x) : lo(_mm_set1_ps(x)), hi(_mm_set1_ps(x)) {}
  static vfloat8 load(const float* p) { return {_mm_load_ps(p), _mm_load_ps(p + 4)}; }
  friend vfloat8 operator+(vfloat8 a, vfloat8 b) { return {_mm_add_ps(a.lo, b.lo), _mm_add_ps(a.hi, b.hi)}; }
  friend vfloat8 operator-(vfloat8 a, vfloat8 b) { return {_mm_sub_ps(a.lo, b.lo), _mm_sub_ps(a.hi, b.hi)}; }
  friend vfloat8 operator*(vfloat8 a, vfloat8 b) { return {_mm_mul_ps(a.lo, b.lo), _mm_mul_ps(a.hi, b.hi)}; }
  friend vfloat8 operator/(vfloat8 a, vfloat8 b) { return {_mm_div_ps(a.lo, b.lo), _mm_div_ps(a.hi, b.hi)}; }
  friend vfloat8 operator&(vfloat8 a, vfloat8 b) { return {_mm_and_ps(a.lo, b.lo), _mm_and_ps(a.hi, b.hi)}; }
  friend vfloat8 operator|(vfloat8 a, vfloat8 b) { return {_mm_or_ps(a.lo, b.lo), _mm_or_ps(a.hi, b.hi)}; }
  friend vfloat8 operator<(vfloat8 a, vfloat8 b) { return {_mm_cmplt_ps(a.lo, b.lo), _mm_cmplt_ps(a.hi, b.hi)}; }
  friend vfloat8 operator<=(vfloat8 a, vfloat8 b) { return {_mm_cmple_ps(a.lo, b.lo), _mm_cmple_ps(a.hi, b.hi)}; }
  friend vfloat8 operator>(vfloat8 a, vfloat8 b) { return {_mm_cmpgt_ps(a.lo, b.lo), _mm_cmpgt_ps(a.hi, b.hi)}; }
  friend vfloat8 operator>=(vfloat8 a, vfloat8 b) { return {_mm_cmpge_ps(a.lo, b.lo), _mm_cmpge_ps(a.hi, b.hi)}; }
  friend vfloat8 operator==(vfloat8 a, vfloat8 b) { return {_mm_cmpeq_ps(a.lo, b.lo), _mm_cmpeq_ps(a.hi, b.hi)}; }
  friend vfloat8 operator!=(vfloat8 a, vfloat8 b) { return {_mm_cmpneq_ps(a.lo, b.lo), _mm_cmpneq_ps(a.hi, b.hi)}; }
  /// One bit per lane.
  int mask() const { return _mm_movemask_ps(lo) | (_mm_movemask_ps(hi) << 4); }
  void store(float* p) const { _mm_store_ps(p, lo); _mm_store_ps(p + 4, hi); }
};
/// max(a, b) per lane; where a is NaN the result is b (x86 maxps semantics).
inline vfloat8 maxKeep(vfloat8 a, vfloat8 b) { return {_mm_max_ps(a.lo, b.lo), _mm_max_ps(a.hi, b.hi)}; }
/// min(a, b) per lane; where a is NaN the result is b.
inline vfloat8 minKeep(vfloat8 a, vfloat8 b) { return {_mm_min_ps(a.lo, b.lo), _mm_min_ps(a.hi, b.hi)}; }
#endif

/// The lanes of a lane-bit mask as a float mask (all bits set where the lane's bit is).
inline vfloat8 laneMask(unsigned mask) {
#if defined(__AVX2__)
  const __m256i bit = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
  return _mm256_castsi256_ps(
      _mm256_cmpeq_epi32(_mm256_and_si256(_mm256_set1_epi32(static_cast<int>(mask)), bit), bit));
#else
  const __m128i bitLo = _mm_setr_epi32(1, 2, 4, 8), bitHi = _mm_setr_epi32(16, 32, 64, 128);
  const __m128i m = _mm_set1_epi32(static_cast<int>(mask));
  return {_mm_castsi128_ps(_mm_cmpeq_epi32(_mm_and_si128(m, bitLo), bitLo)),
          _mm_castsi128_ps(_mm_cmpeq_epi32(_mm_and_si128(m, bitHi), bitHi))};
#endif
}
/// b where mask has the lane's bit, else a.
inline vfloat8 select(unsigned mask, vfloat8 a, vfloat8 b) {
  const vfloat8 m = laneMask(mask);
#if defined(__AVX2__)
  return _mm256_blendv_ps(a.v, b.v, m.v);
#else
  return {_mm_blendv_ps(a.lo, b.lo, m.lo), _mm_blendv_ps(a.hi, b.hi, m.hi)};
#endif
}
/// |a| per lane.
inline vfloat8 abs(vfloat8 a) {
  const vfloat8 magnitude(std::bit_cast<float>(0x7fffffffu));
  return a & magnitude;
}
namespace detail {
/// The lanes of `a` in mask that hold a number; `fill` in the others.
inline vfloat8 lanesOrFill(vfloat8 a, unsigned mask, float fill) {
  return select(mask & static_cast<unsigned>((a == a).mask()), vfloat8(fill), a);
}
/// Lanes 0-3 and 4-7 of a.
inline void halves(vfloat8 a, __m128& lo, __m128& hi) {
#if defined(__AVX2__)
  lo = _mm256_castps256_ps128(a.v), hi = _mm256_extractf128_ps(a.v, 1);
#else
  lo = a.lo, hi = a.hi;
#endif
}
}  // namespace detail

/// The smallest of the lanes in mask (+inf when none; NaN lanes are passed over), reduced in
/// registers: the packet kernels take several per packet and per leaf, and a loop over the lanes
/// after a store was a chain of dependent scalar operations.
inline float minOverLanes(vfloat8 a, unsigned mask) {
  __m128 lo, hi;
  detail::halves(detail::lanesOrFill(a, mask, std::numeric_limits<float>::infinity()), lo, hi);
  __m128 r = _mm_min_ps(lo, hi);
  r = _mm_min_ps(r, _mm_movehl_ps(r, r));
  return _mm_cvtss_f32(_mm_min_ss(r, _mm_movehdup_ps(r)));
}
/// The largest of the lanes in mask (-inf when none; NaN lanes are passed over).
inline float maxOverLanes(vfloat8 a, unsigned mask) {
  __m128 lo, hi;
  detail::halves(detail::lanesOrFill(a, mask, -std::numeric_limits<float>::infinity()), lo, hi);
  __m128 r = _mm_max_ps(lo, hi);
  r = _mm_max_ps(r, _mm_movehl_ps(r, r));
  return _mm_cvtss_f32(_mm_max_ss(r, _mm_movehdup_ps(r)));
}

#if defined(__AVX2__)
/// Eight rows of eight floats (any alignment) as eight columns: lane i of out[k] is rows[i][k].
/// Eight loads and 24 shuffles: what eight gathers of one field each would read.
inline void transposeEight(const float* const rows[8], __m256 out[8]) {
  __m256 r[8], t[8];
  for (int i = 0; i < 8; ++i) r[i] = _mm256_loadu_ps(rows[i]);
  for (int i = 0; i < 8; i += 2) {
    t[i] = _mm256_unpacklo_ps(r[i], r[i + 1]);       // a0 b0 a1 b1 | a4 b4 a5 b5
    t[i + 1] = _mm256_unpackhi_ps(r[i], r[i + 1]);   // a2 b2 a3 b3 | a6 b6 a7 b7
  }
  for (int i = 0; i < 8; i += 4) {
    r[i] = _mm256_shuffle_ps(t[i], t[i + 2], 0x44);       // column 0 | 4 of rows i..i+3
    r[i + 1] = _mm256_shuffle_ps(t[i], t[i + 2], 0xee);   // column 1 | 5
    r[i + 2] = _mm256_shuffle_ps(t[i + 1], t[i + 3], 0x44);   // column 2 | 6
    r[i + 3] = _mm256_shuffle_ps(t[i + 1], t[i + 3], 0xee);   // column 3 | 7
  }
  for (int k = 0; k < 4; ++k) {
    out[k] = _mm256_permute2f128_ps(r[k], r[k + 4], 0x20);
    out[k + 4] = _mm256_permute2f128_ps(r[k], r[k + 4], 0x31);
  }
}
#endif

/// Sixteen lanes as two vfloat8 (lanes 0-7 in lo, 8-15 in hi): the baseline kernels' camera-ray
/// packets of sixteen rays, one ray per lane. Each operation is vfloat8's on both halves.
struct vfloat8x2 {
  vfloat8 lo, hi;
  vfloat8x2() = default;
  vfloat8x2(vfloat8 l, vfloat8 h) : lo(l), hi(h) {}
  explicit vfloat8x2(float x) : lo(x), hi(x) {}
  static vfloat8x2 load(const float* p) { return {vfloat8::load(p), vfloat8::load(p + 8)}; }
  void store(float* p) const { lo.store(p), hi.store(p + 8); }
  /// One bit per lane.
  int mask() const { return lo.mask() | hi.mask() << 8; }
#define PA_SIMD_PAIR_OP(op) \
  friend vfloat8x2 operator op(vfloat8x2 a, vfloat8x2 b) { return {a.lo op b.lo, a.hi op b.hi}; }
  PA_SIMD_PAIR_OP(+) PA_SIMD_PAIR_OP(-) PA_SIMD_PAIR_OP(*) PA_SIMD_PAIR_OP(/) PA_SIMD_PAIR_OP(&)
  PA_SIMD_PAIR_OP(|) PA_SIMD_PAIR_OP(<) PA_SIMD_PAIR_OP(<=) PA_SIMD_PAIR_OP(>) PA_SIMD_PAIR_OP(>=)
  PA_SIMD_PAIR_OP(==) PA_SIMD_PAIR_OP(!=)
#undef PA_SIMD_PAIR_OP
};
/// max(a, b) per lane; where a is NaN the result is b.
inline vfloat8x2 maxKeep(vfloat8x2 a, vfloat8x2 b) { return {maxKeep(a.lo, b.lo), maxKeep(a.hi, b.hi)}; }
/// min(a, b) per lane; where a is NaN the result is b.
inline vfloat8x2 minKeep(vfloat8x2 a, vfloat8x2 b) { return {minKeep(a.lo, b.lo), minKeep(a.hi, b.hi)}; }
/// b where mask has the lane's bit, else a.
inline vfloat8x2 select(unsigned mask, vfloat8x2 a, vfloat8x2 b) {
  return {select(mask & 0xffu, a.lo, b.lo), select(mask >> 8 & 0xffu, a.hi, b.hi)};
}
/// |a| per lane.
inline vfloat8x2 abs(vfloat8x2 a) { return {abs(a.lo), abs(a.hi)}; }
/// The smallest of the lanes in mask (+inf when none; NaN lanes are passed over).
inline float minOverLanes(vfloat8x2 a, unsigned mask) {
  return std::min(minOverLanes(a.lo, mask & 0xffu), minOverLanes(a.hi, mask >> 8 & 0xffu));
}
/// The largest of the lanes in mask (-inf when none; NaN lanes are passed over).
inline float maxOverLanes(vfloat8x2 a, unsigned mask) {
  return std::max(maxOverLanes(a.lo, mask & 0xffu), maxOverLanes(a.hi, mask >> 8 & 0xffu));
}

}  // namespace pa::simd
