// AVX-512 traversal of the 16-wide BVH (wide16_bvh.h): sixteen slab tests and sixteen
// watertight triangle tests per instruction. The float and double operations are those of the
// scalar reference (slab_test.h, watertight.h) in the same order, lane for lane, so hit
// distances are bit-identical to it and to the 8-wide kernels. A closest-hit ray entering
// several children takes them in the node's order for its octant (Wide16Node::order): one
// permutation instead of a sort; the children are pushed with their entry distances and culled
// when popped, as in the 8-wide kernels. Any-hit rays take the children in slot order.
//
// Only the functions below carry the AVX-512 target attribute (see wide_traversal_avx512.cpp);
// in x86-64-v2 builds the file holds only stubs (wide16Available() is false there).
#include <bit>
#include <cstdint>
#include <limits>

#include <immintrin.h>

#include "renderer/bvh/slab_test.h"
#include "renderer/bvh/watertight.h"
#include "renderer/bvh/wide16_bvh.h"
#include "renderer/bvh/wide_traversal_stack.h"

#if defined(__AVX2__)

#define PA_AVX512 __attribute__((target("avx512f,avx512vl,avx512bw,avx512dq")))

// GCC 12 reports the deliberately undefined pass-through operands of _mm512_cvtps_pd and
// _mm512_zextps256_ps512 as (maybe) used uninitialized (false positives inside avx512fintrin.h).
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Wuninitialized"
#endif

namespace pa::bvh_detail {
namespace {

/// Traversal stack of the 16-wide tree (wide_traversal_stack.h).
template <bool kWithDistance>
using Stack16 = TraversalStack<kWithDistance, kWide16Width>;

/// Pushes the lanes of children in mask (in lane order), with their entry distances when the
/// stack keeps them: one register compress each, stored sixteen lanes at once.
template <bool kWithDistance>
PA_AVX512 inline void push(Stack16<kWithDistance>& stack, __mmask16 mask, __m512i children, __m512 entry) {
  _mm512_storeu_si512(stack.node + stack.top, _mm512_maskz_compress_epi32(mask, children));
  if constexpr (kWithDistance) _mm512_storeu_ps(stack.entry + stack.top, _mm512_maskz_compress_ps(mask, entry));
  stack.top += std::popcount(static_cast<uint32_t>(mask));
}

/// Per-ray constants for the box tests.
struct BoxRay16 {
  __m512 ox, oy, oz, idx, idy, idz, tmin;
  int nearX, nearY, nearZ;
  int orderShift;   ///< 4 x octant: where the ray's octant's slot order sits in Wide16Node::order.
};

PA_AVX512 inline BoxRay16 makeBoxRay16(const Ray& ray) {
  BoxRay16 r;
  r.ox = _mm512_set1_ps(ray.origin.x);
  r.oy = _mm512_set1_ps(ray.origin.y);
  r.oz = _mm512_set1_ps(ray.origin.z);
  r.idx = _mm512_set1_ps(1.0f / ray.dir.x);
  r.idy = _mm512_set1_ps(1.0f / ray.dir.y);
  r.idz = _mm512_set1_ps(1.0f / ray.dir.z);
  r.tmin = _mm512_set1_ps(ray.tmin);
  r.nearX = std::signbit(ray.dir.x);
  r.nearY = std::signbit(ray.dir.y);
  r.nearZ = std::signbit(ray.dir.z);
  r.orderShift = 4 * (r.nearX | r.nearY << 1 | r.nearZ << 2);
  return r;
}

/// Entry distances of the sixteen children and the mask of those the ray enters before tmax
/// (the slab test of slab_test.h; max/min keep the second operand on NaN, as there).
PA_AVX512 inline __mmask16 testNode(const BoxRay16& r, const Wide16Node& node, float tmax, __m512& tNear) {
  const __m512 nx = _mm512_mul_ps(_mm512_sub_ps(_mm512_load_ps(node.bounds[r.nearX][0]), r.ox), r.idx);
  const __m512 ny = _mm512_mul_ps(_mm512_sub_ps(_mm512_load_ps(node.bounds[r.nearY][1]), r.oy), r.idy);
  const __m512 nz = _mm512_mul_ps(_mm512_sub_ps(_mm512_load_ps(node.bounds[r.nearZ][2]), r.oz), r.idz);
  const __m512 fx = _mm512_mul_ps(_mm512_sub_ps(_mm512_load_ps(node.bounds[1 - r.nearX][0]), r.ox), r.idx);
  const __m512 fy = _mm512_mul_ps(_mm512_sub_ps(_mm512_load_ps(node.bounds[1 - r.nearY][1]), r.oy), r.idy);
  const __m512 fz = _mm512_mul_ps(_mm512_sub_ps(_mm512_load_ps(node.bounds[1 - r.nearZ][2]), r.oz), r.idz);
  tNear = _mm512_max_ps(nx, _mm512_max_ps(ny, _mm512_max_ps(nz, r.tmin)));
  const __m512 tFar = _mm512_mul_ps(_mm512_min_ps(fx, _mm512_min_ps(fy, _mm512_min_ps(fz, _mm512_set1_ps(tmax)))),
                                    _mm512_set1_ps(kRobustFarScale));
  return _mm512_cmp_ps_mask(tNear, tFar, _CMP_LE_OQ);
}

/// Per-ray constants of the watertight pack test (see watertight.h) and of the accurate plane
/// distance (in double).
struct TriangleRay16 {
  int kx, ky, kz;
  __m512 ox, oy, oz, sx, sy, sz;
  __m512d dox, doy, doz, ddx, ddy, ddz;
};

PA_AVX512 inline TriangleRay16 makeTriangleRay16(const Ray& ray) {
  const RayShear shear(ray.dir);
  TriangleRay16 r;
  r.kx = shear.kx;
  r.ky = shear.ky;
  r.kz = shear.kz;
  r.ox = _mm512_set1_ps(ray.origin[shear.kx]);
  r.oy = _mm512_set1_ps(ray.origin[shear.ky]);
  r.oz = _mm512_set1_ps(ray.origin[shear.kz]);
  r.sx = _mm512_set1_ps(shear.sx);
  r.sy = _mm512_set1_ps(shear.sy);
  r.sz = _mm512_set1_ps(shear.sz);
  r.dox = _mm512_set1_pd(ray.origin.x);
  r.doy = _mm512_set1_pd(ray.origin.y);
  r.doz = _mm512_set1_pd(ray.origin.z);
  r.ddx = _mm512_set1_pd(ray.dir.x);
  r.ddy = _mm512_set1_pd(ray.dir.y);
  r.ddz = _mm512_set1_pd(ray.dir.z);
  return r;
}

/// Lower (half 0) or upper (half 1) eight lanes of a float register, widened to double.
PA_AVX512 inline __m512d widenHalf(__m512 v, int half) {
  return _mm512_cvtps_pd(half ? _mm512_extractf32x8_ps(v, 1) : _mm512_castps512_ps256(v));
}

/// a * b - c * d for all sixteen lanes, computed in double and rounded to float (the exact
/// edge-function fallback of watertight.h).
PA_AVX512 inline __m512 differenceOfProductsInDouble(__m512 a, __m512 b, __m512 c, __m512 d) {
  __m256 halves[2];
  for (int half = 0; half < 2; ++half)
    halves[half] = _mm512_cvtpd_ps(_mm512_sub_pd(_mm512_mul_pd(widenHalf(a, half), widenHalf(b, half)),
                                                 _mm512_mul_pd(widenHalf(c, half), widenHalf(d, half))));
  return _mm512_insertf32x8(_mm512_zextps256_ps512(halves[0]), halves[1], 1);
}

/// planeHitDistance (watertight.h) for eight lanes of a pack starting at `lane0`: the same double
/// operations in the same order; lanes where the ray is parallel to the plane take `fallback`.
/// Sixteen lanes of one vertex coordinate; an 8-wide pack's upper lanes read as zero (never valid).
PA_AVX512 inline __m512 loadLanes(const TrianglePack16& pack, int vertex, int axis) {
  return _mm512_load_ps(pack.v[vertex][axis]);
}
PA_AVX512 inline __m512 loadLanes(const TrianglePack& pack, int vertex, int axis) {
  return _mm512_maskz_loadu_ps(0x00ff, pack.v[vertex][axis]);   // only the 8 lanes are read
}

template <class Pack>
PA_AVX512 inline __m512d loadWidened(const Pack& pack, int vertex, int axis, int lane0) {
  return _mm512_cvtps_pd(_mm256_load_ps(pack.v[vertex][axis] + lane0));
}

template <class Pack>
PA_AVX512 inline __m256 planeDistances(const Pack& pack, int lane0, const TriangleRay16& r, __m256 fallback) {
  const __m512d v0x = loadWidened(pack, 0, 0, lane0), v0y = loadWidened(pack, 0, 1, lane0),
                v0z = loadWidened(pack, 0, 2, lane0);
  const __m512d e1x = _mm512_sub_pd(loadWidened(pack, 1, 0, lane0), v0x),
                e1y = _mm512_sub_pd(loadWidened(pack, 1, 1, lane0), v0y),
                e1z = _mm512_sub_pd(loadWidened(pack, 1, 2, lane0), v0z);
  const __m512d e2x = _mm512_sub_pd(loadWidened(pack, 2, 0, lane0), v0x),
                e2y = _mm512_sub_pd(loadWidened(pack, 2, 1, lane0), v0y),
                e2z = _mm512_sub_pd(loadWidened(pack, 2, 2, lane0), v0z);
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

/// Final lane results of one pack test (bit-identical to the scalar test's).
struct PackCandidates16 {
  alignas(64) float t[kWide16Width];   ///< Accurate (plane) hit distance.
  alignas(64) float u[kWide16Width];
  alignas(64) float v[kWide16Width];
};

/// Watertight test of a pack's sixteen triangles (intersectTriangleWatertight, lane for lane);
/// returns the lanes hit within [tmin, tmax] by their accurate distance, with their distances
/// and barycentrics in out.
template <class Pack>
PA_AVX512 inline unsigned testPack(const Pack& pack, const TriangleRay16& r, float tmin, float tmax,
                                   PackCandidates16& out) {
  const __m512 az = _mm512_sub_ps(loadLanes(pack, 0, r.kz), r.oz);
  const __m512 bz = _mm512_sub_ps(loadLanes(pack, 1, r.kz), r.oz);
  const __m512 cz = _mm512_sub_ps(loadLanes(pack, 2, r.kz), r.oz);
  const __m512 ax = _mm512_sub_ps(_mm512_sub_ps(loadLanes(pack, 0, r.kx), r.ox), _mm512_mul_ps(r.sx, az));
  const __m512 ay = _mm512_sub_ps(_mm512_sub_ps(loadLanes(pack, 0, r.ky), r.oy), _mm512_mul_ps(r.sy, az));
  const __m512 bx = _mm512_sub_ps(_mm512_sub_ps(loadLanes(pack, 1, r.kx), r.ox), _mm512_mul_ps(r.sx, bz));
  const __m512 by = _mm512_sub_ps(_mm512_sub_ps(loadLanes(pack, 1, r.ky), r.oy), _mm512_mul_ps(r.sy, bz));
  const __m512 cx = _mm512_sub_ps(_mm512_sub_ps(loadLanes(pack, 2, r.kx), r.ox), _mm512_mul_ps(r.sx, cz));
  const __m512 cy = _mm512_sub_ps(_mm512_sub_ps(loadLanes(pack, 2, r.ky), r.oy), _mm512_mul_ps(r.sy, cz));
  __m512 u = _mm512_sub_ps(_mm512_mul_ps(cx, by), _mm512_mul_ps(cy, bx));
  __m512 v = _mm512_sub_ps(_mm512_mul_ps(ax, cy), _mm512_mul_ps(ay, cx));
  __m512 w = _mm512_sub_ps(_mm512_mul_ps(bx, ay), _mm512_mul_ps(by, ax));
  const __m512 zero = _mm512_setzero_ps();
  const __mmask16 valid = static_cast<__mmask16>(pack.validBits);
  const __mmask16 onEdge = (_mm512_cmp_ps_mask(u, zero, _CMP_EQ_OQ) | _mm512_cmp_ps_mask(v, zero, _CMP_EQ_OQ) |
                            _mm512_cmp_ps_mask(w, zero, _CMP_EQ_OQ)) & valid;
  if (onEdge) {
    // Exact zero in float: these lanes are decided with the edge functions in double.
    u = _mm512_mask_mov_ps(u, onEdge, differenceOfProductsInDouble(cx, by, cy, bx));
    v = _mm512_mask_mov_ps(v, onEdge, differenceOfProductsInDouble(ax, cy, ay, cx));
    w = _mm512_mask_mov_ps(w, onEdge, differenceOfProductsInDouble(bx, ay, by, ax));
  }
  const __mmask16 negative = _mm512_cmp_ps_mask(u, zero, _CMP_LT_OQ) | _mm512_cmp_ps_mask(v, zero, _CMP_LT_OQ) |
                             _mm512_cmp_ps_mask(w, zero, _CMP_LT_OQ);
  const __mmask16 positive = _mm512_cmp_ps_mask(u, zero, _CMP_GT_OQ) | _mm512_cmp_ps_mask(v, zero, _CMP_GT_OQ) |
                             _mm512_cmp_ps_mask(w, zero, _CMP_GT_OQ);
  __mmask16 hits = valid & ~(negative & positive);
  if (!hits) return 0;
  const __m512 det = _mm512_add_ps(_mm512_add_ps(u, v), w);
  hits &= _mm512_cmp_ps_mask(det, zero, _CMP_NEQ_UQ);
  if (!hits) return 0;
  const __m512 tScaled = _mm512_add_ps(
      _mm512_add_ps(_mm512_mul_ps(u, _mm512_mul_ps(r.sz, az)), _mm512_mul_ps(v, _mm512_mul_ps(r.sz, bz))),
      _mm512_mul_ps(w, _mm512_mul_ps(r.sz, cz)));
  const __m512 rcp = _mm512_div_ps(_mm512_set1_ps(1.0f), det);
  const __m512 fallback = _mm512_mul_ps(tScaled, rcp);
  // The accurate distance only for the halves that hold a candidate.
  __m256 t[2] = {_mm512_castps512_ps256(fallback), _mm512_extractf32x8_ps(fallback, 1)};
  for (int half = 0; half < 2; ++half)
    if (hits >> (8 * half) & 0xff) t[half] = planeDistances(pack, 8 * half, r, t[half]);   // half 1: 16-wide only
  const __m512 tAll = _mm512_insertf32x8(_mm512_zextps256_ps512(t[0]), t[1], 1);
  hits &= _mm512_cmp_ps_mask(tAll, _mm512_set1_ps(tmin), _CMP_GE_OQ) &
          _mm512_cmp_ps_mask(tAll, _mm512_set1_ps(tmax), _CMP_LE_OQ);
  if (!hits) return 0;
  _mm512_store_ps(out.t, tAll);
  _mm512_store_ps(out.u, _mm512_mul_ps(v, rcp));
  _mm512_store_ps(out.v, _mm512_mul_ps(w, rcp));
  return hits;
}

/// Tests a leaf's triangles against [ray.tmin, tmax], in lane order: closest hit (kAnyHit
/// false) shortens tmax and writes hit for every accepted hit; any hit returns true at the
/// first accepted one.
/// Tests one pack's triangles against [ray.tmin, tmax] and accepts its hits (acceptPackHits).
template <bool kAnyHit, class Pack>
PA_AVX512 inline bool testPackHits(const Pack& pack, const TriangleRay16& triRay, const Ray& ray, float& tmax, Hit& hit,
                                   const HitFilter& filter, uint32_t instanceId) {
  PackCandidates16 c;
  const unsigned lanes = testPack(pack, triRay, ray.tmin, tmax, c);
  return acceptPackHits<kAnyHit>(pack, lanes, c.t, c.u, c.v, tmax, hit, filter, instanceId);
}

/// Tests a leaf's triangles (its small pack or its 16-wide packs) as testPackHits does.
template <bool kAnyHit>
PA_AVX512 inline bool testLeaf(const Wide16Bvh& bvh, uint32_t ref, const TriangleRay16& triRay, const Ray& ray,
                               float& tmax, Hit& hit, const HitFilter& filter, uint32_t instanceId) {
  if (ref & kSmallLeafBit)
    return testPackHits<kAnyHit>(bvh.smallPacks[ref & kFirstPackMask], triRay, ray, tmax, hit, filter, instanceId);
  uint32_t first, count;
  leafPacks(ref, first, count);
  bool found = false;
  for (uint32_t p = first; p < first + count; ++p) {
    if (testPackHits<kAnyHit>(bvh.packs[p], triRay, ray, tmax, hit, filter, instanceId)) {
      if constexpr (kAnyHit) return true;
      found = true;
    }
  }
  return found;
}

}  // namespace

bool wide16Available() {
  return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") &&
         __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("avx512dq");
}

PA_AVX512 bool intersectWide16(const Wide16Bvh& bvh, Ray& ray, Hit& hit, const HitFilter& filter, uint32_t instanceId) {
  if (bvh.empty()) return false;
  const BoxRay16 boxRay = makeBoxRay16(ray);
  const TriangleRay16 triRay = makeTriangleRay16(ray);
  const __m128i orderShift = _mm_cvtsi32_si128(boxRay.orderShift);
  Stack16<true> stack;
  uint32_t current = 0;
  bool found = false;
  for (;;) {
    if (!(current & kLeafBit)) {
      const Wide16Node& node = bvh.nodes[current];
      __m512 tNear;
      const __mmask16 mask = testNode(boxRay, node, ray.tmax, tNear);
      if (mask != 0) {
        if ((mask & (mask - 1)) == 0) {   // exactly one child
          current = node.child[std::countr_zero(static_cast<uint32_t>(mask))];
          continue;
        }
        // The entered children in the octant's order, farthest first: the nearest is taken
        // next, the others pushed so that the nearer are popped first.
        const __m512i order = _mm512_and_si512(_mm512_srl_epi32(_mm512_load_si512(node.order), orderShift),
                                               _mm512_set1_epi32(15));
        const uint32_t ordered =
            _mm512_movepi32_mask(_mm512_permutexvar_epi32(order, _mm512_movm_epi32(mask)));
        const int nearestPosition = 31 - std::countl_zero(ordered);
        current = node.child[(node.order[nearestPosition] >> boxRay.orderShift) & 15];
        const __mmask16 rest = static_cast<__mmask16>(ordered & ~(1u << nearestPosition));
        push(stack, rest, _mm512_permutexvar_epi32(order, _mm512_load_si512(node.child)),
             _mm512_permutexvar_ps(order, tNear));
        continue;
      }
    } else if (testLeaf<false>(bvh, current, triRay, ray, ray.tmax, hit, filter, instanceId)) {
      found = true;
    }
    // Pop the next entry that may still hold a nearer hit.
    if (!popEntryWithin(stack, ray.tmax * kRobustFarScale, current)) return found;
  }
}

PA_AVX512 bool occludedWide16(const Wide16Bvh& bvh, const Ray& ray, const HitFilter& filter, uint32_t instanceId) {
  if (bvh.empty()) return false;
  const BoxRay16 boxRay = makeBoxRay16(ray);
  const TriangleRay16 triRay = makeTriangleRay16(ray);
  Stack16<false> stack;
  uint32_t current = 0;
  for (;;) {
    if (!(current & kLeafBit)) {
      const Wide16Node& node = bvh.nodes[current];
      __m512 tNear;
      const __mmask16 mask = testNode(boxRay, node, ray.tmax, tNear);
      if (mask != 0) {
        current = node.child[std::countr_zero(static_cast<uint32_t>(mask))];
        if (const __mmask16 rest = mask & (mask - 1)) push(stack, rest, _mm512_load_si512(node.child), tNear);
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

#else

namespace pa::bvh_detail {
bool wide16Available() { return false; }
bool intersectWide16(const Wide16Bvh&, Ray&, Hit&, const HitFilter&, uint32_t) { return false; }
bool occludedWide16(const Wide16Bvh&, const Ray&, const HitFilter&, uint32_t) { return false; }
}  // namespace pa::bvh_detail

#endif  // __AVX2__
