// The AVX-512 (F/VL/BW/DQ) lanes of the wide traversal (wide_traversal_loop.h) on the 8-wide
// BVH, chosen at run time (WideBvh::kernel). The float and double operations are those of the
// baseline lanes and the scalar reference, in the same order, so hit distances are
// bit-identical. What changes: comparisons go straight to mask registers; hit children are
// pushed with one register compress (no lane table); when a closest-hit ray enters three or
// more children, the others are pushed sorted by entry distance (a 64-bit key sorting network),
// so the nearest is popped first; a leaf's accurate plane distances are computed for all eight
// lanes in one 8-wide double register. The sorted push changes the visiting order, so on an
// exact tie in t the reported triangle may differ from the baseline kernel's (the distance
// never does).
//
// Only the functions here and the loop's templates carry the AVX-512 target attribute;
// everything they inline from the other headers keeps the build's ISA when emitted out of line,
// so no AVX-512 instruction can leak into code that runs on other CPUs. The file is empty in
// x86-64-v2 builds.
#include <bit>
#include <cstdint>
#include <limits>

#include <immintrin.h>

#include "renderer/bvh/slab_test.h"
#include "renderer/bvh/watertight.h"
#include "renderer/bvh/wide16_bvh.h"
#include "renderer/bvh/wide_bvh.h"
#include "renderer/bvh/wide_traversal_stack.h"

#if defined(__AVX2__)

#include "renderer/bvh/simd_avx512.h"

#define PA_BVH_KERNEL PA_AVX512
#include "renderer/bvh/wide_traversal_loop.h"

// GCC 12 reports the deliberately undefined pass-through operand of _mm512_cvtps_pd as
// "may be used uninitialized" (a false positive inside avx512fintrin.h).
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif

namespace pa::bvh_detail {
namespace {

using simd::avx512::vfloat8;

/// One layer of a sorting network on eight 64-bit keys: each lane meets the lane `partner`
/// names and keeps the larger key where takeMax has its bit, else the smaller.
PA_AVX512_INLINE __m512i compareExchange(__m512i keys, __m512i partner, __mmask8 takeMax) {
  const __m512i other = _mm512_permutexvar_epi64(partner, keys);
  return _mm512_mask_max_epi64(_mm512_min_epi64(keys, other), takeMax, keys, other);
}

/// AVX-512 8 lanes on the 8-wide layout.
struct Avx512Lanes8 {
  using Float = vfloat8;
  using Node = WideNode;
  using Bvh = WideBvh;
  using PlaneRay = simd::avx512::PlaneRay;
  static constexpr uint32_t kWidth = kWideWidth;
  static constexpr bool kOctantOrder = false;
  static constexpr bool kSmallLeaves = false;
  static constexpr bool kLaneByLaneHits = false;

  /// Pushes the children in mask (in lane order), with their entry distances when the stack
  /// keeps them, eight lanes at once.
  template <bool kWithDistance>
  PA_AVX512_INLINE static void pushChildren(const WideNode& node, unsigned mask, vfloat8 tNear,
                                            TraversalStack<kWithDistance>& stack) {
    const __m256i children = _mm256_load_si256(reinterpret_cast<const __m256i*>(node.child));
    simd::avx512::compressPush<kWithDistance>(stack, mask, children, tNear);
  }

  /// Pushes the children in mask (>= 2) farthest first, so the nearest is popped first: keys
  /// (entry distance as an ordered integer : child reference) sorted by a 19-comparator network.
  PA_AVX512_INLINE static void pushFarther(const WideNode& node, unsigned mask, vfloat8 tNear,
                                           TraversalStack<true>& stack) {
    // Floats compare like signed integers once the magnitude bits of negative ones are flipped
    // (an involution, undone below); distances are never NaN (tmin is a number).
    const __m256i bits = _mm256_castps_si256(tNear.v);
    const __m256i flip = _mm256_srli_epi32(_mm256_srai_epi32(bits, 31), 1);
    const __m256i order = _mm256_xor_si256(bits, flip);
    const __m256i children = _mm256_load_si256(reinterpret_cast<const __m256i*>(node.child));
    __m512i keys = _mm512_or_si512(_mm512_slli_epi64(_mm512_cvtepi32_epi64(order), 32), _mm512_cvtepu32_epi64(children));
    keys = _mm512_mask_mov_epi64(_mm512_set1_epi64(std::numeric_limits<int64_t>::min()), static_cast<__mmask8>(mask), keys);
    keys = compareExchange(keys, _mm512_set_epi64(5, 4, 7, 6, 1, 0, 3, 2), 0x33);
    keys = compareExchange(keys, _mm512_set_epi64(3, 2, 1, 0, 7, 6, 5, 4), 0x0f);
    keys = compareExchange(keys, _mm512_set_epi64(6, 7, 4, 5, 2, 3, 0, 1), 0x55);
    keys = compareExchange(keys, _mm512_set_epi64(7, 6, 3, 2, 5, 4, 1, 0), 0x0c);
    keys = compareExchange(keys, _mm512_set_epi64(7, 3, 5, 1, 6, 2, 4, 0), 0x0a);
    keys = compareExchange(keys, _mm512_set_epi64(7, 5, 6, 3, 4, 1, 2, 0), 0x2a);
    const __m256i sortedOrder = _mm512_cvtepi64_epi32(_mm512_srli_epi64(keys, 32));
    const __m256i sortedFlip = _mm256_srli_epi32(_mm256_srai_epi32(sortedOrder, 31), 1);
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(stack.node + stack.top), _mm512_cvtepi64_epi32(keys));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(stack.entry + stack.top), _mm256_xor_si256(sortedOrder, sortedFlip));
    stack.top += std::popcount(mask);
  }

  /// Index of the lane in mask (>= 2 bits) with the smallest entry distance (lowest lane on ties).
  PA_AVX512_INLINE static int nearestLane(unsigned mask, vfloat8 tNear) {
    const __mmask8 lanes = static_cast<__mmask8>(mask);
    const __m256 d = _mm256_mask_mov_ps(_mm256_set1_ps(std::numeric_limits<float>::infinity()), lanes, tNear.v);
    __m256 m = _mm256_min_ps(d, _mm256_shuffle_f32x4(d, d, 1));
    m = _mm256_min_ps(m, _mm256_permute_ps(m, 0x4e));
    m = _mm256_min_ps(m, _mm256_permute_ps(m, 0xb1));
    return std::countr_zero(static_cast<uint32_t>(_mm256_mask_cmp_ps_mask(lanes, d, m, _CMP_EQ_OQ)));
  }

  /// One vertex coordinate of the pack's eight triangles.
  PA_AVX512_INLINE static vfloat8 loadVertex(const TrianglePack& pack, int vertex, int axis) {
    return vfloat8::load(pack.v[vertex][axis]);
  }

  /// The edge functions u, v, w of the lanes in onEdge, again in double (as the scalar test).
  PA_AVX512_INLINE static void redoEdgesInDouble(unsigned onEdge, vfloat8 ax, vfloat8 ay, vfloat8 bx, vfloat8 by,
                                                 vfloat8 cx, vfloat8 cy, vfloat8& u, vfloat8& v, vfloat8& w) {
    using simd::avx512::differenceOfProductsInDouble;
    u = select(onEdge, u, differenceOfProductsInDouble(cx.v, by.v, cy.v, bx.v));
    v = select(onEdge, v, differenceOfProductsInDouble(ax.v, cy.v, ay.v, cx.v));
    w = select(onEdge, w, differenceOfProductsInDouble(bx.v, ay.v, by.v, ax.v));
  }

  /// planeHitDistance of all eight lanes (fallback where the ray runs parallel to the plane).
  PA_AVX512_INLINE static vfloat8 planeDistances(const TrianglePack& pack, const PlaneRay& r, vfloat8 fallback,
                                                 unsigned) {
    return simd::avx512::planeDistances8(pack, 0, r, fallback.v);
  }
};

}  // namespace

PA_AVX512 bool intersectWideAvx512(const WideBvh& bvh, Ray& ray, Hit& hit, const HitFilter& filter,
                                   uint32_t instanceId) {
  return traverse<Avx512Lanes8, false>(bvh, ray, ray.tmax, hit, filter, instanceId);
}

PA_AVX512 bool occludedWideAvx512(const WideBvh& bvh, const Ray& ray, const HitFilter& filter, uint32_t instanceId) {
  float tmax = ray.tmax;
  Hit unused;
  return traverse<Avx512Lanes8, true>(bvh, ray, tmax, unused, filter, instanceId);
}

}  // namespace pa::bvh_detail

#endif  // __AVX2__
