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
    const __m256 laneMask = _mm256_castsi256_ps(_mm256_cmpgt_epi32(
        _mm256_and_si256(_mm256_set1_epi32(static_cast<int>(mask)), _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128)),
        _mm256_setzero_si256()));
    const __m256 d = _mm256_blendv_ps(inf, tNear.v, laneMask);
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
};


/// b where the lanes of mask are set, else a.
inline vfloat8 selectLanes(vfloat8 mask, vfloat8 a, vfloat8 b) {
#if defined(__AVX2__)
  return _mm256_blendv_ps(a.v, b.v, mask.v);
#else
  return {_mm_blendv_ps(a.lo, b.lo, mask.lo), _mm_blendv_ps(a.hi, b.hi, mask.hi)};
#endif
}

/// Up to eight rays of one octant as structure of arrays (lane = ray), their interval bounds
/// for culling a node's children or a pack's triangles for all of them at once, and the shear
/// classes of their watertight tests (as in the 16-wide packet kernel).
struct Packet8 {
  alignas(32) float ox[8], oy[8], oz[8], idx[8], idy[8], idz[8], tmin[8], tmax[8];
  alignas(32) float sx[8], sy[8], sz[8];
  PacketBounds box;
  int nearSide[3];
  unsigned classRays[6] = {};
  int axes[6][3] = {};
  uint32_t ray[8];   ///< Lane -> index into the caller's rays.
  unsigned lanes = 0;
};

/// One triangle of a pack against the rays in `rays` (one shear class), one ray per lane, with
/// the single-ray watertight arithmetic (testPackEdges, acceptLaneByLane): accepts in [tmin,
/// tmax] per ray; returns the rays that took the hit.
inline unsigned triangleOverRays8(const TrianglePack& pack, int lane, const int axes[3], Packet8& p, unsigned rays,
                                  Ray* raysIn, Hit* hits, const HitFilter* filters, uint32_t instanceId) {
  const vfloat8 origin[3] = {vfloat8::load(p.ox), vfloat8::load(p.oy), vfloat8::load(p.oz)};
  PackEdges<vfloat8> e;
  unsigned crossed = testTriangleAgainstRays<BaselineLanes>(pack, lane, axes, origin, vfloat8::load(p.sx),
                                                            vfloat8::load(p.sy), vfloat8::load(p.sz), rays, e);
  if (!crossed) return 0;
  alignas(32) float ts[8], ds[8], us[8], vs[8];
  e.tScaled.store(ts);
  e.det.store(ds);
  e.u.store(us);
  e.v.store(vs);
  const glm::vec3 v0(pack.v[0][0][lane], pack.v[0][1][lane], pack.v[0][2][lane]);
  const glm::vec3 v1(pack.v[1][0][lane], pack.v[1][1][lane], pack.v[1][2][lane]);
  const glm::vec3 v2(pack.v[2][0][lane], pack.v[2][1][lane], pack.v[2][2][lane]);
  unsigned accepted = 0;
  for (; crossed; crossed &= crossed - 1) {
    const int r = std::countr_zero(crossed);
    const Ray& ray = raysIn[p.ray[r]];
    const float rcp = 1.0f / ds[r];
    const float t = planeHitDistance(ray.origin, ray.dir, v0, v1, v2, ts[r] * rcp);
    if (!(t >= p.tmin[r] && t <= p.tmax[r])) continue;
    const float u = us[r] * rcp, v = vs[r] * rcp;
    if ((pack.maskedBits >> lane & 1) && !filters[p.ray[r]](instanceId, pack.prim[lane], u, v)) continue;
    p.tmax[r] = t;
    hits[p.ray[r]] = {t, u, v, pack.prim[lane], instanceId};
    accepted |= 1u << r;
  }
  return accepted;
}

/// Closest hits of up to eight rays of one octant with finite inverse directions over the 8-wide
/// layout: the 16-wide packet traversal's scheme (interval cull of a node's children, then each
/// child against every ray, children entered nearest first with their rays, triangles culled by
/// their boxes and tested eight rays per instruction), with the single-ray arithmetic per ray.
unsigned traversePacket8(const WideBvh& bvh, Packet8& p, Ray* rays, Hit* hits, const HitFilter* filters,
                         uint32_t instanceId) {
  const vfloat8 ox = vfloat8::load(p.ox), oy = vfloat8::load(p.oy), oz = vfloat8::load(p.oz);
  const vfloat8 idx = vfloat8::load(p.idx), idy = vfloat8::load(p.idy), idz = vfloat8::load(p.idz);
  const vfloat8 tmin = vfloat8::load(p.tmin);
  const auto tmaxHi = [&](unsigned rays8) {
    float hi = -std::numeric_limits<float>::infinity();
    for (; rays8; rays8 &= rays8 - 1) hi = std::max(hi, p.tmax[std::countr_zero(rays8)]);
    return hi;
  };
  std::array<PacketEntry<8>, kStackSizeFor<kWideWidth>> stack;
  int top = 0;
  uint32_t current = 0;
  unsigned currentRays = p.lanes;
  unsigned found = 0;
  for (;;) {
    if (!(current & kLeafBit)) {
      const WideNode& node = bvh.nodes[current];
      vfloat8 lo[3], hi[3];
      for (int axis = 0; axis < 3; ++axis) {
        lo[axis] = vfloat8::load(node.bounds[0][axis]);
        hi[axis] = vfloat8::load(node.bounds[1][axis]);
      }
      const vfloat8 tmax = vfloat8::load(p.tmax);
      unsigned candidates = packetMayEnterBoxes(lo, hi, p.box, p.nearSide, tmaxHi(currentRays));
      // Each candidate against every ray (slabEntry's operations, lane = ray), nearest first.
      struct Entered {
        float key;
        uint32_t ref;
        unsigned rays;
        vfloat8 tNear;
      };
      std::array<Entered, 8> entered;
      int count = 0;
      for (; candidates; candidates &= candidates - 1) {
        const int c = std::countr_zero(candidates);
        const int* n = p.nearSide;
        const vfloat8 nx = (vfloat8(node.bounds[n[0]][0][c]) - ox) * idx;
        const vfloat8 ny = (vfloat8(node.bounds[n[1]][1][c]) - oy) * idy;
        const vfloat8 nz = (vfloat8(node.bounds[n[2]][2][c]) - oz) * idz;
        const vfloat8 fx = (vfloat8(node.bounds[1 - n[0]][0][c]) - ox) * idx;
        const vfloat8 fy = (vfloat8(node.bounds[1 - n[1]][1][c]) - oy) * idy;
        const vfloat8 fz = (vfloat8(node.bounds[1 - n[2]][2][c]) - oz) * idz;
        const vfloat8 tNear = maxKeep(nx, maxKeep(ny, maxKeep(nz, tmin)));
        const vfloat8 tFar = minKeep(fx, minKeep(fy, minKeep(fz, tmax))) * vfloat8(kRobustFarScale);
        const unsigned rays8 = static_cast<unsigned>((tNear <= tFar).mask()) & currentRays;
        if (!rays8) continue;
        alignas(32) float t[8];
        tNear.store(t);
        float key = std::numeric_limits<float>::infinity();
        for (unsigned r = rays8; r; r &= r - 1) key = std::min(key, t[std::countr_zero(r)]);
        int k = count++;   // insertion, farthest first
        while (k > 0 && entered[k - 1].key < key) {
          entered[k] = entered[k - 1];
          --k;
        }
        entered[k] = {key, node.child[c], rays8, tNear};
      }
      if (count > 0) {
        for (int k = 0; k + 1 < count; ++k) {
          PacketEntry<8>& e = stack[top++];
          entered[k].tNear.store(e.tNear);
          e.ref = entered[k].ref;
          e.rays = entered[k].rays;
        }
        current = entered[count - 1].ref;
        currentRays = entered[count - 1].rays;
        continue;
      }
    } else {
      uint32_t first, packs;
      leafPacks(current, first, packs);
      for (int c = 0; c < 6; ++c) {
        const unsigned classRays = currentRays & p.classRays[c];
        if (!classRays) continue;
        if (std::popcount(classRays) <= 2) {   // few rays: each tests eight triangles at once
          for (unsigned r = classRays; r; r &= r - 1) {
            const int lane = std::countr_zero(r);
            Ray& ray = rays[p.ray[lane]];
            if (testLeaf<BaselineLanes, false>(bvh, current, TriangleRay<BaselineLanes>(ray), ray, p.tmax[lane],
                                               hits[p.ray[lane]], filters[p.ray[lane]], instanceId))
              found |= 1u << lane;
          }
          continue;
        }
        for (uint32_t k = first; k < first + packs; ++k) {
          const TrianglePack& pack = bvh.packs[k];
          vfloat8 lo[3], hi[3];
          for (int axis = 0; axis < 3; ++axis) {
            const vfloat8 a = vfloat8::load(pack.v[0][axis]), b = vfloat8::load(pack.v[1][axis]),
                          d = vfloat8::load(pack.v[2][axis]);
            lo[axis] = minKeep(a, minKeep(b, d));
            hi[axis] = maxKeep(a, maxKeep(b, d));
          }
          unsigned triangles = pack.validBits & packetMayEnterBoxes(lo, hi, p.box, p.nearSide, tmaxHi(classRays));
          for (; triangles; triangles &= triangles - 1)
            found |= triangleOverRays8(pack, std::countr_zero(triangles), p.axes[c], p, classRays, rays, hits,
                                       filters, instanceId);
        }
      }
    }
    if (!popLivePacketEntry(stack.data(), top, vfloat8::load(p.tmax), current, currentRays)) return found;
  }
}

/// Fills a Packet8 with the rays in `rays16` (at most eight, one octant, finite inverse
/// directions): structure of arrays, interval bounds and shear classes.
void makePacket8(const Ray* rays, unsigned rays16, Packet8& p) {
  const int first = std::countr_zero(rays16);
  for (int axis = 0; axis < 3; ++axis) {
    p.box.oLo[axis] = p.box.iLo[axis] = std::numeric_limits<float>::infinity();
    p.box.oHi[axis] = p.box.iHi[axis] = -std::numeric_limits<float>::infinity();
    p.nearSide[axis] = std::signbit(rays[first].dir[axis]);
  }
  p.box.tminLo = std::numeric_limits<float>::infinity();
  int lane = 0;
  for (unsigned r = rays16; r; r &= r - 1, ++lane) {
    const int index = std::countr_zero(r);
    const Ray& ray = rays[index];
    p.ray[lane] = static_cast<uint32_t>(index);
    p.lanes |= 1u << lane;
    p.ox[lane] = ray.origin.x, p.oy[lane] = ray.origin.y, p.oz[lane] = ray.origin.z;
    p.idx[lane] = 1.0f / ray.dir.x, p.idy[lane] = 1.0f / ray.dir.y, p.idz[lane] = 1.0f / ray.dir.z;
    p.tmin[lane] = ray.tmin, p.tmax[lane] = ray.tmax;
    const float o[3] = {p.ox[lane], p.oy[lane], p.oz[lane]}, id[3] = {p.idx[lane], p.idy[lane], p.idz[lane]};
    for (int axis = 0; axis < 3; ++axis) {
      p.box.oLo[axis] = std::min(p.box.oLo[axis], o[axis]), p.box.oHi[axis] = std::max(p.box.oHi[axis], o[axis]);
      p.box.iLo[axis] = std::min(p.box.iLo[axis], id[axis]), p.box.iHi[axis] = std::max(p.box.iHi[axis], id[axis]);
    }
    p.box.tminLo = std::min(p.box.tminLo, ray.tmin);
    const RayShear shear(ray.dir);
    const int c = 2 * shear.kz + (shear.kx != (shear.kz + 1) % 3);
    p.classRays[c] |= 1u << lane;
    p.axes[c][0] = shear.kx, p.axes[c][1] = shear.ky, p.axes[c][2] = shear.kz;
    p.sx[lane] = shear.sx, p.sy[lane] = shear.sy, p.sz[lane] = shear.sz;
  }
  for (; lane < 8; ++lane) {   // idle lanes: a real ray's values, never active
    p.ox[lane] = p.ox[0], p.oy[lane] = p.oy[0], p.oz[lane] = p.oz[0];
    p.idx[lane] = p.idx[0], p.idy[lane] = p.idy[0], p.idz[lane] = p.idz[0];
    p.tmin[lane] = p.tmin[0], p.tmax[lane] = -std::numeric_limits<float>::infinity();
    p.sx[lane] = p.sx[0], p.sy[lane] = p.sy[0], p.sz[lane] = p.sz[0];
  }
}

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
  if (bvh.empty()) return 0;
  unsigned found = 0;
  unsigned byOctant[8] = {};
  for (unsigned r = active; r; r &= r - 1) {
    const int lane = std::countr_zero(r);
    const Ray& ray = rays[lane];
    const bool finite = ray.dir.x != 0.0f && ray.dir.y != 0.0f && ray.dir.z != 0.0f &&
                        std::isfinite(1.0f / ray.dir.x) && std::isfinite(1.0f / ray.dir.y) &&
                        std::isfinite(1.0f / ray.dir.z);
    if (!finite) {
      if (intersectWide(bvh, rays[lane], hits[lane], filters[lane], instanceId)) found |= 1u << lane;
      continue;
    }
    byOctant[std::signbit(ray.dir.x) | std::signbit(ray.dir.y) << 1 | std::signbit(ray.dir.z) << 2] |= 1u << lane;
  }
  for (unsigned octantRays : byOctant) {
    while (octantRays) {
      unsigned chunk = 0;   // the next (up to) eight rays of the octant
      for (int k = 0; k < 8 && octantRays; ++k) {
        chunk |= octantRays & (~octantRays + 1);
        octantRays &= octantRays - 1;
      }
      if (std::popcount(chunk) == 1) {
        const int lane = std::countr_zero(chunk);
        if (intersectWide(bvh, rays[lane], hits[lane], filters[lane], instanceId)) found |= 1u << lane;
        continue;
      }
      Packet8 packet;
      makePacket8(rays, chunk, packet);
      const unsigned hit8 = traversePacket8(bvh, packet, rays, hits, filters, instanceId);
      for (unsigned r = hit8; r; r &= r - 1) {
        const int lane = std::countr_zero(r);
        rays[packet.ray[lane]].tmax = packet.tmax[lane];
        found |= 1u << packet.ray[lane];
      }
    }
  }
  return found;
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
