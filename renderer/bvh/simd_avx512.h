#pragma once
// AVX-512 (F/VL/BW/DQ) lanes for the wide traversal kernels: 8 and 16 floats whose comparisons
// go straight to mask registers, and the pieces both AVX-512 kernels share (the accurate plane
// distance of eight pack lanes in double, compressed stores). Every function carries the
// AVX-512 target attribute itself, so the header may only be included by the AVX-512 kernel
// files (x86-64-v3 builds) and its code only runs where the CPU has AVX-512.
#include <cstdint>

#include <immintrin.h>

#include "renderer/core/ray.h"

#if !defined(__AVX2__)
#error "simd_avx512.h is for x86-64-v3 builds"
#endif

/// Target attribute of every AVX-512 function.
#define PA_AVX512 __attribute__((target("avx512f,avx512vl,avx512bw,avx512dq")))
/// Target attribute of the small wrappers, which must always inline.
#define PA_AVX512_INLINE __attribute__((target("avx512f,avx512vl,avx512bw,avx512dq"), always_inline)) inline

namespace pa::simd::avx512 {

/// Comparison result: one bit per lane (a mask register's contents).
struct LaneMask {
  unsigned bits;
  /// The lanes' bits.
  unsigned mask() const { return bits; }
  friend LaneMask operator|(LaneMask a, LaneMask b) { return {a.bits | b.bits}; }
  friend LaneMask operator&(LaneMask a, LaneMask b) { return {a.bits & b.bits}; }
};

/// 8 floats in a 256-bit register, compared into mask registers.
struct vfloat8 {
  __m256 v;
  vfloat8() = default;
  PA_AVX512_INLINE vfloat8(__m256 x) : v(x) {}
  PA_AVX512_INLINE explicit vfloat8(float x) : v(_mm256_set1_ps(x)) {}
  PA_AVX512_INLINE static vfloat8 load(const float* p) { return _mm256_load_ps(p); }
  PA_AVX512_INLINE void store(float* p) const { _mm256_store_ps(p, v); }
  PA_AVX512_INLINE friend vfloat8 operator+(vfloat8 a, vfloat8 b) { return _mm256_add_ps(a.v, b.v); }
  PA_AVX512_INLINE friend vfloat8 operator-(vfloat8 a, vfloat8 b) { return _mm256_sub_ps(a.v, b.v); }
  PA_AVX512_INLINE friend vfloat8 operator*(vfloat8 a, vfloat8 b) { return _mm256_mul_ps(a.v, b.v); }
  PA_AVX512_INLINE friend vfloat8 operator/(vfloat8 a, vfloat8 b) { return _mm256_div_ps(a.v, b.v); }
  PA_AVX512_INLINE friend LaneMask operator<(vfloat8 a, vfloat8 b) { return {_mm256_cmp_ps_mask(a.v, b.v, _CMP_LT_OQ)}; }
  PA_AVX512_INLINE friend LaneMask operator<=(vfloat8 a, vfloat8 b) { return {_mm256_cmp_ps_mask(a.v, b.v, _CMP_LE_OQ)}; }
  PA_AVX512_INLINE friend LaneMask operator>(vfloat8 a, vfloat8 b) { return {_mm256_cmp_ps_mask(a.v, b.v, _CMP_GT_OQ)}; }
  PA_AVX512_INLINE friend LaneMask operator>=(vfloat8 a, vfloat8 b) { return {_mm256_cmp_ps_mask(a.v, b.v, _CMP_GE_OQ)}; }
  PA_AVX512_INLINE friend LaneMask operator==(vfloat8 a, vfloat8 b) { return {_mm256_cmp_ps_mask(a.v, b.v, _CMP_EQ_OQ)}; }
  PA_AVX512_INLINE friend LaneMask operator!=(vfloat8 a, vfloat8 b) { return {_mm256_cmp_ps_mask(a.v, b.v, _CMP_NEQ_UQ)}; }
};
/// max(a, b) per lane; where a is NaN the result is b (x86 maxps semantics).
PA_AVX512_INLINE vfloat8 maxKeep(vfloat8 a, vfloat8 b) { return _mm256_max_ps(a.v, b.v); }
/// min(a, b) per lane; where a is NaN the result is b.
PA_AVX512_INLINE vfloat8 minKeep(vfloat8 a, vfloat8 b) { return _mm256_min_ps(a.v, b.v); }
/// b where mask has the lane's bit, else a.
PA_AVX512_INLINE vfloat8 select(unsigned mask, vfloat8 a, vfloat8 b) {
  return _mm256_mask_mov_ps(a.v, static_cast<__mmask8>(mask), b.v);
}

/// 16 floats in a 512-bit register, compared into mask registers.
struct vfloat16 {
  __m512 v;
  vfloat16() = default;
  PA_AVX512_INLINE vfloat16(__m512 x) : v(x) {}
  PA_AVX512_INLINE explicit vfloat16(float x) : v(_mm512_set1_ps(x)) {}
  PA_AVX512_INLINE static vfloat16 load(const float* p) { return _mm512_load_ps(p); }
  PA_AVX512_INLINE void store(float* p) const { _mm512_store_ps(p, v); }
  PA_AVX512_INLINE friend vfloat16 operator+(vfloat16 a, vfloat16 b) { return _mm512_add_ps(a.v, b.v); }
  PA_AVX512_INLINE friend vfloat16 operator-(vfloat16 a, vfloat16 b) { return _mm512_sub_ps(a.v, b.v); }
  PA_AVX512_INLINE friend vfloat16 operator*(vfloat16 a, vfloat16 b) { return _mm512_mul_ps(a.v, b.v); }
  PA_AVX512_INLINE friend vfloat16 operator/(vfloat16 a, vfloat16 b) { return _mm512_div_ps(a.v, b.v); }
  PA_AVX512_INLINE friend LaneMask operator<(vfloat16 a, vfloat16 b) { return {_mm512_cmp_ps_mask(a.v, b.v, _CMP_LT_OQ)}; }
  PA_AVX512_INLINE friend LaneMask operator<=(vfloat16 a, vfloat16 b) { return {_mm512_cmp_ps_mask(a.v, b.v, _CMP_LE_OQ)}; }
  PA_AVX512_INLINE friend LaneMask operator>(vfloat16 a, vfloat16 b) { return {_mm512_cmp_ps_mask(a.v, b.v, _CMP_GT_OQ)}; }
  PA_AVX512_INLINE friend LaneMask operator>=(vfloat16 a, vfloat16 b) { return {_mm512_cmp_ps_mask(a.v, b.v, _CMP_GE_OQ)}; }
  PA_AVX512_INLINE friend LaneMask operator==(vfloat16 a, vfloat16 b) { return {_mm512_cmp_ps_mask(a.v, b.v, _CMP_EQ_OQ)}; }
  PA_AVX512_INLINE friend LaneMask operator!=(vfloat16 a, vfloat16 b) { return {_mm512_cmp_ps_mask(a.v, b.v, _CMP_NEQ_UQ)}; }
};
/// max(a, b) per lane; where a is NaN the result is b.
PA_AVX512_INLINE vfloat16 maxKeep(vfloat16 a, vfloat16 b) { return _mm512_max_ps(a.v, b.v); }
/// min(a, b) per lane; where a is NaN the result is b.
PA_AVX512_INLINE vfloat16 minKeep(vfloat16 a, vfloat16 b) { return _mm512_min_ps(a.v, b.v); }
/// b where mask has the lane's bit, else a.
PA_AVX512_INLINE vfloat16 select(unsigned mask, vfloat16 a, vfloat16 b) {
  return _mm512_mask_mov_ps(a.v, static_cast<__mmask16>(mask), b.v);
}

/// Stores the lanes of v set in mask to p, packed in lane order (one register compress, then
/// one full-width store: p needs a register's worth of room).
PA_AVX512_INLINE void compressStore(uint32_t* p, unsigned mask, __m256i v) {
  _mm256_storeu_si256(reinterpret_cast<__m256i*>(p), _mm256_maskz_compress_epi32(static_cast<__mmask8>(mask), v));
}
PA_AVX512_INLINE void compressStore(float* p, unsigned mask, vfloat8 v) {
  _mm256_storeu_ps(p, _mm256_maskz_compress_ps(static_cast<__mmask8>(mask), v.v));
}
PA_AVX512_INLINE void compressStore(uint32_t* p, unsigned mask, __m512i v) {
  _mm512_storeu_si512(p, _mm512_maskz_compress_epi32(static_cast<__mmask16>(mask), v));
}
PA_AVX512_INLINE void compressStore(float* p, unsigned mask, vfloat16 v) {
  _mm512_storeu_ps(p, _mm512_maskz_compress_ps(static_cast<__mmask16>(mask), v.v));
}

/// Pushes the lanes of children set in mask onto a traversal stack (node[], entry[], top; see
/// wide_traversal_stack.h) in lane order, with their entry distances where kWithDistance: one
/// register compress each.
template <bool kWithDistance, class Stack, class Children, class Float>
PA_AVX512_INLINE void compressPush(Stack& stack, unsigned mask, Children children, Float entry) {
  compressStore(stack.node + stack.top, mask, children);
  if constexpr (kWithDistance) compressStore(stack.entry + stack.top, mask, entry);
  stack.top += __builtin_popcount(mask);
}

/// Per-ray constants of the accurate plane distance, in double.
struct PlaneRay {
  __m512d ox, oy, oz, dx, dy, dz;
  PA_AVX512_INLINE explicit PlaneRay(const Ray& ray)
      : ox(_mm512_set1_pd(ray.origin.x)), oy(_mm512_set1_pd(ray.origin.y)), oz(_mm512_set1_pd(ray.origin.z)),
        dx(_mm512_set1_pd(ray.dir.x)), dy(_mm512_set1_pd(ray.dir.y)), dz(_mm512_set1_pd(ray.dir.z)) {}
};

/// Eight floats of p, widened to double.
PA_AVX512_INLINE __m512d loadWidened(const float* p) { return _mm512_cvtps_pd(_mm256_load_ps(p)); }

/// planeHitDistance (watertight.h) for the eight lanes of a pack (of any width) starting at
/// lane0: the same double operations in the same order; lanes where the ray is parallel to the
/// plane take fallback.
template <class Pack>
PA_AVX512_INLINE __m256 planeDistances8(const Pack& pack, int lane0, const PlaneRay& r, __m256 fallback) {
  const __m512d v0x = loadWidened(pack.v[0][0] + lane0), v0y = loadWidened(pack.v[0][1] + lane0),
                v0z = loadWidened(pack.v[0][2] + lane0);
  const __m512d e1x = _mm512_sub_pd(loadWidened(pack.v[1][0] + lane0), v0x),
                e1y = _mm512_sub_pd(loadWidened(pack.v[1][1] + lane0), v0y),
                e1z = _mm512_sub_pd(loadWidened(pack.v[1][2] + lane0), v0z);
  const __m512d e2x = _mm512_sub_pd(loadWidened(pack.v[2][0] + lane0), v0x),
                e2y = _mm512_sub_pd(loadWidened(pack.v[2][1] + lane0), v0y),
                e2z = _mm512_sub_pd(loadWidened(pack.v[2][2] + lane0), v0z);
  const __m512d nx = _mm512_sub_pd(_mm512_mul_pd(e1y, e2z), _mm512_mul_pd(e1z, e2y));
  const __m512d ny = _mm512_sub_pd(_mm512_mul_pd(e1z, e2x), _mm512_mul_pd(e1x, e2z));
  const __m512d nz = _mm512_sub_pd(_mm512_mul_pd(e1x, e2y), _mm512_mul_pd(e1y, e2x));
  const __m512d denom =
      _mm512_add_pd(_mm512_add_pd(_mm512_mul_pd(nx, r.dx), _mm512_mul_pd(ny, r.dy)), _mm512_mul_pd(nz, r.dz));
  const __m512d num = _mm512_add_pd(_mm512_add_pd(_mm512_mul_pd(nx, _mm512_sub_pd(v0x, r.ox)),
                                                  _mm512_mul_pd(ny, _mm512_sub_pd(v0y, r.oy))),
                                    _mm512_mul_pd(nz, _mm512_sub_pd(v0z, r.oz)));
  const __mmask8 parallel = _mm512_cmp_pd_mask(denom, _mm512_setzero_pd(), _CMP_EQ_OQ);
  return _mm256_mask_mov_ps(_mm512_cvtpd_ps(_mm512_div_pd(num, denom)), parallel, fallback);
}

/// a * b - c * d for eight lanes, computed in double and rounded to float (the exact
/// edge-function fallback of watertight.h).
PA_AVX512_INLINE __m256 differenceOfProductsInDouble(__m256 a, __m256 b, __m256 c, __m256 d) {
  return _mm512_cvtpd_ps(_mm512_sub_pd(_mm512_mul_pd(_mm512_cvtps_pd(a), _mm512_cvtps_pd(b)),
                                       _mm512_mul_pd(_mm512_cvtps_pd(c), _mm512_cvtps_pd(d))));
}

}  // namespace pa::simd::avx512
