// AVX-512 (F/VL/BW/DQ) variant of the wide traversal in wide_traversal.cpp, chosen at run time
// (WideBvh::kernel). The float and double operations are those of the AVX2 kernel and the
// scalar reference, in the same order, so hit distances are bit-identical. What changes:
// comparisons go straight to mask registers; hit children are pushed with one register
// compress (no lane table); of two children entered, the nearer is chosen by a branch
// (takeNearerOfTwo); when three or more were entered, the others are pushed sorted by entry
// distance (a 64-bit key sorting network), so the nearest is popped first; a leaf's
// accurate plane distances are computed for all eight lanes in one 8-wide double register.
// The sorted push changes the visiting order, so on an exact tie in t the reported triangle
// may differ from the AVX2 kernel's (the distance never does).
//
// Only the functions below carry the AVX-512 target attribute; everything they inline from the
// shared headers keeps the build's ISA when emitted out of line, so no AVX-512 instruction can
// leak into code that runs on other CPUs. The file is empty in x86-64-v2 builds.
#include <bit>
#include <cstdint>
#include <limits>

#include <immintrin.h>

#include "renderer/bvh/slab_test.h"
#include "renderer/bvh/watertight.h"
#include "renderer/bvh/wide_bvh.h"
#include "renderer/bvh/wide_traversal_stack.h"

#if defined(__AVX2__)

#define PA_AVX512 __attribute__((target("avx512f,avx512vl,avx512bw,avx512dq")))

// GCC 12 reports the deliberately undefined pass-through operand of _mm512_cvtps_pd as
// "may be used uninitialized" (a false positive inside avx512fintrin.h).
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif

namespace pa::bvh_detail {
namespace {

/// Per-ray constants for the box tests.
struct BoxRay {
  __m256 ox, oy, oz, idx, idy, idz, tmin;
  int nearX, nearY, nearZ;
};

PA_AVX512 inline BoxRay makeBoxRay(const Ray& ray) {
  BoxRay r;
  r.ox = _mm256_set1_ps(ray.origin.x);
  r.oy = _mm256_set1_ps(ray.origin.y);
  r.oz = _mm256_set1_ps(ray.origin.z);
  r.idx = _mm256_set1_ps(1.0f / ray.dir.x);
  r.idy = _mm256_set1_ps(1.0f / ray.dir.y);
  r.idz = _mm256_set1_ps(1.0f / ray.dir.z);
  r.tmin = _mm256_set1_ps(ray.tmin);
  r.nearX = std::signbit(ray.dir.x);
  r.nearY = std::signbit(ray.dir.y);
  r.nearZ = std::signbit(ray.dir.z);
  return r;
}

/// Entry distances of the eight children and the mask of those the ray enters before tmax
/// (the slab test of slab_test.h; max/min keep the second operand on NaN, as there).
PA_AVX512 inline __mmask8 testNode(const BoxRay& r, const WideNode& node, float tmax, __m256& tNear) {
  const __m256 nx = _mm256_mul_ps(_mm256_sub_ps(_mm256_load_ps(node.bounds[r.nearX][0]), r.ox), r.idx);
  const __m256 ny = _mm256_mul_ps(_mm256_sub_ps(_mm256_load_ps(node.bounds[r.nearY][1]), r.oy), r.idy);
  const __m256 nz = _mm256_mul_ps(_mm256_sub_ps(_mm256_load_ps(node.bounds[r.nearZ][2]), r.oz), r.idz);
  const __m256 fx = _mm256_mul_ps(_mm256_sub_ps(_mm256_load_ps(node.bounds[1 - r.nearX][0]), r.ox), r.idx);
  const __m256 fy = _mm256_mul_ps(_mm256_sub_ps(_mm256_load_ps(node.bounds[1 - r.nearY][1]), r.oy), r.idy);
  const __m256 fz = _mm256_mul_ps(_mm256_sub_ps(_mm256_load_ps(node.bounds[1 - r.nearZ][2]), r.oz), r.idz);
  tNear = _mm256_max_ps(nx, _mm256_max_ps(ny, _mm256_max_ps(nz, r.tmin)));
  const __m256 tFar = _mm256_mul_ps(_mm256_min_ps(fx, _mm256_min_ps(fy, _mm256_min_ps(fz, _mm256_set1_ps(tmax)))),
                                    _mm256_set1_ps(kRobustFarScale));
  return _mm256_cmp_ps_mask(tNear, tFar, _CMP_LE_OQ);
}

/// Pushes the children in mask (in lane order), with their entry distances when the stack
/// keeps them: one register compress each, stored eight lanes at once.
template <bool kWithDistance>
PA_AVX512 inline void pushChildren(const WideNode& node, __mmask8 mask, __m256 tNear,
                                   TraversalStack<kWithDistance>& stack) {
  const __m256i children = _mm256_load_si256(reinterpret_cast<const __m256i*>(node.child));
  _mm256_storeu_si256(reinterpret_cast<__m256i*>(stack.node + stack.top), _mm256_maskz_compress_epi32(mask, children));
  if constexpr (kWithDistance) _mm256_storeu_ps(stack.entry + stack.top, _mm256_maskz_compress_ps(mask, tNear));
  stack.top += std::popcount(static_cast<uint32_t>(mask));
}

/// One layer of a sorting network on eight 64-bit keys: each lane meets the lane `partner`
/// names and keeps the larger key where takeMax has its bit, else the smaller.
PA_AVX512 inline __m512i compareExchange(__m512i keys, __m512i partner, __mmask8 takeMax) {
  const __m512i other = _mm512_permutexvar_epi64(partner, keys);
  return _mm512_mask_max_epi64(_mm512_min_epi64(keys, other), takeMax, keys, other);
}

/// Pushes the children in mask (>= 2) farthest first, so the nearest is popped first: keys
/// (entry distance as an ordered integer : child reference) sorted by a 19-comparator network.
PA_AVX512 inline void pushChildrenSorted(const WideNode& node, __mmask8 mask, __m256 tNear,
                                         TraversalStack<true>& stack) {
  // Floats compare like signed integers once the magnitude bits of negative ones are flipped
  // (an involution, undone below); distances are never NaN (tmin is a number).
  const __m256i bits = _mm256_castps_si256(tNear);
  const __m256i flip = _mm256_srli_epi32(_mm256_srai_epi32(bits, 31), 1);
  const __m256i order = _mm256_xor_si256(bits, flip);
  const __m256i children = _mm256_load_si256(reinterpret_cast<const __m256i*>(node.child));
  __m512i keys = _mm512_or_si512(_mm512_slli_epi64(_mm512_cvtepi32_epi64(order), 32), _mm512_cvtepu32_epi64(children));
  keys = _mm512_mask_mov_epi64(_mm512_set1_epi64(std::numeric_limits<int64_t>::min()), mask, keys);
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
  stack.top += std::popcount(static_cast<uint32_t>(mask));
}

/// Index of the lane in mask (>= 2 bits) with the smallest entry distance (lowest lane on ties).
PA_AVX512 inline int nearestLane(__mmask8 mask, __m256 tNear) {
  const __m256 d = _mm256_mask_mov_ps(_mm256_set1_ps(std::numeric_limits<float>::infinity()), mask, tNear);
  __m256 m = _mm256_min_ps(d, _mm256_shuffle_f32x4(d, d, 1));
  m = _mm256_min_ps(m, _mm256_permute_ps(m, 0x4e));
  m = _mm256_min_ps(m, _mm256_permute_ps(m, 0xb1));
  return std::countr_zero(static_cast<uint32_t>(_mm256_mask_cmp_ps_mask(mask, d, m, _CMP_EQ_OQ)));
}

/// Per-ray constants of the watertight pack test (see watertight.h) and of the accurate
/// plane distance (in double).
struct TriangleRay {
  int kx, ky, kz;
  __m256 ox, oy, oz, sx, sy, sz;
  __m512d dox, doy, doz, ddx, ddy, ddz;
};

PA_AVX512 inline TriangleRay makeTriangleRay(const Ray& ray) {
  const RayShear shear(ray.dir);
  TriangleRay r;
  r.kx = shear.kx;
  r.ky = shear.ky;
  r.kz = shear.kz;
  r.ox = _mm256_set1_ps(ray.origin[shear.kx]);
  r.oy = _mm256_set1_ps(ray.origin[shear.ky]);
  r.oz = _mm256_set1_ps(ray.origin[shear.kz]);
  r.sx = _mm256_set1_ps(shear.sx);
  r.sy = _mm256_set1_ps(shear.sy);
  r.sz = _mm256_set1_ps(shear.sz);
  r.dox = _mm512_set1_pd(ray.origin.x);
  r.doy = _mm512_set1_pd(ray.origin.y);
  r.doz = _mm512_set1_pd(ray.origin.z);
  r.ddx = _mm512_set1_pd(ray.dir.x);
  r.ddy = _mm512_set1_pd(ray.dir.y);
  r.ddz = _mm512_set1_pd(ray.dir.z);
  return r;
}

/// Final lane results of one pack test (bit-identical to the scalar test's).
struct PackCandidates {
  alignas(32) float t[kPackWidth];   ///< Accurate (plane) hit distance.
  alignas(32) float u[kPackWidth];
  alignas(32) float v[kPackWidth];
};

/// planeHitDistance (watertight.h) for all eight lanes: the same double operations in the same
/// order; lanes where the ray is parallel to the plane in double take `fallback`.
PA_AVX512 inline __m256 planeDistances(const TrianglePack& pack, const TriangleRay& r, __m256 fallback) {
  const __m512d v0x = _mm512_cvtps_pd(_mm256_load_ps(pack.v[0][0]));
  const __m512d v0y = _mm512_cvtps_pd(_mm256_load_ps(pack.v[0][1]));
  const __m512d v0z = _mm512_cvtps_pd(_mm256_load_ps(pack.v[0][2]));
  const __m512d e1x = _mm512_sub_pd(_mm512_cvtps_pd(_mm256_load_ps(pack.v[1][0])), v0x);
  const __m512d e1y = _mm512_sub_pd(_mm512_cvtps_pd(_mm256_load_ps(pack.v[1][1])), v0y);
  const __m512d e1z = _mm512_sub_pd(_mm512_cvtps_pd(_mm256_load_ps(pack.v[1][2])), v0z);
  const __m512d e2x = _mm512_sub_pd(_mm512_cvtps_pd(_mm256_load_ps(pack.v[2][0])), v0x);
  const __m512d e2y = _mm512_sub_pd(_mm512_cvtps_pd(_mm256_load_ps(pack.v[2][1])), v0y);
  const __m512d e2z = _mm512_sub_pd(_mm512_cvtps_pd(_mm256_load_ps(pack.v[2][2])), v0z);
  const __m512d nx = _mm512_sub_pd(_mm512_mul_pd(e1y, e2z), _mm512_mul_pd(e1z, e2y));
  const __m512d ny = _mm512_sub_pd(_mm512_mul_pd(e1z, e2x), _mm512_mul_pd(e1x, e2z));
  const __m512d nz = _mm512_sub_pd(_mm512_mul_pd(e1x, e2y), _mm512_mul_pd(e1y, e2x));
  const __m512d denom =
      _mm512_add_pd(_mm512_add_pd(_mm512_mul_pd(nx, r.ddx), _mm512_mul_pd(ny, r.ddy)), _mm512_mul_pd(nz, r.ddz));
  const __m512d num = _mm512_add_pd(_mm512_add_pd(_mm512_mul_pd(nx, _mm512_sub_pd(v0x, r.dox)),
                                                  _mm512_mul_pd(ny, _mm512_sub_pd(v0y, r.doy))),
                                    _mm512_mul_pd(nz, _mm512_sub_pd(v0z, r.doz)));
  const __mmask8 parallel = _mm512_cmp_pd_mask(denom, _mm512_setzero_pd(), _CMP_EQ_OQ);
  return _mm256_mask_mov_ps(_mm512_cvtpd_ps(_mm512_div_pd(num, denom)), parallel, fallback);
}

/// Watertight test of a pack's triangles (the arithmetic of intersectTriangleWatertight, lane for
/// lane); returns the lanes hit within [tmin, tmax] by their accurate distance, with their
/// distances and barycentrics in out.
PA_AVX512 inline unsigned testPack(const TrianglePack& pack, const TriangleRay& r, float tmin, float tmax,
                                   PackCandidates& out) {
  const __m256 az = _mm256_sub_ps(_mm256_load_ps(pack.v[0][r.kz]), r.oz);
  const __m256 bz = _mm256_sub_ps(_mm256_load_ps(pack.v[1][r.kz]), r.oz);
  const __m256 cz = _mm256_sub_ps(_mm256_load_ps(pack.v[2][r.kz]), r.oz);
  const __m256 ax = _mm256_sub_ps(_mm256_sub_ps(_mm256_load_ps(pack.v[0][r.kx]), r.ox), _mm256_mul_ps(r.sx, az));
  const __m256 ay = _mm256_sub_ps(_mm256_sub_ps(_mm256_load_ps(pack.v[0][r.ky]), r.oy), _mm256_mul_ps(r.sy, az));
  const __m256 bx = _mm256_sub_ps(_mm256_sub_ps(_mm256_load_ps(pack.v[1][r.kx]), r.ox), _mm256_mul_ps(r.sx, bz));
  const __m256 by = _mm256_sub_ps(_mm256_sub_ps(_mm256_load_ps(pack.v[1][r.ky]), r.oy), _mm256_mul_ps(r.sy, bz));
  const __m256 cx = _mm256_sub_ps(_mm256_sub_ps(_mm256_load_ps(pack.v[2][r.kx]), r.ox), _mm256_mul_ps(r.sx, cz));
  const __m256 cy = _mm256_sub_ps(_mm256_sub_ps(_mm256_load_ps(pack.v[2][r.ky]), r.oy), _mm256_mul_ps(r.sy, cz));
  __m256 u = _mm256_sub_ps(_mm256_mul_ps(cx, by), _mm256_mul_ps(cy, bx));
  __m256 v = _mm256_sub_ps(_mm256_mul_ps(ax, cy), _mm256_mul_ps(ay, cx));
  __m256 w = _mm256_sub_ps(_mm256_mul_ps(bx, ay), _mm256_mul_ps(by, ax));
  const __m256 zero = _mm256_setzero_ps();
  const __mmask8 valid = static_cast<__mmask8>(pack.validBits);
  const __mmask8 onEdge = (_mm256_cmp_ps_mask(u, zero, _CMP_EQ_OQ) | _mm256_cmp_ps_mask(v, zero, _CMP_EQ_OQ) |
                           _mm256_cmp_ps_mask(w, zero, _CMP_EQ_OQ)) & valid;
  if (onEdge) {
    // Exact zero in float: these lanes are decided with the edge functions in double.
    const __m512d dax = _mm512_cvtps_pd(ax), day = _mm512_cvtps_pd(ay), dbx = _mm512_cvtps_pd(bx),
                  dby = _mm512_cvtps_pd(by), dcx = _mm512_cvtps_pd(cx), dcy = _mm512_cvtps_pd(cy);
    u = _mm256_mask_mov_ps(u, onEdge, _mm512_cvtpd_ps(_mm512_sub_pd(_mm512_mul_pd(dcx, dby), _mm512_mul_pd(dcy, dbx))));
    v = _mm256_mask_mov_ps(v, onEdge, _mm512_cvtpd_ps(_mm512_sub_pd(_mm512_mul_pd(dax, dcy), _mm512_mul_pd(day, dcx))));
    w = _mm256_mask_mov_ps(w, onEdge, _mm512_cvtpd_ps(_mm512_sub_pd(_mm512_mul_pd(dbx, day), _mm512_mul_pd(dby, dax))));
  }
  const __mmask8 negative = _mm256_cmp_ps_mask(u, zero, _CMP_LT_OQ) | _mm256_cmp_ps_mask(v, zero, _CMP_LT_OQ) |
                            _mm256_cmp_ps_mask(w, zero, _CMP_LT_OQ);
  const __mmask8 positive = _mm256_cmp_ps_mask(u, zero, _CMP_GT_OQ) | _mm256_cmp_ps_mask(v, zero, _CMP_GT_OQ) |
                            _mm256_cmp_ps_mask(w, zero, _CMP_GT_OQ);
  __mmask8 hits = valid & ~(negative & positive);
  if (!hits) return 0;
  const __m256 det = _mm256_add_ps(_mm256_add_ps(u, v), w);
  hits &= _mm256_cmp_ps_mask(det, zero, _CMP_NEQ_UQ);
  if (!hits) return 0;
  const __m256 tScaled = _mm256_add_ps(
      _mm256_add_ps(_mm256_mul_ps(u, _mm256_mul_ps(r.sz, az)), _mm256_mul_ps(v, _mm256_mul_ps(r.sz, bz))),
      _mm256_mul_ps(w, _mm256_mul_ps(r.sz, cz)));
  const __m256 rcp = _mm256_div_ps(_mm256_set1_ps(1.0f), det);
  const __m256 t = planeDistances(pack, r, _mm256_mul_ps(tScaled, rcp));
  hits &= _mm256_cmp_ps_mask(t, _mm256_set1_ps(tmin), _CMP_GE_OQ) & _mm256_cmp_ps_mask(t, _mm256_set1_ps(tmax), _CMP_LE_OQ);
  if (!hits) return 0;
  _mm256_store_ps(out.t, t);
  _mm256_store_ps(out.u, _mm256_mul_ps(v, rcp));
  _mm256_store_ps(out.v, _mm256_mul_ps(w, rcp));
  return hits;
}

/// Tests a leaf's triangles against [ray.tmin, tmax], in the order of the other kernels: closest
/// hit (kAnyHit false) shortens tmax and writes hit for every accepted hit; any hit returns true
/// at the first accepted one.
template <bool kAnyHit>
PA_AVX512 inline bool testLeaf(const WideBvh& bvh, uint32_t ref, const TriangleRay& triRay, const Ray& ray,
                               float& tmax, Hit& hit, const HitFilter& filter, uint32_t instanceId) {
  uint32_t first, count;
  leafPacks(ref, first, count);
  bool found = false;
  for (uint32_t p = first; p < first + count; ++p) {
    const TrianglePack& pack = bvh.packs[p];
    PackCandidates c;
    const unsigned lanes = testPack(pack, triRay, ray.tmin, tmax, c);
    if (acceptPackHits<kAnyHit>(pack, lanes, c.t, c.u, c.v, tmax, hit, filter, instanceId)) {
      if constexpr (kAnyHit) return true;
      found = true;
    }
  }
  return found;
}

}  // namespace

PA_AVX512 bool intersectWideAvx512(const WideBvh& bvh, Ray& ray, Hit& hit, const HitFilter& filter,
                                   uint32_t instanceId) {
  if (bvh.empty()) return false;
  const BoxRay boxRay = makeBoxRay(ray);
  const TriangleRay triRay = makeTriangleRay(ray);
  TraversalStack<true> stack;
  uint32_t current = 0;
  bool found = false;
  for (;;) {
    if (!(current & kLeafBit)) {
      const WideNode& node = bvh.nodes[current];
      __m256 tNear;
      const __mmask8 mask = testNode(boxRay, node, ray.tmax, tNear);
      if (mask != 0) {
        if ((mask & (mask - 1)) == 0) {   // exactly one child
          current = node.child[std::countr_zero(static_cast<uint32_t>(mask))];
          continue;
        }
        const uint32_t afterFirst = mask & (mask - 1u);
        if ((afterFirst & (afterFirst - 1)) == 0) {   // exactly two children
          alignas(32) float entry[kWideWidth];
          _mm256_store_ps(entry, tNear);
          current = takeNearerOfTwo(node, mask, entry, stack);
          continue;
        }
        const int nearest = nearestLane(mask, tNear);
        current = node.child[nearest];
        pushChildrenSorted(node, static_cast<__mmask8>(mask & ~(1u << nearest)), tNear, stack);
        continue;
      }
    } else if (testLeaf<false>(bvh, current, triRay, ray, ray.tmax, hit, filter, instanceId)) {
      found = true;
    }
    // Pop the next entry that may still hold a nearer hit.
    if (!popEntryWithin(stack, ray.tmax * kRobustFarScale, current)) return found;
  }
}

PA_AVX512 bool occludedWideAvx512(const WideBvh& bvh, const Ray& ray, const HitFilter& filter, uint32_t instanceId) {
  if (bvh.empty()) return false;
  const BoxRay boxRay = makeBoxRay(ray);
  const TriangleRay triRay = makeTriangleRay(ray);
  TraversalStack<false> stack;
  uint32_t current = 0;
  for (;;) {
    if (!(current & kLeafBit)) {
      const WideNode& node = bvh.nodes[current];
      __m256 tNear;
      const __mmask8 mask = testNode(boxRay, node, ray.tmax, tNear);
      if (mask != 0) {
        current = node.child[std::countr_zero(static_cast<uint32_t>(mask))];
        if (const __mmask8 rest = mask & (mask - 1)) pushChildren(node, rest, tNear, stack);
        continue;
      }
    } else {
      float tmax = ray.tmax;
      Hit unused;
      if (testLeaf<true>(bvh, current, triRay, ray, tmax, unused, filter, instanceId)) return true;
    }
    if (stack.top == 0) return false;
    current = stack.node[--stack.top];
  }
}

}  // namespace pa::bvh_detail

#endif  // __AVX2__
