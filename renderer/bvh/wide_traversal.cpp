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
      if ((pack.maskedBits >> lane & 1) && !filter(instanceId, pack.prim[lane], u, v, t)) continue;
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

  /// Packets: rays[i] in lane i for the lanes given, the first of them in the other lanes.
  static PacketRays<vfloat8> loadRays(const Ray* rays, unsigned lanes) {
    const int first = std::countr_zero(lanes);
    vfloat8 field[kRayRecordFloats];
#if defined(__AVX2__)
    // Each lane's record index (the first live ray's in idle lanes) x kRayRecordFloats (8), one
    // field per gather (here as fast as loading the records and transposing them, which the
    // sixteen-lane AVX-512 packets do).
    const __m256i lane = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
    const __m256i bit = _mm256_sllv_epi32(_mm256_set1_epi32(1), lane);
    const __m256i live = _mm256_cmpeq_epi32(_mm256_and_si256(_mm256_set1_epi32(static_cast<int>(lanes)), bit), bit);
    const __m256i records = _mm256_slli_epi32(_mm256_blendv_epi8(_mm256_set1_epi32(first), lane, live), 3);
    const float* base = &rays[0].origin.x;
    for (int k = 0; k < kRayRecordFloats; ++k)
      field[k] = _mm256_i32gather_ps(base, _mm256_add_epi32(records, _mm256_set1_epi32(k)), 4);
#else
    alignas(32) float soa[kRayRecordFloats][kWideWidth];
    for (uint32_t lane = 0; lane < kWideWidth; ++lane) {
      const float* record = &rays[lanes >> lane & 1 ? lane : first].origin.x;
      for (int k = 0; k < kRayRecordFloats; ++k) soa[k][lane] = record[k];
    }
    for (int k = 0; k < kRayRecordFloats; ++k) field[k] = vfloat8::load(soa[k]);
#endif
    return packetRaysFromRecords(field);
  }

  /// Packets: each ray's origin and direction, in double.
  struct PacketPlane {
    alignas(32) double o[3][kWideWidth], d[3][kWideWidth];
    PacketPlane() = default;
    PacketPlane(const vfloat8 (&origin)[3], const vfloat8 (&dir)[3]) {
      alignas(32) float f[6][kWideWidth];
      for (int axis = 0; axis < 3; ++axis) {
        origin[axis].store(f[axis]);
        dir[axis].store(f[3 + axis]);
      }
      for (int axis = 0; axis < 3; ++axis)
        for (uint32_t lane = 0; lane < kWideWidth; ++lane) {
          o[axis][lane] = f[axis][lane];
          d[axis][lane] = f[3 + axis][lane];
        }
    }
  };

  /// Packets: planeHitDistance of triangle `lane` of the pack for each ray (lane) in rays,
  /// fallback elsewhere: the triangle's normal once, then the rays' distances (four per AVX
  /// register where there is one), the same double operations in the same order.
  static vfloat8 planeDistancesOverRays(const TrianglePack& pack, int lane, const PacketPlane& r, unsigned rays,
                                        vfloat8 fallback) {
    const double v0x = pack.v[0][0][lane], v0y = pack.v[0][1][lane], v0z = pack.v[0][2][lane];
    const double e1x = double(pack.v[1][0][lane]) - v0x, e1y = double(pack.v[1][1][lane]) - v0y,
                 e1z = double(pack.v[1][2][lane]) - v0z;
    const double e2x = double(pack.v[2][0][lane]) - v0x, e2y = double(pack.v[2][1][lane]) - v0y,
                 e2z = double(pack.v[2][2][lane]) - v0z;
    const double nx = e1y * e2z - e1z * e2y, ny = e1z * e2x - e1x * e2z, nz = e1x * e2y - e1y * e2x;
    alignas(32) float t[kWideWidth];
    fallback.store(t);
#if defined(__AVX2__)
    const __m256d vnx = _mm256_set1_pd(nx), vny = _mm256_set1_pd(ny), vnz = _mm256_set1_pd(nz);
    const __m256d px = _mm256_set1_pd(v0x), py = _mm256_set1_pd(v0y), pz = _mm256_set1_pd(v0z);
    for (int part = 0; part < 2; ++part) {
      if (!(rays >> (4 * part) & 0xf)) continue;
      const int at = 4 * part;
      const __m256d denom = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(vnx, _mm256_load_pd(r.d[0] + at)),
                                                        _mm256_mul_pd(vny, _mm256_load_pd(r.d[1] + at))),
                                          _mm256_mul_pd(vnz, _mm256_load_pd(r.d[2] + at)));
      const __m256d num =
          _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(vnx, _mm256_sub_pd(px, _mm256_load_pd(r.o[0] + at))),
                                      _mm256_mul_pd(vny, _mm256_sub_pd(py, _mm256_load_pd(r.o[1] + at)))),
                        _mm256_mul_pd(vnz, _mm256_sub_pd(pz, _mm256_load_pd(r.o[2] + at))));
      const __m128 distance = _mm256_cvtpd_ps(_mm256_div_pd(num, denom));
      // All-ones where parallel: a NaN whose float conversion keeps the sign bit blendv reads.
      const __m128 parallel = _mm256_cvtpd_ps(_mm256_cmp_pd(denom, _mm256_setzero_pd(), _CMP_EQ_OQ));
      _mm_store_ps(t + at, _mm_blendv_ps(distance, _mm_load_ps(t + at), parallel));
    }
#else
    for (; rays; rays &= rays - 1) {
      const int ray = std::countr_zero(rays);
      const double denom = nx * r.d[0][ray] + ny * r.d[1][ray] + nz * r.d[2][ray];
      if (denom == 0.0) continue;
      const double num = nx * (v0x - r.o[0][ray]) + ny * (v0y - r.o[1][ray]) + nz * (v0z - r.o[2][ray]);
      t[ray] = static_cast<float>(num / denom);
    }
#endif
    return vfloat8::load(t);
  }
};

/// Camera-ray packets of sixteen rays (a 4x4 pixel block) over the 8-wide layout with the
/// baseline lanes: each ray operation on two registers of eight (vfloat8x2), so the block walks
/// the tree once, not as two packets of eight that each cull and pop the same nodes. Node and
/// pack boxes are culled for the packet in eight lanes (Float8); leaves reached by one or two
/// rays of a shear class are tested with the single-ray lanes. Each half's operations are
/// BaselineLanes', so every ray's answer is still the single-ray kernel's.
struct BaselinePacketLanes16 {
  using Float = simd::vfloat8x2;
  using Float8 = vfloat8;
  using Node = WideNode;
  using Bvh = WideBvh;
  using SingleRayLanes = BaselineLanes;
  static constexpr uint32_t kWidth = 2 * kWideWidth;
  static constexpr bool kOctantOrder = false;
  static constexpr bool kSmallLeaves = false;

  /// The edge functions u, v, w of the lanes in onEdge, again in double (as the scalar test).
  static void redoEdgesInDouble(unsigned onEdge, Float ax, Float ay, Float bx, Float by, Float cx, Float cy, Float& u,
                                Float& v, Float& w) {
    if (const unsigned low = onEdge & 0xffu)
      BaselineLanes::redoEdgesInDouble(low, ax.lo, ay.lo, bx.lo, by.lo, cx.lo, cy.lo, u.lo, v.lo, w.lo);
    if (const unsigned high = onEdge >> 8 & 0xffu)
      BaselineLanes::redoEdgesInDouble(high, ax.hi, ay.hi, bx.hi, by.hi, cx.hi, cy.hi, u.hi, v.hi, w.hi);
  }

  /// rays[i] in lane i for the lanes given; every other lane holds one of them (a half without
  /// one holds the first).
  static PacketRays<Float> loadRays(const Ray* rays, unsigned lanes) {
    const int first = std::countr_zero(lanes);
    const unsigned low = lanes & 0xffu, high = lanes >> 8 & 0xffu;
    const PacketRays<vfloat8> lo = low ? BaselineLanes::loadRays(rays, low) : BaselineLanes::loadRays(rays + first, 1u);
    const PacketRays<vfloat8> hi =
        high ? BaselineLanes::loadRays(rays + kWideWidth, high) : BaselineLanes::loadRays(rays + first, 1u);
    PacketRays<Float> r;
    for (int axis = 0; axis < 3; ++axis) r.o[axis] = {lo.o[axis], hi.o[axis]}, r.d[axis] = {lo.d[axis], hi.d[axis]};
    r.tmin = {lo.tmin, hi.tmin};
    r.tmax = {lo.tmax, hi.tmax};
    return r;
  }

  /// Each ray's origin and direction in double, per half.
  struct PacketPlane {
    BaselineLanes::PacketPlane lo, hi;
    PacketPlane() = default;
    PacketPlane(const Float (&origin)[3], const Float (&dir)[3])
        : lo({origin[0].lo, origin[1].lo, origin[2].lo}, {dir[0].lo, dir[1].lo, dir[2].lo}),
          hi({origin[0].hi, origin[1].hi, origin[2].hi}, {dir[0].hi, dir[1].hi, dir[2].hi}) {}
  };

  /// planeHitDistance of triangle `lane` of the pack for each ray (lane) in rays, fallback
  /// elsewhere (BaselineLanes' per half that holds one of the rays).
  static Float planeDistancesOverRays(const TrianglePack& pack, int lane, const PacketPlane& r, unsigned rays,
                                      Float fallback) {
    Float t = fallback;
    if (const unsigned low = rays & 0xffu) t.lo = BaselineLanes::planeDistancesOverRays(pack, lane, r.lo, low, t.lo);
    if (const unsigned high = rays >> 8 & 0xffu)
      t.hi = BaselineLanes::planeDistancesOverRays(pack, lane, r.hi, high, t.hi);
    return t;
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
  return intersectPacket<BaselinePacketLanes16, intersectWide>(bvh, rays, hits, active, filters, instanceId);
}

bool occludedWide(const WideBvh& bvh, const Ray& ray, const HitFilter& filter, uint32_t instanceId) {
#if defined(__AVX2__)
  if (bvh.kernel == WideKernel::Avx512) return occludedWideAvx512(bvh, ray, filter, instanceId);
#endif
  float tmax = ray.tmax;
  Hit unused;
  return traverse<BaselineLanes, true>(bvh, ray, tmax, unused, filter, instanceId);
}

unsigned occludedWidePacket(const WideBvh& bvh, const Ray* rays, unsigned active, const HitFilter* filters,
                            uint32_t instanceId) {
#if defined(__AVX2__)
  if (bvh.kernel == WideKernel::Avx512) return occludedWidePacketAvx512(bvh, rays, active, filters, instanceId);
#endif
  return occludedPacket<BaselinePacketLanes16, occludedWide>(bvh, rays, active, filters, instanceId);
}

}  // namespace pa::bvh_detail
