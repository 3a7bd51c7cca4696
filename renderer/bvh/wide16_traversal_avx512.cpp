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
#include <algorithm>

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


/// Leaves reached by at most this many rays of a shear class are tested ray by ray (sixteen
/// triangles per instruction); more rays test the leaf triangle by triangle (sixteen rays per
/// instruction).
inline constexpr int kRayByRayLeaf = 2;

/// Packet stack bound: as TraversalStack's (each level defers at most 15 children).
inline constexpr int kPacketStackSize = kStackSizeFor<kWide16Width>;

/// The rays of one packet as structure of arrays, lane i = ray i; the per-ray slab constants
/// are BoxRay's, so a lane's child test is the single-ray test's lane for that child.
struct PacketRays {
  vfloat16 ox, oy, oz, idx, idy, idz, tmin;
  alignas(64) float tmax[kWide16Width];
};

/// Children of node that some ray of the packet may enter before tmaxHi (packetMayEnterBoxes).
PA_AVX512_INLINE unsigned packetChildren(const Wide16Node& node, const PacketBounds& b, const int nearSide[3],
                                         float tmaxHi) {
  const vfloat16 lo[3] = {vfloat16::load(node.bounds[0][0]), vfloat16::load(node.bounds[0][1]),
                          vfloat16::load(node.bounds[0][2])};
  const vfloat16 hi[3] = {vfloat16::load(node.bounds[1][0]), vfloat16::load(node.bounds[1][1]),
                          vfloat16::load(node.bounds[1][2])};
  return packetMayEnterBoxes(lo, hi, b, nearSide, tmaxHi);
}

/// The rays (lanes) of the packet that enter child slot s of node, with their entry distances:
/// testChildren's operations for that slot, one ray per lane.
PA_AVX512_INLINE unsigned raysEnteringChild(const Wide16Node& node, int s, const PacketRays& p, vfloat16 tmax,
                                            const int nearSide[3], vfloat16& tNear) {
  const vfloat16 nx = (vfloat16(node.bounds[nearSide[0]][0][s]) - p.ox) * p.idx;
  const vfloat16 ny = (vfloat16(node.bounds[nearSide[1]][1][s]) - p.oy) * p.idy;
  const vfloat16 nz = (vfloat16(node.bounds[nearSide[2]][2][s]) - p.oz) * p.idz;
  const vfloat16 fx = (vfloat16(node.bounds[1 - nearSide[0]][0][s]) - p.ox) * p.idx;
  const vfloat16 fy = (vfloat16(node.bounds[1 - nearSide[1]][1][s]) - p.oy) * p.idy;
  const vfloat16 fz = (vfloat16(node.bounds[1 - nearSide[2]][2][s]) - p.oz) * p.idz;
  tNear = maxKeep(nx, maxKeep(ny, maxKeep(nz, p.tmin)));
  const vfloat16 tFar = minKeep(fx, minKeep(fy, minKeep(fz, tmax))) * vfloat16(kRobustFarScale);
  return static_cast<unsigned>((tNear <= tFar).mask());
}

/// Largest tmax over the rays in mask.
PA_AVX512_INLINE float largestTmax(const float* tmax, unsigned rays) {
  return _mm512_mask_reduce_max_ps(static_cast<__mmask16>(rays), _mm512_load_ps(tmax));
}

/// What the watertight test needs of a packet's rays, lane i = ray i: the shear (RayShear per
/// ray; rays of one shear class share kx, ky, kz), and origin and direction in double for the
/// accurate plane distance (two halves of eight rays).
struct PacketShear {
  vfloat16 sx, sy, sz;
  __m512d ox[2], oy[2], oz[2], dx[2], dy[2], dz[2];
  unsigned classRays[6] = {};   ///< Rays of each (kz, swapped) class.
  int axes[6][3] = {};          ///< kx, ky, kz of each class.
};

/// The shear class of a RayShear: its dominant axis and whether kx and ky are swapped.
inline int shearClass(const RayShear& s) { return 2 * s.kz + (s.kx != (s.kz + 1) % 3); }

/// One triangle of a pack against the rays in `rays` (one shear class), one ray per lane:
/// intersectTriangleWatertight's float and double operations in the pack kernel's order (as
/// testPackEdges and planeDistances8 do them for one ray and sixteen triangles), so each
/// ray's distance and barycentrics are bit-identical to its single-ray test. Returns the rays
/// whose line crosses the triangle, with their distance and barycentrics.
template <class Pack>
PA_AVX512_INLINE unsigned triangleOverRays(const Pack& pack, int lane, const int axes[3], const vfloat16 origin[3],
                                           const PacketShear& shear, unsigned rays, vfloat16& t, vfloat16& u,
                                           vfloat16& v) {
  PackEdges<vfloat16> e;
  const unsigned hits =
      testTriangleAgainstRays<Avx512Lanes16>(pack, lane, axes, origin, shear.sx, shear.sy, shear.sz, rays, e);
  if (!hits) return 0;
  const vfloat16 det = e.det, tScaled = e.tScaled;
  const vfloat16 rcp = vfloat16(1.0f) / det;
  // planeHitDistance in double: the triangle's normal once, then each ray's distance.
  const double v0x = pack.v[0][0][lane], v0y = pack.v[0][1][lane], v0z = pack.v[0][2][lane];
  const double e1x = double(pack.v[1][0][lane]) - v0x, e1y = double(pack.v[1][1][lane]) - v0y,
               e1z = double(pack.v[1][2][lane]) - v0z;
  const double e2x = double(pack.v[2][0][lane]) - v0x, e2y = double(pack.v[2][1][lane]) - v0y,
               e2z = double(pack.v[2][2][lane]) - v0z;
  const __m512d nx = _mm512_set1_pd(e1y * e2z - e1z * e2y), ny = _mm512_set1_pd(e1z * e2x - e1x * e2z),
                nz = _mm512_set1_pd(e1x * e2y - e1y * e2x);
  const __m512d px = _mm512_set1_pd(v0x), py = _mm512_set1_pd(v0y), pz = _mm512_set1_pd(v0z);
  const vfloat16 fallback = tScaled * rcp;
  __m256 half[2] = {lowerHalf(fallback.v), upperHalf(fallback.v)};
  for (int h = 0; h < 2; ++h) {
    if (!(hits >> (8 * h) & 0xff)) continue;
    const __m512d denom = _mm512_add_pd(_mm512_add_pd(_mm512_mul_pd(nx, shear.dx[h]), _mm512_mul_pd(ny, shear.dy[h])),
                                        _mm512_mul_pd(nz, shear.dz[h]));
    const __m512d num = _mm512_add_pd(_mm512_add_pd(_mm512_mul_pd(nx, _mm512_sub_pd(px, shear.ox[h])),
                                                    _mm512_mul_pd(ny, _mm512_sub_pd(py, shear.oy[h]))),
                                      _mm512_mul_pd(nz, _mm512_sub_pd(pz, shear.oz[h])));
    const __mmask8 parallel = _mm512_cmp_pd_mask(denom, _mm512_setzero_pd(), _CMP_EQ_OQ);
    half[h] = _mm256_mask_mov_ps(_mm512_cvtpd_ps(_mm512_div_pd(num, denom)), parallel, half[h]);
  }
  t = joinHalves(half[0], half[1]);
  u = e.u * rcp;
  v = e.v * rcp;
  return hits;
}

/// The triangles of a pack whose bounding boxes some ray of the packet may enter before tmaxHi
/// (packetMayEnterBoxes on boxes made from the vertices): a triangle a ray hits within
/// [tmin, tmax] lies in a box the ray enters, so the others are skipped for the whole packet.
template <class Pack>
PA_AVX512_INLINE unsigned trianglesPacketMayHit(const Pack& pack, const PacketBounds& b, const int nearSide[3],
                                                float tmaxHi) {
  vfloat16 lo[3], hi[3];
  for (int axis = 0; axis < 3; ++axis) {
    const vfloat16 v0 = Avx512Lanes16::loadVertex(pack, 0, axis), v1 = Avx512Lanes16::loadVertex(pack, 1, axis),
                   v2 = Avx512Lanes16::loadVertex(pack, 2, axis);
    lo[axis] = minKeep(v0, minKeep(v1, v2));
    hi[axis] = maxKeep(v0, maxKeep(v1, v2));
  }
  return packetMayEnterBoxes(lo, hi, b, nearSide, tmaxHi);
}

/// A leaf's triangles against the rays in `rays` (one shear class), triangle by triangle in
/// the order the single-ray kernel accepts them (pack by pack, lane by lane): a ray takes a hit
/// within [tmin, its current tmax] that its filter accepts (alpha-masked triangles only).
/// Returns the rays that took a hit; their tmax (vector and array) and hits are updated.
template <class Pack>
PA_AVX512_INLINE unsigned packOverRays(const Pack& pack, const PacketBounds& bounds, const int nearSide[3],
                                       const int axes[3], const vfloat16 origin[3], const PacketShear& shear,
                                       vfloat16 tmin, unsigned rays, vfloat16& tmax, Hit* hits,
                                       const HitFilter* filters, uint32_t instanceId) {
  unsigned found = 0;
  const float tmaxHi = _mm512_mask_reduce_max_ps(static_cast<__mmask16>(rays), tmax.v);
  const unsigned candidates = pack.validBits & trianglesPacketMayHit(pack, bounds, nearSide, tmaxHi);
  for (unsigned triangles = candidates; triangles; triangles &= triangles - 1) {
    const int lane = std::countr_zero(triangles);
    vfloat16 t, u, v;
    unsigned accepted = triangleOverRays(pack, lane, axes, origin, shear, rays, t, u, v);
    if (!accepted) continue;
    accepted &= static_cast<unsigned>(((t >= tmin) & (t <= tmax)).mask());
    if (!accepted) continue;
    alignas(64) float ts[16], us[16], vs[16];
    t.store(ts);
    u.store(us);
    v.store(vs);
    if (pack.maskedBits >> lane & 1) {
      for (unsigned r = accepted; r; r &= r - 1) {
        const int ray = std::countr_zero(r);
        if (!filters[ray](instanceId, pack.prim[lane], us[ray], vs[ray])) accepted &= ~(1u << ray);
      }
    }
    for (unsigned r = accepted; r; r &= r - 1) {
      const int ray = std::countr_zero(r);
      hits[ray] = {ts[ray], us[ray], vs[ray], pack.prim[lane], instanceId};
    }
    tmax = select(accepted, tmax, t);
    found |= accepted;
  }
  return found;
}

/// Closest hits of the rays in `rays` (all in one octant, finite inverse directions): one
/// traversal for the packet. A node's children are culled for the whole packet by interval
/// arithmetic, then each remaining child is tested against every ray at once (the single-ray
/// slab test, lane per ray); children are entered in the octant's order with the rays that
/// entered them, and a leaf's triangles are tested ray by ray with the single-ray pack test.
/// Per ray, hit distances are therefore the single-ray kernel's; only the order in which leaves
/// are visited differs (which of two hits at exactly the same distance is kept).
PA_AVX512 unsigned traversePacket(const Wide16Bvh& bvh, Ray* rays, Hit* hits, unsigned rays16,
                                  const HitFilter* filters, uint32_t instanceId) {
  using Lanes = Avx512Lanes16;
  const int first = std::countr_zero(rays16);
  const int nearSide[3] = {std::signbit(rays[first].dir.x), std::signbit(rays[first].dir.y),
                           std::signbit(rays[first].dir.z)};
  const int orderShift = 4 * (nearSide[0] | nearSide[1] << 1 | nearSide[2] << 2);
  // The rays as structure of arrays (idle lanes repeat a real ray, with tmax -inf).
  alignas(64) float soa[8][16];
  for (int lane = 0; lane < 16; ++lane) {
    const bool live = rays16 >> lane & 1;
    const Ray& ray = rays[live ? lane : first];
    soa[0][lane] = ray.origin.x, soa[1][lane] = ray.origin.y, soa[2][lane] = ray.origin.z;
    soa[3][lane] = ray.dir.x, soa[4][lane] = ray.dir.y, soa[5][lane] = ray.dir.z;
    soa[6][lane] = ray.tmin;
    soa[7][lane] = live ? ray.tmax : -std::numeric_limits<float>::infinity();
  }
  PacketRays packet;
  packet.ox = vfloat16::load(soa[0]), packet.oy = vfloat16::load(soa[1]), packet.oz = vfloat16::load(soa[2]);
  const vfloat16 dx = vfloat16::load(soa[3]), dy = vfloat16::load(soa[4]), dz = vfloat16::load(soa[5]);
  packet.idx = vfloat16(1.0f) / dx, packet.idy = vfloat16(1.0f) / dy, packet.idz = vfloat16(1.0f) / dz;
  packet.tmin = vfloat16::load(soa[6]);
  std::copy_n(soa[7], 16, packet.tmax);
  const __mmask16 live = static_cast<__mmask16>(rays16);
  PacketBounds bounds;
  const vfloat16 origins[3] = {packet.ox, packet.oy, packet.oz}, inverses[3] = {packet.idx, packet.idy, packet.idz};
  for (int axis = 0; axis < 3; ++axis) {
    bounds.oLo[axis] = _mm512_mask_reduce_min_ps(live, origins[axis].v);
    bounds.oHi[axis] = _mm512_mask_reduce_max_ps(live, origins[axis].v);
    bounds.iLo[axis] = _mm512_mask_reduce_min_ps(live, inverses[axis].v);
    bounds.iHi[axis] = _mm512_mask_reduce_max_ps(live, inverses[axis].v);
  }
  bounds.tminLo = _mm512_mask_reduce_min_ps(live, packet.tmin.v);
  // RayShear of every ray at once (the same comparisons and divisions, lane by lane).
  PacketShear shear;
  {
    const vfloat16 ax = _mm512_abs_ps(dx.v), ay = _mm512_abs_ps(dy.v), az = _mm512_abs_ps(dz.v);
    const unsigned xy = (ax > ay).mask(), xz = (ax > az).mask(), yz = (ay > az).mask();
    const unsigned kz0 = xy & xz, kz1 = ~xy & yz, kz2 = ~(kz0 | kz1);
    const vfloat16 dkz = select(kz1, select(kz0, dz, dx), dy);
    const vfloat16 kxPlain = select(kz1, select(kz0, dx, dy), dz);   // (kz + 1) % 3
    const vfloat16 kyPlain = select(kz1, select(kz0, dy, dz), dx);   // (kz + 2) % 3
    const unsigned swapped = (dkz < vfloat16(0.0f)).mask();
    shear.sx = select(swapped, kxPlain, kyPlain) / dkz;
    shear.sy = select(swapped, kyPlain, kxPlain) / dkz;
    shear.sz = vfloat16(1.0f) / dkz;
    const unsigned byAxis[3] = {kz0, kz1, kz2};
    for (int kz = 0; kz < 3; ++kz) {
      shear.classRays[2 * kz] = rays16 & byAxis[kz] & ~swapped;
      shear.classRays[2 * kz + 1] = rays16 & byAxis[kz] & swapped;
      shear.axes[2 * kz][0] = (kz + 1) % 3, shear.axes[2 * kz][1] = (kz + 2) % 3, shear.axes[2 * kz][2] = kz;
      shear.axes[2 * kz + 1][0] = (kz + 2) % 3, shear.axes[2 * kz + 1][1] = (kz + 1) % 3, shear.axes[2 * kz + 1][2] = kz;
    }
    const vfloat16 d[3] = {dx, dy, dz};
    __m512d* origin[3] = {shear.ox, shear.oy, shear.oz};
    __m512d* direction[3] = {shear.dx, shear.dy, shear.dz};
    for (int axis = 0; axis < 3; ++axis) {
      origin[axis][0] = _mm512_cvtps_pd(lowerHalf(origins[axis].v));
      origin[axis][1] = _mm512_cvtps_pd(upperHalf(origins[axis].v));
      direction[axis][0] = _mm512_cvtps_pd(lowerHalf(d[axis].v));
      direction[axis][1] = _mm512_cvtps_pd(upperHalf(d[axis].v));
    }
  }

  PacketEntry<kWide16Width> stack[kPacketStackSize];
  int top = 0;
  uint32_t current = 0;
  unsigned currentRays = rays16;
  unsigned found = 0;
  vfloat16 tmax = vfloat16::load(packet.tmax);
  for (;;) {
    if (!(current & kLeafBit)) {
      const Wide16Node& node = bvh.nodes[current];
      const unsigned candidates = packetChildren(node, bounds, nearSide, largestTmax(packet.tmax, currentRays));
      if (candidates) {
        // Candidate slots in visiting order, farthest first (Wide16Node::order for the octant).
        const __m512i order = _mm512_and_si512(
            _mm512_srl_epi32(_mm512_load_si512(node.order), _mm_cvtsi32_si128(orderShift)), _mm512_set1_epi32(15));
        unsigned ordered = _mm512_movepi32_mask(
            _mm512_permutexvar_epi32(order, _mm512_movm_epi32(static_cast<__mmask16>(candidates))));
        bool haveNext = false;
        uint32_t nextRef = 0;
        unsigned nextRays = 0;
        vfloat16 nextNear;
        for (; ordered; ordered &= ordered - 1) {
          const int slot = (node.order[std::countr_zero(ordered)] >> orderShift) & 15;
          vfloat16 tNear;
          const unsigned entered = raysEnteringChild(node, slot, packet, tmax, nearSide, tNear) & currentRays;
          if (!entered) continue;
          if (haveNext) {   // the previous one is farther: deferred
            PacketEntry<kWide16Width>& e = stack[top++];
            nextNear.store(e.tNear);
            e.ref = nextRef;
            e.rays = nextRays;
          }
          haveNext = true;
          nextRef = node.child[slot];
          nextRays = entered;
          nextNear = tNear;
        }
        if (haveNext) {
          current = nextRef;
          currentRays = nextRays;
          continue;
        }
      }
    } else {
      const vfloat16 origin[3] = {packet.ox, packet.oy, packet.oz};
      for (int c = 0; c < 6; ++c) {
        const unsigned classRays = currentRays & shear.classRays[c];
        if (!classRays) continue;
        if (std::popcount(classRays) <= kRayByRayLeaf) {   // few rays: each tests 16 triangles at once
          tmax.store(packet.tmax);
          for (unsigned r = classRays; r; r &= r - 1) {
            const int lane = std::countr_zero(r);
            if (testLeaf<Lanes, false>(bvh, current, TriangleRay<Lanes>(rays[lane]), rays[lane], packet.tmax[lane],
                                       hits[lane], filters[lane], instanceId))
              found |= 1u << lane;
          }
          tmax = vfloat16::load(packet.tmax);
          continue;
        }
        if (current & kSmallLeafBit) {
          found |= packOverRays(bvh.smallPacks[current & kFirstPackMask], bounds, nearSide, shear.axes[c], origin,
                                shear, packet.tmin, classRays, tmax, hits, filters, instanceId);
        } else {
          uint32_t firstPack, packCount;
          leafPacks(current, firstPack, packCount);
          for (uint32_t k = firstPack; k < firstPack + packCount; ++k)
            found |= packOverRays(bvh.packs[k], bounds, nearSide, shear.axes[c], origin, shear, packet.tmin,
                                  classRays, tmax, hits, filters, instanceId);
        }
      }
      tmax.store(packet.tmax);
    }
    if (!popLivePacketEntry(stack, top, tmax, current, currentRays)) {
      for (unsigned r = found; r; r &= r - 1) rays[std::countr_zero(r)].tmax = packet.tmax[std::countr_zero(r)];
      return found;
    }
  }
}

/// True when every inverse direction component of the ray is finite (the packet's interval
/// bounds need that; rays along an axis plane take the single-ray kernel).
bool finiteInverseDirection(const Ray& ray) {
  return ray.dir.x != 0.0f && ray.dir.y != 0.0f && ray.dir.z != 0.0f && std::isfinite(1.0f / ray.dir.x) &&
         std::isfinite(1.0f / ray.dir.y) && std::isfinite(1.0f / ray.dir.z);
}

}  // namespace

PA_AVX512 unsigned intersectWide16Packet(const Wide16Bvh& bvh, Ray* rays, Hit* hits, unsigned active,
                                         const HitFilter* filters, uint32_t instanceId) {
  if (bvh.empty()) return 0;
  unsigned found = 0;
  unsigned byOctant[8] = {};
  for (unsigned r = active; r; r &= r - 1) {
    const int lane = std::countr_zero(r);
    const Ray& ray = rays[lane];
    if (!finiteInverseDirection(ray)) {
      if (traverse<Avx512Lanes16, false>(bvh, ray, rays[lane].tmax, hits[lane], filters[lane], instanceId))
        found |= 1u << lane;
      continue;
    }
    byOctant[std::signbit(ray.dir.x) | std::signbit(ray.dir.y) << 1 | std::signbit(ray.dir.z) << 2] |= 1u << lane;
  }
  for (unsigned octantRays : byOctant) {
    if (std::popcount(octantRays) == 1) {
      const int lane = std::countr_zero(octantRays);
      if (traverse<Avx512Lanes16, false>(bvh, rays[lane], rays[lane].tmax, hits[lane], filters[lane], instanceId))
        found |= 1u << lane;
    } else if (octantRays) {
      found |= traversePacket(bvh, rays, hits, octantRays, filters, instanceId);
    }
  }
  return found;
}

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
unsigned intersectWide16Packet(const Wide16Bvh&, Ray*, Hit*, unsigned, const HitFilter*, uint32_t) { return 0; }
}  // namespace pa::bvh_detail

#endif  // __AVX2__
