// SIMD traversal of the 8-wide BVH: one ray against eight child boxes at a time (conservative
// slab test, see slab_test.h), nearest child first for closest hits (any-hit rays skip even
// that), other hit children pushed branch-free, and a leaf's (up to) eight triangles at a time
// with the watertight test (see watertight.h; same operations in the same order, so the
// results are bit-identical to the scalar reference). This is the baseline kernel (AVX2 in
// x86-64-v3 builds, SSE halves in x86-64-v2 builds); BVHs collapsed on a CPU with AVX-512 run the
// kernel of wide_traversal_avx512.cpp instead (WideBvh::kernel, dispatched below).
#include <cmath>
#include <algorithm>
#include <array>
#include <limits>
#include <bit>
#include <cstring>
#include <type_traits>

#include "renderer/bvh/simd.h"
#include "renderer/bvh/slab_test.h"
#include "renderer/bvh/watertight.h"
#include "renderer/bvh/wide_bvh.h"
#include "renderer/bvh/wide_traversal_stack.h"

namespace pa::bvh_detail {
namespace {

using simd::vfloat4;
using simd::vfloat8;

/// Per-ray constants for the box tests.
struct BoxRay {
  vfloat8 ox, oy, oz, idx, idy, idz;
  int nearX, nearY, nearZ;
  vfloat8 tmin;

  explicit BoxRay(const Ray& ray)
      : ox(ray.origin.x), oy(ray.origin.y), oz(ray.origin.z), idx(1.0f / ray.dir.x), idy(1.0f / ray.dir.y),
        idz(1.0f / ray.dir.z), nearX(std::signbit(ray.dir.x)), nearY(std::signbit(ray.dir.y)), nearZ(std::signbit(ray.dir.z)),
        tmin(ray.tmin) {}

  /// Entry distances of the eight children and the mask of those the ray enters before tmax.
  int test(const WideNode& node, float tmax, vfloat8& tNear) const {
    const vfloat8 nx = (vfloat8::load(node.bounds[nearX][0]) - ox) * idx;
    const vfloat8 ny = (vfloat8::load(node.bounds[nearY][1]) - oy) * idy;
    const vfloat8 nz = (vfloat8::load(node.bounds[nearZ][2]) - oz) * idz;
    const vfloat8 fx = (vfloat8::load(node.bounds[1 - nearX][0]) - ox) * idx;
    const vfloat8 fy = (vfloat8::load(node.bounds[1 - nearY][1]) - oy) * idy;
    const vfloat8 fz = (vfloat8::load(node.bounds[1 - nearZ][2]) - oz) * idz;
    tNear = simd::maxKeep(nx, simd::maxKeep(ny, simd::maxKeep(nz, tmin)));
    const vfloat8 tFar = simd::minKeep(fx, simd::minKeep(fy, simd::minKeep(fz, vfloat8(tmax)))) *
                         vfloat8(kRobustFarScale);
    return (tNear <= tFar).mask();
  }
};

/// SIMD register type with one lane per pack triangle.
using PackFloat = std::conditional_t<kPackWidth == 8, vfloat8, vfloat4>;

/// Per-ray constants for the watertight triangle test of a whole pack.
struct TriangleRay {
  RayShear shear;
  PackFloat ox, oy, oz, sx, sy, sz;

  explicit TriangleRay(const Ray& ray)
      : shear(ray.dir), ox(ray.origin[shear.kx]), oy(ray.origin[shear.ky]), oz(ray.origin[shear.kz]),
        sx(shear.sx), sy(shear.sy), sz(shear.sz) {}
};

/// Lane results of one pack test.
struct PackCandidates {
  alignas(32) float t[kPackWidth];   ///< Sheared-space t (T), not yet divided by det; fallback only.
  alignas(32) float det[kPackWidth];
  alignas(32) float u[kPackWidth];
  alignas(32) float v[kPackWidth];
};

/// Watertight test of a pack's triangles; returns the lanes the ray line passes through (any t).
int testPack(const TrianglePack& pack, const TriangleRay& r, PackCandidates& out) {
  const int kx = r.shear.kx, ky = r.shear.ky, kz = r.shear.kz;
  const PackFloat az = PackFloat::load(pack.v[0][kz]) - r.oz;
  const PackFloat bz = PackFloat::load(pack.v[1][kz]) - r.oz;
  const PackFloat cz = PackFloat::load(pack.v[2][kz]) - r.oz;
  const PackFloat ax = (PackFloat::load(pack.v[0][kx]) - r.ox) - r.sx * az;
  const PackFloat ay = (PackFloat::load(pack.v[0][ky]) - r.oy) - r.sy * az;
  const PackFloat bx = (PackFloat::load(pack.v[1][kx]) - r.ox) - r.sx * bz;
  const PackFloat by = (PackFloat::load(pack.v[1][ky]) - r.oy) - r.sy * bz;
  const PackFloat cx = (PackFloat::load(pack.v[2][kx]) - r.ox) - r.sx * cz;
  const PackFloat cy = (PackFloat::load(pack.v[2][ky]) - r.oy) - r.sy * cz;
  PackFloat u = cx * by - cy * bx;
  PackFloat v = ax * cy - ay * cx;
  PackFloat w = bx * ay - by * ax;
  const PackFloat zero(0.0f);
  const int valid = static_cast<int>(pack.validBits);
  if (const int onEdge = ((u == zero) | (v == zero) | (w == zero)).mask() & valid) {
    // Exact zero in float: decide these lanes in double, as the scalar test does.
    alignas(32) float f[9][kPackWidth];
    ax.store(f[0]); ay.store(f[1]); bx.store(f[2]); by.store(f[3]); cx.store(f[4]); cy.store(f[5]);
    u.store(f[6]); v.store(f[7]); w.store(f[8]);
    for (int lane = 0; lane < int(kPackWidth); ++lane) {
      if (!(onEdge >> lane & 1)) continue;
      const double dax = f[0][lane], day = f[1][lane], dbx = f[2][lane], dby = f[3][lane], dcx = f[4][lane],
                   dcy = f[5][lane];
      f[6][lane] = static_cast<float>(dcx * dby - dcy * dbx);
      f[7][lane] = static_cast<float>(dax * dcy - day * dcx);
      f[8][lane] = static_cast<float>(dbx * day - dby * dax);
    }
    u = PackFloat::load(f[6]);
    v = PackFloat::load(f[7]);
    w = PackFloat::load(f[8]);
  }
  const int negative = ((u < zero) | (v < zero) | (w < zero)).mask();
  const int positive = ((u > zero) | (v > zero) | (w > zero)).mask();
  int hits = valid & ~(negative & positive);
  if (!hits) return 0;
  const PackFloat det = u + v + w;
  const PackFloat tScaled = (u * (r.sz * az) + v * (r.sz * bz)) + w * (r.sz * cz);
  // No range test on the sheared distance (inaccurate on slivers): callers test the plane distance.
  hits &= (det != zero).mask();
  if (!hits) return 0;
  tScaled.store(out.t);
  det.store(out.det);
  v.store(out.u);
  w.store(out.v);
  return hits;
}

/// Accurate hit distance of one pack lane (see planeHitDistance).
inline float packPlaneDistance(const TrianglePack& pack, int lane, const Ray& ray, float fallback) {
  const auto vertex = [&](int k) { return glm::vec3(pack.v[k][0][lane], pack.v[k][1][lane], pack.v[k][2][lane]); };
  return planeHitDistance(ray.origin, ray.dir, vertex(0), vertex(1), vertex(2), fallback);
}

#if defined(__AVX2__)
/// For every 8-bit lane mask, the indices of its set lanes, lowest first, 3 bits each.
constexpr auto kCompactLanes = [] {
  std::array<uint32_t, 256> table{};
  for (uint32_t mask = 0; mask < 256; ++mask) {
    uint32_t packed = 0, count = 0;
    for (uint32_t lane = 0; lane < 8; ++lane)
      if (mask >> lane & 1) packed |= lane << (3 * count++);
    table[mask] = packed;
  }
  return table;
}();

/// Permutation that moves the lanes set in mask to the front, in lane order.
inline __m256i compactPermutation(int mask) {
  const __m256i packed = _mm256_set1_epi32(static_cast<int>(kCompactLanes[mask]));
  const __m256i shifts = _mm256_setr_epi32(0, 3, 6, 9, 12, 15, 18, 21);
  return _mm256_and_si256(_mm256_srlv_epi32(packed, shifts), _mm256_set1_epi32(7));
}
#endif

/// Pushes the children in mask (in lane order) onto the stack, with their entry distances when
/// the stack keeps them. Branch free: which children a ray enters is unpredictable.
template <bool kWithDistance>
[[gnu::always_inline]] inline void pushChildren(const WideNode& node, int mask, vfloat8 tNear,
                                                TraversalStack<kWithDistance>& stack) {
#if defined(__AVX2__)
  const __m256i permutation = compactPermutation(mask);
  const __m256i children = _mm256_load_si256(reinterpret_cast<const __m256i*>(node.child));
  _mm256_storeu_si256(reinterpret_cast<__m256i*>(stack.node + stack.top),
                      _mm256_permutevar8x32_epi32(children, permutation));
  if constexpr (kWithDistance)
    _mm256_storeu_ps(stack.entry + stack.top, _mm256_permutevar8x32_ps(tNear.v, permutation));
  stack.top += std::popcount(static_cast<uint32_t>(mask));
#else
  alignas(32) float t[kWideWidth];
  tNear.store(t);
  while (mask) {
    const int i = std::countr_zero(static_cast<uint32_t>(mask));
    mask &= mask - 1;
    stack.node[stack.top] = node.child[i];
    if constexpr (kWithDistance) stack.entry[stack.top] = t[i];
    ++stack.top;
  }
#endif
}

/// Index of the lane in mask (>= 2 bits) with the smallest entry distance (lowest lane on ties).
[[gnu::always_inline]] inline int nearestLane(int mask, vfloat8 tNear) {
  alignas(32) float t[kWideWidth];
  tNear.store(t);
#if defined(__AVX2__)
  const __m256 inf = _mm256_set1_ps(std::numeric_limits<float>::infinity());
  const __m256 laneMask = _mm256_castsi256_ps(_mm256_cmpgt_epi32(
      _mm256_and_si256(_mm256_set1_epi32(mask), _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128)),
      _mm256_setzero_si256()));
  const __m256 d = _mm256_blendv_ps(inf, tNear.v, laneMask);
  __m256 m = _mm256_min_ps(d, _mm256_permute2f128_ps(d, d, 0x01));
  m = _mm256_min_ps(m, _mm256_shuffle_ps(m, m, 0x4e));
  m = _mm256_min_ps(m, _mm256_shuffle_ps(m, m, 0xb1));
  const int nearest = _mm256_movemask_ps(_mm256_cmp_ps(d, m, _CMP_EQ_OQ)) & mask;
  return std::countr_zero(static_cast<uint32_t>(nearest));
#else
  int best = std::countr_zero(static_cast<uint32_t>(mask));
  for (int rest = mask & (mask - 1); rest; rest &= rest - 1) {
    const int i = std::countr_zero(static_cast<uint32_t>(rest));
    if (t[i] < t[best]) best = i;
  }
  return best;
#endif
}

/// Tests a leaf's triangles against the ray segment [ray.tmin, tmax]. Closest hit (kAnyHit
/// false): every accepted hit shortens tmax and is written to hit; returns whether any was.
/// Any hit: returns true at the first accepted hit and writes nothing.
template <bool kAnyHit>
[[gnu::always_inline]] inline bool testLeaf(const WideBvh& bvh, uint32_t ref, const TriangleRay& triRay,
                                            const Ray& ray, float& tmax, Hit& hit, const HitFilter& filter,
                                            uint32_t instanceId) {
  uint32_t first, count;
  leafPacks(ref, first, count);
  bool found = false;
  for (uint32_t p = first; p < first + count; ++p) {
    const TrianglePack& pack = bvh.packs[p];
    PackCandidates c;
    int lanes = testPack(pack, triRay, c);
    while (lanes) {
      const int lane = std::countr_zero(static_cast<uint32_t>(lanes));
      lanes &= lanes - 1;
      const float rcp = 1.0f / c.det[lane];
      const float t = packPlaneDistance(pack, lane, ray, c.t[lane] * rcp);
      if (!(t >= ray.tmin && t <= tmax)) continue;
      const float u = c.u[lane] * rcp, v = c.v[lane] * rcp;
      if ((pack.maskedBits >> lane & 1) && !filter(instanceId, pack.prim[lane], u, v)) continue;
      if constexpr (kAnyHit) {
        return true;
      } else {
        tmax = t;
        hit = {t, u, v, pack.prim[lane], instanceId};
        found = true;
      }
    }
  }
  return found;
}

}  // namespace

bool wideKernelAvailable(WideKernel kernel) {
  if (kernel == WideKernel::Baseline) return true;
#if defined(__AVX2__)
  return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") &&
         __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("avx512dq");
#else
  return false;
#endif
}

WideKernel bestWideKernel() {
  return wideKernelAvailable(WideKernel::Avx512) ? WideKernel::Avx512 : WideKernel::Baseline;
}

bool intersectWide(const WideBvh& bvh, Ray& ray, Hit& hit, const HitFilter& filter, uint32_t instanceId) {
  if (bvh.empty()) return false;
#if defined(__AVX2__)
  if (bvh.kernel == WideKernel::Avx512) return intersectWideAvx512(bvh, ray, hit, filter, instanceId);
#endif
  const BoxRay boxRay(ray);
  const TriangleRay triRay(ray);
  // The nearest child is traversed next; the others are pushed unsorted, with their entry
  // distances, and culled when popped if a hit nearer than their entry was found meanwhile
  // (a full sort measured slower, docs/performance.md).
  TraversalStack<true> stack;
  uint32_t current = 0;
  bool found = false;
  for (;;) {
    if (!(current & kLeafBit)) {
      const WideNode& node = bvh.nodes[current];
      vfloat8 tNear;
      const int mask = boxRay.test(node, ray.tmax, tNear);
      if (mask != 0) {
        if ((mask & (mask - 1)) == 0) {   // exactly one child
          current = node.child[std::countr_zero(static_cast<uint32_t>(mask))];
          continue;
        }
        const int afterFirst = mask & (mask - 1);
        if ((afterFirst & (afterFirst - 1)) == 0) {   // exactly two children
          alignas(32) float entry[kWideWidth];
          tNear.store(entry);
          current = takeNearerOfTwo(node, static_cast<uint32_t>(mask), entry, stack);
          continue;
        }
        const int nearest = nearestLane(mask, tNear);
        current = node.child[nearest];
        pushChildren(node, mask & ~(1 << nearest), tNear, stack);
        continue;
      }
    } else if (testLeaf<false>(bvh, current, triRay, ray, ray.tmax, hit, filter, instanceId)) {
      found = true;
    }
    // Pop the next entry that may still hold a nearer hit.
    if (!popEntryWithin(stack, ray.tmax * kRobustFarScale, current)) return found;
  }
}

bool occludedWide(const WideBvh& bvh, const Ray& ray, const HitFilter& filter, uint32_t instanceId) {
  if (bvh.empty()) return false;
#if defined(__AVX2__)
  if (bvh.kernel == WideKernel::Avx512) return occludedWideAvx512(bvh, ray, filter, instanceId);
#endif
  const BoxRay boxRay(ray);
  const TriangleRay triRay(ray);
  // Children are visited in node order, not sorted by distance: any occluder ends the search,
  // and skipping the sort measured faster (docs/performance.md).
  TraversalStack<false> stack;
  uint32_t current = 0;
  for (;;) {
    if (!(current & kLeafBit)) {
      const WideNode& node = bvh.nodes[current];
      vfloat8 tNear;
      const int mask = boxRay.test(node, ray.tmax, tNear);
      if (mask != 0) {
        current = node.child[std::countr_zero(static_cast<uint32_t>(mask))];
        if (const int rest = mask & (mask - 1)) pushChildren(node, rest, tNear, stack);
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
