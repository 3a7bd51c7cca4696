#pragma once
// The wide BVH traversal, written once over lane traits L (one traversal loop for the 8-wide
// AVX2 / SSE, 8-wide AVX-512 and 16-wide AVX-512 kernels) and over the kind of query (closest
// hit or any hit). The loop tests one ray against all N children of a node (the conservative
// slab test of slab_test.h), goes on with one entered child and pushes the others, and tests a
// leaf's triangles N at a time with the watertight test of watertight.h: the same float and
// double operations in the same order as the scalar reference, so hit distances are
// bit-identical to it in every kernel (any-hit rays skip the double operations for the lanes an
// error bound decides, with the same answers: shearedDistanceBound).
//
// L supplies the per-ISA pieces:
//   Float, Node, Bvh, kWidth         lane type (N floats, comparisons -> .mask()), node, tree
//   PlaneRay                         per-ray constants of L::planeDistances
//   pushChildren<kWithDistance>      push the children in a lane mask (lane order)
//   kOctantOrder                     true: closest-hit rays take entered children in the node's
//                                    per-octant order (enterInOctantOrder); false: the nearest
//                                    first (nearestLane), the rest pushed by pushFarther
//   loadVertex, redoEdgesInDouble    pieces of the triangle pack test
//   kLaneByLaneHits                  true: accurate distances and acceptance lane by lane
//                                    (acceptLaneByLane); false: distances of all lanes in SIMD
//                                    (planeDistances), then acceptPackHits
//   kSmallLeaves                     leaves may be one 8-wide pack in bvh.smallPacks
// The packet traversal (wide_packet_loop.h) runs over the same traits.
//
// Include this header once per kernel file, after the other headers, with PA_BVH_KERNEL
// defined as the file's target attribute (empty for the build's ISA): the templates below take
// it, and every L is local to its file, so no instantiation is shared between ISAs.
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

#include "renderer/bvh/slab_test.h"
#include "renderer/bvh/watertight.h"
#include "renderer/bvh/wide16_bvh.h"
#include "renderer/bvh/wide_bvh.h"
#include "renderer/bvh/wide_traversal_stack.h"

#if !defined(PA_BVH_KERNEL)
#error "define PA_BVH_KERNEL (the kernel's target attribute) before including wide_traversal_loop.h"
#endif
/// The kernel's target attribute on a function that always inlines into its caller.
#define PA_BVH_INLINE [[gnu::always_inline]] PA_BVH_KERNEL inline

namespace pa::bvh_detail {

/// A bound on how far the watertight test's own distance of a hit, t = tScaled / det in float
/// (intersectTriangleWatertight's tSheared), lies from planeHitDistance's: |t - tPlane| <= the
/// result, or the result is +inf or NaN where no bound holds. From |1 / det|, the largest |x|,
/// |y| of the three sheared vertices (maxXY = M), their largest |z| before the scale sz
/// (maxZ = Z), and |sz|. Forward error analysis of each rounding (as PBRT 4th ed., 6.8.7) with
/// the edge functions of one sign on a hit, so |t| <= |sz| Z: each sheared x, y off by
/// u (2M + 3Z) (u = 2^-24), each edge function by 12 u M (M + Z), tScaled and det accordingly;
/// plus the ray the rounded shear constants stand for (the line drifts by |t| u across a plane
/// whose slope is below 16 M Z / |det|); plus planeHitDistance's own rounding in double and the
/// float rounding of either distance. With P = M (M + Z) / |det|, about |sz| Z u (88 P + 10),
/// doubled: u (|sz| Z (192 P + 32) + 2^-20 |sz| M (1 + 16 P)), where 2048 u P < 1 (the edge
/// functions' error then stays below 2% of det); +inf beyond. A kernel decides a lane from t
/// alone where t +- the bound lies wholly inside or wholly outside its [tmin, tmax]: the
/// accurate distance would decide the same (distance_bound_test.cpp).
template <class Float>
PA_BVH_INLINE Float shearedDistanceBound(Float absRcp, Float maxXY, Float maxZ, Float absSz) {
  constexpr float kUnit = 0x1p-24f;
  const Float conditioning = maxXY * (maxXY + maxZ) * absRcp;   // P
  const Float bound = Float(kUnit) * absSz *
                          (maxZ * (Float(192.0f) * conditioning + Float(32.0f)) +
                           Float(0x1p-20f) * maxXY * (Float(1.0f) + Float(16.0f) * conditioning)) +
                      Float(1e-30f);
  // (P - limit) x inf: +inf where 2048 u P > 1, -inf below; the bound plus the larger of it and
  // 0, so that a NaN in either stays NaN (a lane it cannot decide).
  const Float beyond =
      (conditioning - Float(1.0f / (2048.0f * kUnit))) * Float(std::numeric_limits<float>::infinity());
  return bound + maxKeep(Float(0.0f), beyond);
}

/// Per-ray constants of the slab test of N children.
template <class L>
struct BoxRay {
  using Float = typename L::Float;
  Float ox, oy, oz, idx, idy, idz, tmin;
  /// The reciprocals times kRobustFarScale (rounded), for the far planes: the scale taken before
  /// the slab's rounded operations instead of after them (testChildren). Scalars, broadcast where
  /// used: three more registers held through the loop made the leaf test spill.
  float fdx, fdy, fdz;
  int nearX, nearY, nearZ;
  int orderShift;   ///< 4 x the ray's octant: where its slot order sits in Wide16Node::order.

  PA_BVH_KERNEL explicit BoxRay(const Ray& ray)
      : ox(ray.origin.x), oy(ray.origin.y), oz(ray.origin.z), idx(1.0f / ray.dir.x), idy(1.0f / ray.dir.y),
        idz(1.0f / ray.dir.z), tmin(ray.tmin), fdx((1.0f / ray.dir.x) * kRobustFarScale),
        fdy((1.0f / ray.dir.y) * kRobustFarScale), fdz((1.0f / ray.dir.z) * kRobustFarScale),
        nearX(std::signbit(ray.dir.x)), nearY(std::signbit(ray.dir.y)), nearZ(std::signbit(ray.dir.z)),
        orderShift(4 * (nearX | nearY << 1 | nearZ << 2)) {}
};

/// Entry distances of the node's children (tNear) and the mask of those the ray enters before
/// tmax, given as farTmax = tmax x kRobustFarScale (as slabEntry widens it): slabEntry of
/// slab_test.h, lane for lane, but for where the far planes' scale is taken: (bound - origin) x
/// (reciprocal x scale) rounds four times, as ((bound - origin) x reciprocal) x scale does, so it
/// lies as far above the exact distance (a box the ray touches is never missed: Ize's bound,
/// kRobustFarScale), and one multiplication less waits between the node's bounds and the child
/// to enter.
template <class L, class Node>
PA_BVH_INLINE unsigned testChildren(const BoxRay<L>& r, const Node& node, float farTmax,
                                    typename L::Float& tNear) {
  using Float = typename L::Float;
  const Float nx = (Float::load(node.bounds[r.nearX][0]) - r.ox) * r.idx;
  const Float ny = (Float::load(node.bounds[r.nearY][1]) - r.oy) * r.idy;
  const Float nz = (Float::load(node.bounds[r.nearZ][2]) - r.oz) * r.idz;
  const Float fx = (Float::load(node.bounds[1 - r.nearX][0]) - r.ox) * Float(r.fdx);
  const Float fy = (Float::load(node.bounds[1 - r.nearY][1]) - r.oy) * Float(r.fdy);
  const Float fz = (Float::load(node.bounds[1 - r.nearZ][2]) - r.oz) * Float(r.fdz);
  tNear = maxKeep(nx, maxKeep(ny, maxKeep(nz, r.tmin)));
  const Float tFar = minKeep(fx, minKeep(fy, minKeep(fz, Float(farTmax))));
  return static_cast<unsigned>((tNear <= tFar).mask());
}

/// Per-ray constants of the watertight pack test, of the face culling of one-sided triangles
/// and of the accurate plane distance.
template <class L>
struct TriangleRay {
  using Float = typename L::Float;
  RayShear shear;
  Float ox, oy, oz, sx, sy, sz;
  Float absSz;  ///< |sz|, for shearedDistanceBound.
  Float cull;   ///< cullSign(HitFilter::cull): one-sided lanes with det x cull < 0 are skipped.
  bool cullsAFace;   ///< HitFilter::cull is not None (shadow rays skip the cull's operations).
  typename L::PlaneRay plane;

  PA_BVH_KERNEL TriangleRay(const Ray& ray, FaceCull faceCull)
      : shear(ray.dir), ox(ray.origin[shear.kx]), oy(ray.origin[shear.ky]), oz(ray.origin[shear.kz]),
        sx(shear.sx), sy(shear.sy), sz(shear.sz), absSz(std::fabs(shear.sz)), cull(cullSign(faceCull)),
        cullsAFace(faceCull != FaceCull::None), plane(ray) {}
};

/// The lanes of `lanes` to keep after face culling: one-sided lanes (oneSidedBits) whose det
/// (crossedEdges' det: > 0 on the front face) times cull is negative are dropped. Costs a
/// multiply and a compare on values the watertight test already has.
template <class Float>
PA_BVH_INLINE unsigned afterFaceCull(unsigned lanes, unsigned oneSidedBits, Float det, Float cull) {
  return lanes & ~(oneSidedBits & static_cast<unsigned>((det * cull < Float(0.0f)).mask()));
}

/// Final lane results of one pack test.
template <uint32_t kWidth>
struct PackCandidates {
  alignas(4 * kWidth) float t[kWidth];   ///< Accurate (plane) hit distance.
  alignas(4 * kWidth) float u[kWidth];
  alignas(4 * kWidth) float v[kWidth];
};

/// What a pack's hit distances and barycentrics are computed from, per lane.
template <class Float>
struct PackEdges {
  Float tScaled;   ///< Sheared-space distance times det (tScaled / det: the fallback distance).
  Float det;       ///< Sum of the edge functions.
  Float u, v;      ///< Barycentrics of vertices 1 and 2, times det.
  Float maxXY;     ///< Largest |x|, |y| of the three sheared vertices (shearedDistanceBound).
  Float maxZ;      ///< Largest |z| of the three vertices relative to the origin, before sz.
};

/// The watertight edge test (intersectTriangleWatertight's float operations, lane for lane) up
/// to the distance. x, y, z: the three vertices' coordinates on the ray's shear axes kx, ky, kz;
/// origin: the ray origin on the same axes; sx, sy, sz: the shear. Returns the lanes of `lanes`
/// whose triangle the ray's line passes through (any t), with what their distances and
/// barycentrics are computed from in out. Used with a pack's triangles against one ray
/// (testPackEdges) and with one triangle against a packet's rays (testTriangleAgainstRays).
template <class L>
PA_BVH_INLINE unsigned crossedEdges(const typename L::Float (&x)[3], const typename L::Float (&y)[3],
                                    const typename L::Float (&z)[3], const typename L::Float (&origin)[3],
                                    typename L::Float sx, typename L::Float sy, typename L::Float sz,
                                    unsigned lanes, PackEdges<typename L::Float>& out) {
  using Float = typename L::Float;
  const Float az = z[0] - origin[2];
  const Float bz = z[1] - origin[2];
  const Float cz = z[2] - origin[2];
  const Float ax = (x[0] - origin[0]) - sx * az;
  const Float ay = (y[0] - origin[1]) - sy * az;
  const Float bx = (x[1] - origin[0]) - sx * bz;
  const Float by = (y[1] - origin[1]) - sy * bz;
  const Float cx = (x[2] - origin[0]) - sx * cz;
  const Float cy = (y[2] - origin[1]) - sy * cz;
  Float u = cx * by - cy * bx;
  Float v = ax * cy - ay * cx;
  Float w = bx * ay - by * ax;
  const Float zero(0.0f);
  // Exact zero in float: these lanes are decided with the edge functions in double.
  if (const unsigned onEdge = static_cast<unsigned>(((u == zero) | (v == zero) | (w == zero)).mask()) & lanes)
    L::redoEdgesInDouble(onEdge, ax, ay, bx, by, cx, cy, u, v, w);
  const unsigned negative = static_cast<unsigned>(((u < zero) | (v < zero) | (w < zero)).mask());
  const unsigned positive = static_cast<unsigned>(((u > zero) | (v > zero) | (w > zero)).mask());
  unsigned hits = lanes & ~(negative & positive);
  if (!hits) return 0;
  const Float det = u + v + w;
  hits &= static_cast<unsigned>((det != zero).mask());
  if (!hits) return 0;
  // No range test here: the sheared distance is inaccurate on slivers; the callers test it with
  // its error bound, and the plane distance where that cannot decide.
  out.tScaled = (u * (sz * az) + v * (sz * bz)) + w * (sz * cz);
  out.det = det;
  out.u = v;
  out.v = w;
  // Dead code where the caller does not read them (closest-hit rays, the packets).
  out.maxXY = maxKeep(maxKeep(maxKeep(abs(ax), abs(ay)), maxKeep(abs(bx), abs(by))), maxKeep(abs(cx), abs(cy)));
  out.maxZ = maxKeep(maxKeep(abs(az), abs(bz)), abs(cz));
  return hits;
}

/// Watertight test of a pack's triangles against one ray (crossedEdges, lane = triangle): the
/// valid lanes whose triangle the ray's line passes through.
template <class L, class Pack>
PA_BVH_INLINE unsigned testPackEdges(const Pack& pack, const TriangleRay<L>& r, PackEdges<typename L::Float>& out) {
  using Float = typename L::Float;
  const int kx = r.shear.kx, ky = r.shear.ky, kz = r.shear.kz;
  const Float x[3] = {L::loadVertex(pack, 0, kx), L::loadVertex(pack, 1, kx), L::loadVertex(pack, 2, kx)};
  const Float y[3] = {L::loadVertex(pack, 0, ky), L::loadVertex(pack, 1, ky), L::loadVertex(pack, 2, ky)};
  const Float z[3] = {L::loadVertex(pack, 0, kz), L::loadVertex(pack, 1, kz), L::loadVertex(pack, 2, kz)};
  const Float origin[3] = {r.ox, r.oy, r.oz};
  return crossedEdges<L>(x, y, z, origin, r.sx, r.sy, r.sz, pack.validBits, out);
}

/// Tests one pack's triangles against [ray.tmin, tmax] and accepts its hits in lane order (as
/// acceptPackHits), one-sided lanes seen from the face the ray culls skipped first: the accurate
/// distances of all candidate lanes in SIMD, or lane by lane where L::kLaneByLaneHits
/// (L::acceptLaneByLane). Any hit with kDecideByBound: the lanes the sheared distance's error
/// bound decides first (shearedDistanceBound); the packets' leaves keep the accurate distances.
template <class L, bool kAnyHit, bool kDecideByBound, class Pack>
PA_BVH_INLINE bool testPackHits(const Pack& pack, const TriangleRay<L>& triRay, const Ray& ray, float& tmax, Hit& hit,
                                const HitFilter& filter, uint32_t instanceId) {
  using Float = typename L::Float;
  PackEdges<Float> e;
  unsigned lanes = testPackEdges<L>(pack, triRay, e);
  if (!lanes) return false;
  if (triRay.cullsAFace) {
    lanes = afterFaceCull(lanes, pack.oneSidedBits, e.det, triRay.cull);
    if (!lanes) return false;
  }
  const Float rcp = Float(1.0f) / e.det;
  const Float tSheared = e.tScaled * rcp;
  if constexpr (kAnyHit && kDecideByBound) {
    // Any hit: lanes whose sheared distance, give or take its error bound, lies wholly outside
    // [tmin, tmax] are dropped, and one that lies wholly inside (and needs no filter call) is
    // taken at once; the accurate distance in double would decide them the same. (Closest-hit
    // rays need the accurate distance of each hit they take, and most lanes in range are.)
    const Float bound = shearedDistanceBound(abs(rcp), e.maxXY, e.maxZ, triRay.absSz);
    const Float tmin(ray.tmin), tmaxLanes(tmax);
    lanes &= ~static_cast<unsigned>(((tSheared + bound < tmin) | (tSheared - bound > tmaxLanes)).mask());
    if (!lanes) return false;
    if (lanes & ~pack.maskedBits &
        static_cast<unsigned>(((tSheared - bound >= tmin) & (tSheared + bound <= tmaxLanes)).mask()))
      return true;
  }
  if constexpr (L::kLaneByLaneHits) {
    return L::template acceptLaneByLane<kAnyHit>(pack, lanes, e, triRay.plane, ray.tmin, tmax, hit, filter,
                                                 instanceId);
  } else {
    const Float t = L::planeDistances(pack, triRay.plane, tSheared, lanes);
    lanes &= static_cast<unsigned>(((t >= Float(ray.tmin)) & (t <= Float(tmax))).mask());
    if (!lanes) return false;
    PackCandidates<L::kWidth> c;
    t.store(c.t);
    (e.u * rcp).store(c.u);
    (e.v * rcp).store(c.v);
    return acceptPackHits<kAnyHit>(pack, lanes, c.t, c.u, c.v, tmax, hit, filter, instanceId);
  }
}

/// Tests a leaf's triangles against [ray.tmin, tmax], pack by pack in lane order: closest hit
/// (kAnyHit false) shortens tmax and writes hit for every accepted hit and returns whether any
/// was; any hit returns true at the first accepted one.
template <class L, bool kAnyHit, bool kDecideByBound = true>
PA_BVH_INLINE bool testLeaf(const typename L::Bvh& bvh, uint32_t ref,
                            const TriangleRay<L>& triRay, const Ray& ray, float& tmax,
                            Hit& hit, const HitFilter& filter, uint32_t instanceId) {
  if constexpr (L::kSmallLeaves) {
    if (ref & kSmallLeafBit)
      return testPackHits<L, kAnyHit, kDecideByBound>(bvh.smallPacks[ref & kFirstPackMask], triRay, ray, tmax,
                                                      hit, filter, instanceId);
  }
  uint32_t first, count;
  leafPacks(ref, first, count);
  bool found = false;
  for (uint32_t p = first; p < first + count; ++p) {
    if (testPackHits<L, kAnyHit, kDecideByBound>(bvh.packs[p], triRay, ray, tmax, hit, filter, instanceId)) {
      if constexpr (kAnyHit) return true;
      found = true;
    }
  }
  return found;
}

/// Closest hit: of the two or more children in mask, returns the one to visit next and pushes
/// the others with their entry distances, the nearer ones popped first where the kernel can.
template <class L>
PA_BVH_INLINE uint32_t enterNearest(const typename L::Node& node, unsigned mask,
                                    typename L::Float tNear, const BoxRay<L>& boxRay,
                                    TraversalStack<true, L::kWidth>& stack) {
  if constexpr (L::kOctantOrder) {
    return L::enterInOctantOrder(node, mask, tNear, boxRay.orderShift, stack);
  } else {
    const unsigned afterFirst = mask & (mask - 1);
    if ((afterFirst & (afterFirst - 1)) == 0) {   // exactly two children
      alignas(4 * L::kWidth) float entry[L::kWidth];
      tNear.store(entry);
      return takeNearerOfTwo(node, mask, entry, stack);
    }
    const int nearest = L::nearestLane(mask, tNear);
    const uint32_t next = node.child[nearest];
    L::pushFarther(node, mask & ~(1u << nearest), tNear, stack);
    return next;
  }
}

/// The traversal loop. Closest hit (kAnyHit false): nearest entered child first, the others
/// pushed with their entry distances and culled when popped behind a nearer hit; tmax shrinks
/// to each accepted hit (written to hit) and the result says whether there was one. Any hit:
/// children in slot order, true at the first accepted hit (tmax and hit stay as they are).
template <class L, bool kAnyHit>
PA_BVH_INLINE bool traverse(const typename L::Bvh& bvh, const Ray& ray, float& tmax,
                            Hit& hit, const HitFilter& filter, uint32_t instanceId) {
  if (bvh.empty()) return false;
  const BoxRay<L> boxRay(ray);
  const TriangleRay<L> triRay(ray, filter.cull);
  TraversalStack<!kAnyHit, L::kWidth> stack;
  uint32_t current = 0;
  bool found = false;
  float farTmax = tmax * kRobustFarScale;   // testChildren's far limit
  for (;;) {
    if (!(current & kLeafBit)) {
      const typename L::Node& node = bvh.nodes[current];
      typename L::Float tNear;
      const unsigned mask = testChildren(boxRay, node, farTmax, tNear);
      if (mask != 0) {
        const unsigned rest = mask & (mask - 1);
        if constexpr (kAnyHit) {
          current = node.child[std::countr_zero(mask)];
          if (rest) L::pushChildren(node, rest, tNear, stack);
        } else if (rest == 0) {   // exactly one child
          current = node.child[std::countr_zero(mask)];
        } else {
          current = enterNearest<L>(node, mask, tNear, boxRay, stack);
        }
        continue;
      }
    } else if (testLeaf<L, kAnyHit>(bvh, current, triRay, ray, tmax, hit, filter, instanceId)) {
      if constexpr (kAnyHit) return true;
      found = true;
      farTmax = tmax * kRobustFarScale;
    }
    if constexpr (kAnyHit) {
      if (stack.top == 0) return false;
      current = stack.node[--stack.top];
    } else if (!popEntryWithin(stack, farTmax, current)) {   // the next that may hold a nearer hit
      return found;
    }
  }
}

}  // namespace pa::bvh_detail
