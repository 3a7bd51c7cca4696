#pragma once
// AVX-512 (F/VL/BW/DQ) lanes for the wide traversal kernels: vfloat<8> and vfloat<16>, floats
// whose comparisons go straight to mask registers, and the pieces the AVX-512 kernels share
// (the accurate plane distance of eight pack lanes in double, compressed stores). Every
// function carries the AVX-512 target attribute itself, so the header may only be included by
// the AVX-512 kernel file (x86-64-v3 builds) and its code only runs where the CPU has AVX-512.
#include <cstdint>
#include <limits>

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

/// The register of kLanes floats.
template <int kLanes>
struct RegisterOf;
template <>
struct RegisterOf<8> {
  using type = __m256;
};
template <>
struct RegisterOf<16> {
  using type = __m512;
};

/// kLanes (8 or 16) floats in one register (256 or 512 bits), compared into mask registers.
/// Arithmetic uses the compiler's vector operators (one vaddps, vmulps, ... as the intrinsics).
template <int kLanes>
struct vfloat {
  using Register = typename RegisterOf<kLanes>::type;
  Register v;
  vfloat() = default;
  PA_AVX512_INLINE vfloat(Register x) : v(x) {}
  PA_AVX512_INLINE explicit vfloat(float x) {
    if constexpr (kLanes == 8) v = _mm256_set1_ps(x);
    else v = _mm512_set1_ps(x);
  }
  PA_AVX512_INLINE static vfloat load(const float* p) {
    if constexpr (kLanes == 8) return _mm256_load_ps(p);
    else return _mm512_load_ps(p);
  }
  PA_AVX512_INLINE void store(float* p) const {
    if constexpr (kLanes == 8) _mm256_store_ps(p, v);
    else _mm512_store_ps(p, v);
  }
  /// The lanes where `a kPredicate b` holds (a _CMP_* predicate).
  template <int kPredicate>
  PA_AVX512_INLINE static LaneMask compare(vfloat a, vfloat b) {
    if constexpr (kLanes == 8) return {_mm256_cmp_ps_mask(a.v, b.v, kPredicate)};
    else return {_mm512_cmp_ps_mask(a.v, b.v, kPredicate)};
  }
  PA_AVX512_INLINE friend vfloat operator+(vfloat a, vfloat b) { return a.v + b.v; }
  PA_AVX512_INLINE friend vfloat operator-(vfloat a, vfloat b) { return a.v - b.v; }
  PA_AVX512_INLINE friend vfloat operator*(vfloat a, vfloat b) { return a.v * b.v; }
  PA_AVX512_INLINE friend vfloat operator/(vfloat a, vfloat b) { return a.v / b.v; }
  PA_AVX512_INLINE friend LaneMask operator<(vfloat a, vfloat b) { return compare<_CMP_LT_OQ>(a, b); }
  PA_AVX512_INLINE friend LaneMask operator<=(vfloat a, vfloat b) { return compare<_CMP_LE_OQ>(a, b); }
  PA_AVX512_INLINE friend LaneMask operator>(vfloat a, vfloat b) { return compare<_CMP_GT_OQ>(a, b); }
  PA_AVX512_INLINE friend LaneMask operator>=(vfloat a, vfloat b) { return compare<_CMP_GE_OQ>(a, b); }
  PA_AVX512_INLINE friend LaneMask operator==(vfloat a, vfloat b) { return compare<_CMP_EQ_OQ>(a, b); }
  PA_AVX512_INLINE friend LaneMask operator!=(vfloat a, vfloat b) { return compare<_CMP_NEQ_UQ>(a, b); }
};
using vfloat8 = vfloat<8>;
using vfloat16 = vfloat<16>;

/// max(a, b) per lane; where a is NaN the result is b (x86 maxps semantics).
template <int N>
PA_AVX512_INLINE vfloat<N> maxKeep(vfloat<N> a, vfloat<N> b) {
  if constexpr (N == 8) return _mm256_max_ps(a.v, b.v);
  else return _mm512_max_ps(a.v, b.v);
}
/// min(a, b) per lane; where a is NaN the result is b.
template <int N>
PA_AVX512_INLINE vfloat<N> minKeep(vfloat<N> a, vfloat<N> b) {
  if constexpr (N == 8) return _mm256_min_ps(a.v, b.v);
  else return _mm512_min_ps(a.v, b.v);
}
/// b where mask has the lane's bit, else a.
template <int N>
PA_AVX512_INLINE vfloat<N> select(unsigned mask, vfloat<N> a, vfloat<N> b) {
  if constexpr (N == 8) return _mm256_mask_mov_ps(a.v, static_cast<__mmask8>(mask), b.v);
  else return _mm512_mask_mov_ps(a.v, static_cast<__mmask16>(mask), b.v);
}
/// |a| per lane.
template <int N>
PA_AVX512_INLINE vfloat<N> abs(vfloat<N> a) {
  if constexpr (N == 8) return _mm256_and_ps(a.v, _mm256_castsi256_ps(_mm256_set1_epi32(0x7fffffff)));
  else return _mm512_abs_ps(a.v);
}
/// The largest (kLargest) or smallest of the lanes in mask (-inf or +inf when none).
template <bool kLargest, int N>
PA_AVX512_INLINE float extremeOverLanes(vfloat<N> a, unsigned mask) {
  __m512 all;
  if constexpr (N == 16) all = a.v;
  else all = _mm512_castps256_ps512(a.v);   // the upper lanes are not in the mask
  const __mmask16 lanes = static_cast<__mmask16>(mask & ((1u << N) - 1));
  if constexpr (kLargest) return _mm512_mask_reduce_max_ps(lanes, all);
  else return _mm512_mask_reduce_min_ps(lanes, all);
}
/// The smallest of the lanes in mask (+inf when none).
template <int N>
PA_AVX512_INLINE float minOverLanes(vfloat<N> a, unsigned mask) { return extremeOverLanes<false>(a, mask); }
/// The largest of the lanes in mask (-inf when none).
template <int N>
PA_AVX512_INLINE float maxOverLanes(vfloat<N> a, unsigned mask) { return extremeOverLanes<true>(a, mask); }

/// Lanes 8 * part .. 8 * part + 7 of a register (part 0 of an 8-lane register is all of it).
template <int N>
PA_AVX512_INLINE __m256 eightLanes(vfloat<N> a, int part) {
  if constexpr (N == 8) return a.v;
  else return part == 0 ? _mm512_castps512_ps256(a.v) : _mm512_extractf32x8_ps(a.v, 1);
}
/// A register made of N / 8 parts of eight lanes, lowest first.
template <int N>
PA_AVX512_INLINE vfloat<N> joinEightLanes(const __m256* parts) {
  if constexpr (N == 8) return parts[0];
  else return _mm512_insertf32x8(_mm512_zextps256_ps512(parts[0]), parts[1], 1);
}

/// Stores the lanes of v set in mask to p, packed in lane order (one register compress, then
/// one full-width store: p needs a register's worth of room).
PA_AVX512_INLINE void compressStore(uint32_t* p, unsigned mask, __m256i v) {
  _mm256_storeu_si256(reinterpret_cast<__m256i*>(p), _mm256_maskz_compress_epi32(static_cast<__mmask8>(mask), v));
}
PA_AVX512_INLINE void compressStore(uint32_t* p, unsigned mask, __m512i v) {
  _mm512_storeu_si512(p, _mm512_maskz_compress_epi32(static_cast<__mmask16>(mask), v));
}
template <int N>
PA_AVX512_INLINE void compressStore(float* p, unsigned mask, vfloat<N> v) {
  if constexpr (N == 8) _mm256_storeu_ps(p, _mm256_maskz_compress_ps(static_cast<__mmask8>(mask), v.v));
  else _mm512_storeu_ps(p, _mm512_maskz_compress_ps(static_cast<__mmask16>(mask), v.v));
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

/// Eight floats of p, widened to double.
PA_AVX512_INLINE __m512d loadWidened(const float* p) { return _mm512_cvtps_pd(_mm256_load_ps(p)); }

/// The plane distance of planeHitDistance (watertight.h) for eight lanes, from the triangles'
/// normals and first vertices and the rays' origins and directions, all in double: the same
/// operations in the same order; lanes where the ray is parallel to the plane take fallback.
PA_AVX512_INLINE __m256 planeDistance8(__m512d nx, __m512d ny, __m512d nz, __m512d px, __m512d py, __m512d pz,
                                       __m512d ox, __m512d oy, __m512d oz, __m512d dx, __m512d dy, __m512d dz,
                                       __m256 fallback) {
  const __m512d denom =
      _mm512_add_pd(_mm512_add_pd(_mm512_mul_pd(nx, dx), _mm512_mul_pd(ny, dy)), _mm512_mul_pd(nz, dz));
  const __m512d num = _mm512_add_pd(_mm512_add_pd(_mm512_mul_pd(nx, _mm512_sub_pd(px, ox)),
                                                  _mm512_mul_pd(ny, _mm512_sub_pd(py, oy))),
                                    _mm512_mul_pd(nz, _mm512_sub_pd(pz, oz)));
  const __mmask8 parallel = _mm512_cmp_pd_mask(denom, _mm512_setzero_pd(), _CMP_EQ_OQ);
  return _mm256_mask_mov_ps(_mm512_cvtpd_ps(_mm512_div_pd(num, denom)), parallel, fallback);
}

/// Per-ray constants of the accurate plane distance, in double.
struct PlaneRay {
  __m512d ox, oy, oz, dx, dy, dz;
  PA_AVX512_INLINE explicit PlaneRay(const Ray& ray)
      : ox(_mm512_set1_pd(ray.origin.x)), oy(_mm512_set1_pd(ray.origin.y)), oz(_mm512_set1_pd(ray.origin.z)),
        dx(_mm512_set1_pd(ray.dir.x)), dy(_mm512_set1_pd(ray.dir.y)), dz(_mm512_set1_pd(ray.dir.z)) {}
};

/// planeHitDistance (watertight.h) for the eight lanes of a pack (of any width) starting at
/// lane0, for one ray; lanes where the ray is parallel to the plane take fallback.
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
  return planeDistance8(nx, ny, nz, v0x, v0y, v0z, r.ox, r.oy, r.oz, r.dx, r.dy, r.dz, fallback);
}

/// a * b - c * d for eight lanes, computed in double and rounded to float (the exact
/// edge-function fallback of watertight.h).
PA_AVX512_INLINE __m256 differenceOfProductsInDouble(__m256 a, __m256 b, __m256 c, __m256 d) {
  return _mm512_cvtpd_ps(_mm512_sub_pd(_mm512_mul_pd(_mm512_cvtps_pd(a), _mm512_cvtps_pd(b)),
                                       _mm512_mul_pd(_mm512_cvtps_pd(c), _mm512_cvtps_pd(d))));
}

/// a * b - c * d per lane in double, rounded to float (eight lanes at a time).
template <int N>
PA_AVX512_INLINE vfloat<N> differenceOfProductsInDouble(vfloat<N> a, vfloat<N> b, vfloat<N> c, vfloat<N> d) {
  __m256 parts[N / 8];
  for (int part = 0; part < N / 8; ++part)
    parts[part] = differenceOfProductsInDouble(eightLanes(a, part), eightLanes(b, part), eightLanes(c, part),
                                               eightLanes(d, part));
  return joinEightLanes<N>(parts);
}

}  // namespace pa::simd::avx512
