// The baseline lanes of the wide traversal (wide_traversal_loop.h) on the 8-wide BVH: AVX2 in
// x86-64-v3 builds, SSE halves in x86-64-v2 builds (simd.h). Hit children are pushed in lane
// order through a lane table (AVX2) or one by one (SSE); a closest-hit ray goes on with the
// nearest entered child; a leaf's accurate plane distances are computed lane by lane. BVHs
// collapsed on a CPU with AVX-512 run the lanes of wide_traversal_avx512.cpp instead
// (WideBvh::kernel, dispatched below).
#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

#include "renderer/bvh/cpu_features.h"
#include "renderer/bvh/simd.h"
#include "renderer/bvh/slab_test.h"
#include "renderer/bvh/watertight.h"
#include "renderer/bvh/wide16_bvh.h"
#include "renderer/bvh/wide_bvh.h"
#include "renderer/bvh/wide_traversal_stack.h"

#define PA_BVH_KERNEL
#include "renderer/bvh/wide_traversal_loop.h"
#include "renderer/bvh/wide_packet_loop.h"

namespace pa::bvh_detail {
namespace {

using simd::vfloat8;
static_assert(kPackWidth == kWideWidth, "one register holds a node's children and a pack's triangles");

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
inline __m256i compactPermutation(unsigned mask) {
  const __m256i packed = _mm256_set1_epi32(static_cast<int>(kCompactLanes[mask]));
  const __m256i shifts = _mm256_setr_epi32(0, 3, 6, 9, 12, 15, 18, 21);
  return _mm256_and_si256(_mm256_srlv_epi32(packed, shifts), _mm256_set1_epi32(7));
}
#endif

/// The build's 8 lanes (AVX2, or SSE halves) on the 8-wide layout.
struct BaselineLanes {
  using Float = vfloat8;
  using Float8 = vfloat8;
  using Node = WideNode;
  using Bvh = WideBvh;
  static constexpr uint32_t kWidth = kWideWidth;
  static constexpr bool kOctantOrder = false;
  static constexpr bool kSmallLeaves = false;
  static constexpr bool kLaneByLaneHits = true;

  /// The ray, for planeHitDistance.
  struct PlaneRay {
    glm::vec3 origin, dir;
    explicit PlaneRay(const Ray& ray) : origin(ray.origin), dir(ray.dir) {}
  };

  /// Pushes the children in mask (in lane order), with their entry distances when the stack
  /// keeps them. Branch free: which children a ray enters is unpredictable.
  template <bool kWithDistance>
  [[gnu::always_inline]] static void pushChildren(const WideNode& node, unsigned mask, vfloat8 tNear,
                                                  TraversalStack<kWithDistance>& stack) {
#if defined(__AVX2__)
    const __m256i permutation = compactPermutation(mask);
    const __m256i children = _mm256_load_si256(reinterpret_cast<const __m256i*>(node.child));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(stack.node + stack.top),
                        _mm256_permutevar8x32_epi32(children, permutation));
    if constexpr (kWithDistance)
      _mm256_storeu_ps(stack.entry + stack.top, _mm256_permutevar8x32_ps(tNear.v, permutation));
    stack.top += std::popcount(mask);
#else
    alignas(32) float t[kWideWidth];
    tNear.store(t);
    for (; mask; mask &= mask - 1) {
      const int i = std::countr_zero(mask);
      stack.node[stack.top] = node.child[i];
      if constexpr (kWithDistance) stack.entry[stack.top] = t[i];
      ++stack.top;
    }
#endif
  }

  /// Closest hit: the children other than the nearest are pushed unsorted and culled when
  /// popped behind a nearer hit (a full sort measured slower here, renderer/bvh/README.md).
  [[gnu::always_inline]] static void pushFarther(const WideNode& node, unsigned mask, vfloat8 tNear,
                                                 TraversalStack<true>& stack) {
    pushChildren(node, mask, tNear, stack);
  }

  /// Index of the lane in mask (>= 2 bits) with the smallest entry distance (lowest lane on ties).
  [[gnu::always_inline]] static int nearestLane(unsigned mask, vfloat8 tNear) {
#if defined(__AVX2__)
    const __m256 inf = _mm256_set1_ps(std::numeric_limits<float>::infinity());
    const __m256 d = _mm256_blendv_ps(inf, tNear.v, simd::laneMask(mask).v);
    __m256 m = _mm256_min_ps(d, _mm256_permute2f128_ps(d, d, 0x01));
    m = _mm256_min_ps(m, _mm256_shuffle_ps(m, m, 0x4e));
    m = _mm256_min_ps(m, _mm256_shuffle_ps(m, m, 0xb1));
    return std::countr_zero(static_cast<unsigned>(_mm256_movemask_ps(_mm256_cmp_ps(d, m, _CMP_EQ_OQ))) & mask);
#else
    alignas(32) float t[kWideWidth];
    tNear.store(t);
    int best = std::countr_zero(mask);
    for (unsigned rest = mask & (mask - 1); rest; rest &= rest - 1) {
      const int i = std::countr_zero(rest);
      if (t[i] < t[best]) best = i;
    }
    return best;
#endif
  }

  /// One vertex coordinate of the pack's eight triangles.
  static vfloat8 loadVertex(const TrianglePack& pack, int vertex, int axis) {
    return vfloat8::load(pack.v[vertex][axis]);
  }

  /// The edge functions u, v, w of the lanes in onEdge, again in double (as the scalar test).
  static void redoEdgesInDouble(unsigned onEdge, vfloat8 ax, vfloat8 ay, vfloat8 bx, vfloat8 by, vfloat8 cx,
                                vfloat8 cy, vfloat8& u, vfloat8& v, vfloat8& w) {
    alignas(32) float f[9][kPackWidth];
    ax.store(f[0]); ay.store(f[1]); bx.store(f[2]); by.store(f[3]); cx.store(f[4]); cy.store(f[5]);
    u.store(f[6]); v.store(f[7]); w.store(f[8]);
    for (; onEdge; onEdge &= onEdge - 1) {
      const int lane = std::countr_zero(onEdge);
      const double dax = f[0][lane], day = f[1][lane], dbx = f[2][lane], dby = f[3][lane], dcx = f[4][lane],
                   dcy = f[5][lane];
      f[6][lane] = static_cast<float>(dcx * dby - dcy * dbx);
      f[7][lane] = static_cast<float>(dax * dcy - day * dcx);
      f[8][lane] = static_cast<float>(dbx * day - dby * dax);
    }
    u = vfloat8::load(f[6]);
    v = vfloat8::load(f[7]);
    w = vfloat8::load(f[8]);
  }

  /// Accepts the lanes of a pack test in lane order, each lane's accurate distance computed
  /// (planeHitDistance) and range-tested on its own: closest hit (kAnyHit false) shortens tmax
  /// and writes hit for every accepted lane; any hit returns true at the first one.
  template <bool kAnyHit>
  [[gnu::always_inline]] static bool acceptLaneByLane(const TrianglePack& pack, unsigned lanes,
                                                      const PackEdges<vfloat8>& e, const PlaneRay& r, float tmin,
                                                      float& tmax, Hit& hit, const HitFilter& filter,
                                                      uint32_t instanceId) {
    alignas(32) float tScaled[kPackWidth], det[kPackWidth], bu[kPackWidth], bv[kPackWidth];
    e.tScaled.store(tScaled);
    e.det.store(det);
    e.u.store(bu);
    e.v.store(bv);
    bool found = false;
    for (; lanes; lanes &= lanes - 1) {
      const int lane = std::countr_zero(lanes);
      const float rcp = 1.0f / det[lane];
      const auto vertex = [&](int k) { return glm::vec3(pack.v[k][0][lane], pack.v[k][1][lane], pack.v[k][2][lane]); };
      const float t = planeHitDistance(r.origin, r.dir, vertex(0), vertex(1), vertex(2), tScaled[lane] * rcp);
      if (!(t >= tmin && t <= tmax)) continue;
      const float u = bu[lane] * rcp, v = bv[lane] * rcp;
      if ((pack.maskedBits >> lane & 1) && !filter(instanceId, pack.prim[lane], u, v)) continue;
      if constexpr (kAnyHit) {
        return true;
      } else {
        tmax = t;
        hit = {t, u, v, pack.prim[lane], instanceId};
        found = true;
      }
    }
    return found;
  }

  /// Packets: each ray's origin and direction.
  struct PacketPlane {
    glm::vec3 origin[kWideWidth], dir[kWideWidth];
    PacketPlane() = default;
    PacketPlane(const vfloat8 (&o)[3], const vfloat8 (&d)[3]) {
      alignas(32) float f[6][kWideWidth];
      for (int axis = 0; axis < 3; ++axis) {
        o[axis].store(f[axis]);
        d[axis].store(f[3 + axis]);
      }
      for (uint32_t lane = 0; lane < kWideWidth; ++lane) {
        origin[lane] = {f[0][lane], f[1][lane], f[2][lane]};
        dir[lane] = {f[3][lane], f[4][lane], f[5][lane]};
      }
    }
  };

  /// Packets: planeHitDistance of triangle `lane` of the pack for each ray (lane) in rays,
  /// fallback elsewhere.
  static vfloat8 planeDistancesOverRays(const TrianglePack& pack, int lane, const PacketPlane& r, unsigned rays,
                                        vfloat8 fallback) {
    const auto vertex = [&](int k) { return glm::vec3(pack.v[k][0][lane], pack.v[k][1][lane], pack.v[k][2][lane]); };
    const glm::vec3 v0 = vertex(0), v1 = vertex(1), v2 = vertex(2);
    alignas(32) float t[kWideWidth];
    fallback.store(t);
    for (; rays; rays &= rays - 1) {
      const int ray = std::countr_zero(rays);
      t[ray] = planeHitDistance(r.origin[ray], r.dir[ray], v0, v1, v2, t[ray]);
    }
    return vfloat8::load(t);
  }
};


}  // namespace

bool wideKernelAvailable(WideKernel kernel) { return kernel == WideKernel::Baseline || avx512KernelsAvailable(); }

WideKernel bestWideKernel() {
  return wideKernelAvailable(WideKernel::Avx512) ? WideKernel::Avx512 : WideKernel::Baseline;
}

bool intersectWide(const WideBvh& bvh, Ray& ray, Hit& hit, const HitFilter& filter, uint32_t instanceId) {
#if defined(__AVX2__)
  if (bvh.kernel == WideKernel::Avx512) return intersectWideAvx512(bvh, ray, hit, filter, instanceId);
#endif
  return traverse<BaselineLanes, false>(bvh, ray, ray.tmax, hit, filter, instanceId);
}

unsigned intersectWidePacket(const WideBvh& bvh, Ray* rays, Hit* hits, unsigned active, const HitFilter* filters,
                             uint32_t instanceId) {
#if defined(__AVX2__)
  if (bvh.kernel == WideKernel::Avx512)
    return intersectWidePacketAvx512(bvh, rays, hits, active, filters, instanceId);
#endif
  return intersectPacket<BaselineLanes, intersectWide>(bvh, rays, hits, active, filters, instanceId);
}

bool occludedWide(const WideBvh& bvh, const Ray& ray, const HitFilter& filter, uint32_t instanceId) {
#if defined(__AVX2__)
  if (bvh.kernel == WideKernel::Avx512) return occludedWideAvx512(bvh, ray, filter, instanceId);
#endif
  float tmax = ray.tmax;
  Hit unused;
  return traverse<BaselineLanes, true>(bvh, ray, tmax, unused, filter, instanceId);
}

}  // namespace pa::bvh_detail
