// The AVX-512 lanes of the wide traversal (wide_traversal_loop.h) on the 16-wide BVH
// (wide16_bvh.h): sixteen slab tests and sixteen watertight triangle tests per instruction, with
// the float and double operations of the scalar reference in the same order, lane for lane, so
// hit distances are bit-identical to it and to the 8-wide kernels. A closest-hit ray entering
// several children takes them in the node's order for its octant (Wide16Node::order): one
// permutation instead of a sort; the children are pushed with their entry distances and culled
// when popped. Any-hit rays take the children in slot order. Leaves are one 8-wide pack (small
// leaves, read as sixteen lanes whose upper half is never valid) or up to eight 16-wide packs.
//
// Only the functions here and the loop's templates carry the AVX-512 target attribute (see
// wide_traversal_avx512.cpp); in x86-64-v2 builds the file holds only stubs (wide16Available()
// is false there).
#include <bit>
#include <cstdint>
#include <limits>

#include <immintrin.h>

#include "renderer/bvh/cpu_features.h"
#include "renderer/bvh/slab_test.h"
#include "renderer/bvh/watertight.h"
#include "renderer/bvh/wide16_bvh.h"
#include "renderer/bvh/wide_bvh.h"
#include "renderer/bvh/wide_traversal_stack.h"

#if defined(__AVX2__)

#include "renderer/bvh/simd_avx512.h"

#define PA_BVH_KERNEL PA_AVX512
#include "renderer/bvh/wide_traversal_loop.h"

// GCC 12 reports the deliberately undefined pass-through operands of _mm512_cvtps_pd and
// _mm512_zextps256_ps512 as (maybe) used uninitialized (false positives inside avx512fintrin.h).
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Wuninitialized"
#endif

namespace pa::bvh_detail {
namespace {

using simd::avx512::vfloat16;

/// The lower eight lanes of a 16-lane register.
PA_AVX512_INLINE __m256 lowerHalf(__m512 x) { return _mm512_castps512_ps256(x); }
/// The upper eight lanes of a 16-lane register.
PA_AVX512_INLINE __m256 upperHalf(__m512 x) { return _mm512_extractf32x8_ps(x, 1); }

/// The two halves of a 16-lane register joined again.
PA_AVX512_INLINE __m512 joinHalves(__m256 lo, __m256 hi) {
  return _mm512_insertf32x8(_mm512_zextps256_ps512(lo), hi, 1);
}

/// AVX-512 16 lanes on the 16-wide layout.
struct Avx512Lanes16 {
  using Float = vfloat16;
  using Node = Wide16Node;
  using Bvh = Wide16Bvh;
  using PlaneRay = simd::avx512::PlaneRay;
  static constexpr uint32_t kWidth = kWide16Width;
  static constexpr bool kOctantOrder = true;
  static constexpr bool kSmallLeaves = true;
  static constexpr bool kLaneByLaneHits = false;

  /// Pushes the children in mask (in slot order), with their entry distances when the stack
  /// keeps them, sixteen lanes at once.
  template <bool kWithDistance>
  PA_AVX512_INLINE static void pushChildren(const Wide16Node& node, unsigned mask, vfloat16 tNear,
                                            TraversalStack<kWithDistance, kWidth>& stack) {
    simd::avx512::compressPush<kWithDistance>(stack, mask, _mm512_load_si512(node.child), tNear);
  }

  /// Closest hit: of the children in mask (>= 2), returns the nearest in the octant's order and
  /// pushes the others farthest first, so the nearer are popped first.
  PA_AVX512_INLINE static uint32_t enterInOctantOrder(const Wide16Node& node, unsigned mask, vfloat16 tNear,
                                                      int orderShift, TraversalStack<true, kWidth>& stack) {
    const __m512i order = _mm512_and_si512(
        _mm512_srl_epi32(_mm512_load_si512(node.order), _mm_cvtsi32_si128(orderShift)), _mm512_set1_epi32(15));
    const uint32_t ordered =
        _mm512_movepi32_mask(_mm512_permutexvar_epi32(order, _mm512_movm_epi32(static_cast<__mmask16>(mask))));
    const int nearestPosition = 31 - std::countl_zero(ordered);
    const uint32_t next = node.child[(node.order[nearestPosition] >> orderShift) & 15];
    simd::avx512::compressPush<true>(stack, ordered & ~(1u << nearestPosition),
                                     _mm512_permutexvar_epi32(order, _mm512_load_si512(node.child)),
                                     vfloat16(_mm512_permutexvar_ps(order, tNear.v)));
    return next;
  }

  /// Sixteen lanes of one vertex coordinate; a small (8-wide) pack's upper lanes read as zero
  /// (never valid).
  PA_AVX512_INLINE static vfloat16 loadVertex(const TrianglePack16& pack, int vertex, int axis) {
    return vfloat16::load(pack.v[vertex][axis]);
  }
  PA_AVX512_INLINE static vfloat16 loadVertex(const TrianglePack& pack, int vertex, int axis) {
    return _mm512_maskz_loadu_ps(0x00ff, pack.v[vertex][axis]);   // only the 8 lanes are read
  }

  /// a * b - c * d for all sixteen lanes, in double, rounded to float.
  PA_AVX512_INLINE static __m512 productDifferenceInDouble(__m512 a, __m512 b, __m512 c, __m512 d) {
    using simd::avx512::differenceOfProductsInDouble;
    return joinHalves(differenceOfProductsInDouble(lowerHalf(a), lowerHalf(b), lowerHalf(c), lowerHalf(d)),
                      differenceOfProductsInDouble(upperHalf(a), upperHalf(b), upperHalf(c), upperHalf(d)));
  }

  /// The edge functions u, v, w of the lanes in onEdge, again in double (as the scalar test).
  PA_AVX512_INLINE static void redoEdgesInDouble(unsigned onEdge, vfloat16 ax, vfloat16 ay, vfloat16 bx, vfloat16 by,
                                                 vfloat16 cx, vfloat16 cy, vfloat16& u, vfloat16& v, vfloat16& w) {
    u = select(onEdge, u, productDifferenceInDouble(cx.v, by.v, cy.v, bx.v));
    v = select(onEdge, v, productDifferenceInDouble(ax.v, cy.v, ay.v, cx.v));
    w = select(onEdge, w, productDifferenceInDouble(bx.v, ay.v, by.v, ax.v));
  }

  /// planeHitDistance of the halves that hold a lane of hits (fallback elsewhere, and where the
  /// ray runs parallel to the plane); a small pack's upper half never does.
  template <class Pack>
  PA_AVX512_INLINE static vfloat16 planeDistances(const Pack& pack, const PlaneRay& r, vfloat16 fallback,
                                                  unsigned hits) {
    __m256 t[2] = {lowerHalf(fallback.v), upperHalf(fallback.v)};
    for (int half = 0; half < 2; ++half)
      if (hits >> (8 * half) & 0xff) t[half] = simd::avx512::planeDistances8(pack, 8 * half, r, t[half]);
    return joinHalves(t[0], t[1]);
  }
};

}  // namespace

bool wide16Available() { return avx512KernelsAvailable(); }

PA_AVX512 bool intersectWide16(const Wide16Bvh& bvh, Ray& ray, Hit& hit, const HitFilter& filter, uint32_t instanceId) {
  return traverse<Avx512Lanes16, false>(bvh, ray, ray.tmax, hit, filter, instanceId);
}

PA_AVX512 bool occludedWide16(const Wide16Bvh& bvh, const Ray& ray, const HitFilter& filter, uint32_t instanceId) {
  float tmax = ray.tmax;
  Hit unused;
  return traverse<Avx512Lanes16, true>(bvh, ray, tmax, unused, filter, instanceId);
}

}  // namespace pa::bvh_detail

#else

namespace pa::bvh_detail {
bool wide16Available() { return false; }
bool intersectWide16(const Wide16Bvh&, Ray&, Hit&, const HitFilter&, uint32_t) { return false; }
bool occludedWide16(const Wide16Bvh&, const Ray&, const HitFilter&, uint32_t) { return false; }
}  // namespace pa::bvh_detail

#endif  // __AVX2__
