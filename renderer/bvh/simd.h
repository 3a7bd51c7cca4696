#pragma once
// Minimal SIMD wrapper for the BVH kernels' baseline lanes: 4- and 8-wide floats (the AVX-512
// lanes are in simd_avx512.h).
// With AVX2 (the x86-64-v3 build target) vfloat8 is one __m256. Without it (the x86-64-v2
// fallback, SSE4.2) vfloat8 is emulated with two __m128 halves, so the same kernels compile
// and give bit-identical results, only slower. Only what the kernels need is provided.
#include <cstdint>

#include <immintrin.h>

#if !defined(__SSE4_1__)
#error "pa_bvh needs at least SSE4.1 (x86-64-v2)"
#endif

namespace pa::simd {

/// 4 floats (SSE).
struct vfloat4 {
  __m128 v;
  vfloat4() = default;
  vfloat4(__m128 x) : v(x) {}
  explicit vfloat4(float x) : v(_mm_set1_ps(x)) {}
  static vfloat4 load(const float* p) { return _mm_load_ps(p); }
  friend vfloat4 operator+(vfloat4 a, vfloat4 b) { return _mm_add_ps(a.v, b.v); }
  friend vfloat4 operator-(vfloat4 a, vfloat4 b) { return _mm_sub_ps(a.v, b.v); }
  friend vfloat4 operator*(vfloat4 a, vfloat4 b) { return _mm_mul_ps(a.v, b.v); }
  friend vfloat4 operator/(vfloat4 a, vfloat4 b) { return _mm_div_ps(a.v, b.v); }
  friend vfloat4 operator^(vfloat4 a, vfloat4 b) { return _mm_xor_ps(a.v, b.v); }
  friend vfloat4 operator&(vfloat4 a, vfloat4 b) { return _mm_and_ps(a.v, b.v); }
  friend vfloat4 operator|(vfloat4 a, vfloat4 b) { return _mm_or_ps(a.v, b.v); }
  friend vfloat4 operator<(vfloat4 a, vfloat4 b) { return _mm_cmplt_ps(a.v, b.v); }
  friend vfloat4 operator<=(vfloat4 a, vfloat4 b) { return _mm_cmple_ps(a.v, b.v); }
  friend vfloat4 operator>(vfloat4 a, vfloat4 b) { return _mm_cmpgt_ps(a.v, b.v); }
  friend vfloat4 operator>=(vfloat4 a, vfloat4 b) { return _mm_cmpge_ps(a.v, b.v); }
  friend vfloat4 operator==(vfloat4 a, vfloat4 b) { return _mm_cmpeq_ps(a.v, b.v); }
  friend vfloat4 operator!=(vfloat4 a, vfloat4 b) { return _mm_cmpneq_ps(a.v, b.v); }
  /// One bit per lane from the lanes' sign bits (comparison results).
  int mask() const { return _mm_movemask_ps(v); }
  void store(float* p) const { _mm_store_ps(p, v); }
};

/// The sign bit of each lane of a, as a float mask.
inline vfloat4 signBits(vfloat4 a) { return a & vfloat4(_mm_castsi128_ps(_mm_set1_epi32(INT32_MIN))); }

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

}  // namespace pa::simd
