#pragma once
// The packet traversal of coherent rays (camera rays of a pixel block), written once over the
// lane traits of wide_traversal_loop.h: one packet of up to L::kWidth rays of one octant, one
// ray per lane, traverses the tree together. A node's children are culled for the whole packet
// by interval arithmetic and entered with the packet's live rays (a deferred child drops the
// rays whose hit is nearer than its box when popped); a leaf's triangles are culled by their
// boxes for the packet, then each triangle is tested against all of its rays at once with the
// single-ray watertight arithmetic. Per ray, hit distances are
// therefore the single-ray kernel's; only the order in which leaves are visited differs (which
// of two hits at exactly the same distance is kept). The same loop answers any-hit queries
// (shadow rays of a pixel block toward one light): a ray leaves the packet at its first accepted
// hit, and the traversal ends when every ray has one; per ray the single-ray kernel's answer.
// Any-hit packets whose rays part widely (kPerRayChildSpread) also test each child the interval
// lets through against each ray, and enter it with the rays that enter it.
//
// L supplies, beyond what the single-ray loop needs (or what its SingleRayLanes need, where it
// names lanes of its own for leaves tested ray by ray):
//   loadRays                         PacketRays of rays[i] in lane i for the lanes given, the
//                                    first of them in every other lane
//   Float ops                        abs, select(bits, a, b), minOverLanes, maxOverLanes
//   Float8                           eight lanes: the 8-wide nodes' and packs' boxes are culled
//                                    for the packet in it (Float, one ray per lane, may be wider)
//   PacketPlane, planeDistancesOverRays   the accurate plane distance of one triangle for all
//                                    rays of a packet
//   kOctantOrder: octantOrder, octantSlot   children in the node's per-octant order (else the
//                                    nearest first, by the nearest ray's entry distance)
//
// Include after wide_traversal_loop.h, in a kernel file (PA_BVH_KERNEL defined).
#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <type_traits>

#if !defined(PA_BVH_INLINE)
#error "include wide_traversal_loop.h before wide_packet_loop.h"
#endif

namespace pa::bvh_detail {

/// Interval bounds of a packet whose rays share one octant (all inverse directions finite):
/// origins and inverse directions per axis over the packet's rays, and their smallest tmin.
struct PacketBounds {
  float oLo[3], oHi[3], iLo[3], iHi[3], tminLo;
};

/// The boxes (lower and upper bounds per axis, one box per lane) that some ray of the packet may
/// enter before tmaxHi: each ray's slab distances (bound - origin) * inverse bounded over the
/// intervals' corners. Rounding is monotonic, so the bounds hold for the rounded per-ray values
/// and the test is a superset of the union of the rays' own slab tests.
template <class Float>
PA_BVH_INLINE unsigned packetMayEnterBoxes(const Float lo[3], const Float hi[3], const PacketBounds& b,
                                           const int nearSide[3], float tmaxHi, Float* entry = nullptr) {
  Float tNear(b.tminLo), tFar(tmaxHi);
  for (int axis = 0; axis < 3; ++axis) {
    const Float iLo(b.iLo[axis]), iHi(b.iHi[axis]);
    const Float nearBound = nearSide[axis] ? hi[axis] : lo[axis];
    const Float farBound = nearSide[axis] ? lo[axis] : hi[axis];
    const Float n0 = nearBound - Float(b.oHi[axis]), n1 = nearBound - Float(b.oLo[axis]);
    const Float f0 = farBound - Float(b.oHi[axis]), f1 = farBound - Float(b.oLo[axis]);
    tNear = maxKeep(tNear, minKeep(minKeep(n0 * iLo, n0 * iHi), minKeep(n1 * iLo, n1 * iHi)));
    tFar = minKeep(tFar, maxKeep(maxKeep(f0 * iLo, f0 * iHi), maxKeep(f1 * iLo, f1 * iHi)));
  }
  if (entry != nullptr) *entry = tNear;
  return static_cast<unsigned>((tNear <= tFar * Float(kRobustFarScale)).mask());
}

/// One deferred child of a packet traversal: its reference, the rays that were live when it was
/// deferred, and the least entry distance any ray of the packet may have into its box (the
/// packet's interval test), culled per ray when popped.
struct PacketEntry {
  float entry;
  uint32_t ref;
  unsigned rays;
};

/// Packet traversals: pops the next deferred child that some of its rays may still find a nearer
/// hit in (its entry within the ray's tmax x kRobustFarScale) into current / currentRays; false
/// when the stack runs empty.
template <class Float>
PA_BVH_INLINE bool popLivePacketEntry(const PacketEntry* stack, int& top, Float tmax, uint32_t& current,
                                      unsigned& currentRays) {
  const Float cull = tmax * Float(kRobustFarScale);
  while (top > 0) {
    const PacketEntry& e = stack[--top];
    const unsigned live = e.rays & static_cast<unsigned>((Float(e.entry) <= cull).mask());
    if (live) {
      current = e.ref;
      currentRays = live;
      return true;
    }
  }
  return false;
}

/// The lanes of a node or pack whose boxes a packet's cull tests: L::Float8 for the 8-wide
/// layout's (Eight: WideNode or TrianglePack), else L::Float.
template <class L, class NodeOrPack, class Eight>
using LayoutFloat = std::conditional_t<std::is_same_v<NodeOrPack, Eight>, typename L::Float8, typename L::Float>;

/// The lane traits a packet's leaf is tested with ray by ray: L::SingleRayLanes where L names
/// them (packets wider than the single-ray lanes), else L.
template <class L, class = void>
struct SingleRayLanesOf {
  using type = L;
};
template <class L>
struct SingleRayLanesOf<L, std::void_t<typename L::SingleRayLanes>> {
  using type = typename L::SingleRayLanes;
};

/// Leaves reached by at most this many rays of a shear class are tested ray by ray (a pack's
/// triangles per instruction); more rays test the leaf triangle by triangle (rays per
/// instruction).
inline constexpr int kRayByRayLeaf = 2;

/// Any-hit packets whose directions part by more than this share of their size (the widest
/// axis' range over the rays over the largest |direction|_1) have each child a node's interval
/// test lets through tested against each ray (enterPacketChildren): shadow rays from one lamp to
/// a pixel block's surfaces part where the block spans a depth edge, and there the interval
/// alone took every ray through what any one needed (oacmpdm9: 0.22x Embree's rtcOccluded16).
/// Ten maps, `scripts/bench_maps.sh -- --primary-size 320x180`, 2-3 runs a value (Zen 4, AVX-512 /
/// AVX2 geometric mean and worst map): 0.015: 1.009 / 0.818, worst 0.784 / 0.631; 0.03: 1.046-1.075
/// / 0.827-0.837, worst 0.845-0.869 / 0.641-0.669; 0.05: 1.076 / 0.837, worst 0.724 / 0.599; 0.1:
/// 1.078 / 0.802, worst 0.617 / 0.455; every packet: 0.851 / 0.783; none: 0.776-0.780 / 0.609-0.617.
inline constexpr float kPerRayChildSpread = 0.03f;

/// Up to L::kWidth rays of one octant with finite inverse directions, one per lane (lane i: the
/// caller's i-th ray of the L::kWidth traced together): origins and tmin, the per-ray constants
/// of the watertight test (RayShear's), the rays' interval bounds (what nodes are culled with),
/// and their shear classes. Idle lanes repeat the first ray, with tmax -inf.
template <class L>
struct Packet {
  using Float = typename L::Float;
  Float ox, oy, oz, tmin;
  Float ix, iy, iz;                        ///< Inverse directions (set with perRayChildren).
  Float sx, sy, sz;                        ///< RayShear::sx, sy, sz per ray.
  Float cull;                              ///< cullSign of each ray's HitFilter::cull.
  bool cullsAFace = false;                 ///< Some ray's HitFilter::cull is not None.
  typename L::PacketPlane plane;           ///< What L::planeDistancesOverRays needs of the rays.
  PacketBounds box;
  bool sharedOrigin = false;               ///< Every live ray starts at box.oLo (camera rays).
  float dLo[3], dHi[3];                    ///< Bounds of the live rays' directions per axis.
  float dSize;                             ///< Largest |direction|_1 of the live rays (bound).
  bool perRayChildren = false;             ///< Nodes' children tested ray by ray (enterPacketChildren).
  int nearSide[3];                         ///< The octant's near box side per axis.
  int orderShift;                          ///< 4 x the octant (Wide16Node::order).
  unsigned lanes = 0;                      ///< The live lanes.
  unsigned classRays[6] = {};              ///< Lanes of each shear class (kz, kx/ky swapped).
  int axes[6][3] = {};                     ///< kx, ky, kz of each shear class.
  alignas(4 * L::kWidth) float tmax[L::kWidth];
};

/// A packet's rays as lanes: origins, directions, tmin and tmax.
template <class Float>
struct PacketRays {
  Float o[3], d[3], tmin, tmax;
};

/// The lane traits' loadRays read each Ray as one record of eight floats: origin x y z, tmin,
/// direction x y z, tmax.
inline constexpr int kRayRecordFloats = 8;
static_assert(kRayRecordFloats == 8 && sizeof(Ray) == kRayRecordFloats * sizeof(float) &&
              offsetof(Ray, origin) == 0 && offsetof(Ray, tmin) == 12 && offsetof(Ray, dir) == 16 &&
              offsetof(Ray, tmax) == 28);

/// PacketRays from the records' fields, one register per field (field[k]: float k of each
/// lane's record).
template <class Float>
PA_BVH_INLINE PacketRays<Float> packetRaysFromRecords(const Float (&field)[kRayRecordFloats]) {
  return {{field[0], field[1], field[2]}, {field[4], field[5], field[6]}, field[3], field[7]};
}

/// Fills p from the rays in r's lanes `lanes` (one octant, finite inverse directions; every
/// other lane holds a copy of one of them): the divisions and comparisons of RayShear,
/// all lanes at once, and the packet's interval bounds. With `perRayAllowed` (any-hit packets),
/// perRayChildren where the rays part by more than kPerRayChildSpread, and then their inverse
/// directions.
template <class L>
PA_BVH_INLINE void finishPacket(const PacketRays<typename L::Float>& r, unsigned lanes, Packet<L>& p,
                                bool perRayAllowed) {
  using Float = typename L::Float;
  const auto bits = [](auto laneMask) { return static_cast<unsigned>(laneMask.mask()); };
  const Float minusInfinity(-std::numeric_limits<float>::infinity());
  p.lanes = lanes;
  select(lanes, minusInfinity, r.tmax).store(p.tmax);   // idle lanes: -inf
  const int first = std::countr_zero(lanes);
  for (int axis = 0; axis < 3; ++axis) p.nearSide[axis] = bits(r.d[axis] < Float(0.0f)) >> first & 1;
  p.orderShift = 4 * (p.nearSide[0] | p.nearSide[1] << 1 | p.nearSide[2] << 2);
  p.ox = r.o[0], p.oy = r.o[1], p.oz = r.o[2];
  const Float dx = r.d[0], dy = r.d[1], dz = r.d[2];
  p.tmin = r.tmin;
  p.sharedOrigin = true;
  p.dSize = 0.0f;
  for (int axis = 0; axis < 3; ++axis) {
    p.box.oLo[axis] = minOverLanes(r.o[axis], lanes);
    p.box.oHi[axis] = maxOverLanes(r.o[axis], lanes);
    p.dLo[axis] = minOverLanes(r.d[axis], lanes);
    p.dHi[axis] = maxOverLanes(r.d[axis], lanes);
    // 1/d falls as d rises on either side of zero, and rounding keeps that order: the bounds of
    // the lanes' own inverses.
    p.box.iLo[axis] = 1.0f / p.dHi[axis];
    p.box.iHi[axis] = 1.0f / p.dLo[axis];
    p.sharedOrigin = p.sharedOrigin && p.box.oLo[axis] == p.box.oHi[axis];
    p.dSize += std::max(std::abs(p.dLo[axis]), std::abs(p.dHi[axis]));
  }
  p.box.tminLo = minOverLanes(p.tmin, lanes);
  // Any-hit packets whose rays part widely have their nodes' children tested ray by ray.
  if (perRayAllowed) {
    float spread = 0.0f;
    for (int axis = 0; axis < 3; ++axis) spread = std::max(spread, p.dHi[axis] - p.dLo[axis]);
    p.perRayChildren = !(spread <= kPerRayChildSpread * p.dSize);
    if (p.perRayChildren) p.ix = Float(1.0f) / dx, p.iy = Float(1.0f) / dy, p.iz = Float(1.0f) / dz;
  }
  // RayShear of every ray: the dominant axis kz, kx and ky swapped where dir[kz] < 0.
  const Float ax = abs(dx), ay = abs(dy), az = abs(dz);
  const unsigned xy = bits(ax > ay), xz = bits(ax > az), yz = bits(ay > az);
  const unsigned kz0 = xy & xz, kz1 = ~xy & yz, kz2 = ~(kz0 | kz1);
  const Float dkz = select(kz1, select(kz0, dz, dx), dy);
  const Float kxPlain = select(kz1, select(kz0, dx, dy), dz);   // (kz + 1) % 3
  const Float kyPlain = select(kz1, select(kz0, dy, dz), dx);   // (kz + 2) % 3
  const unsigned swapped = bits(dkz < Float(0.0f));
  p.sx = select(swapped, kxPlain, kyPlain) / dkz;
  p.sy = select(swapped, kyPlain, kxPlain) / dkz;
  p.sz = Float(1.0f) / dkz;
  const unsigned byAxis[3] = {kz0, kz1, kz2};
  for (int kz = 0; kz < 3; ++kz) {
    p.classRays[2 * kz] = lanes & byAxis[kz] & ~swapped;
    p.classRays[2 * kz + 1] = lanes & byAxis[kz] & swapped;
    p.axes[2 * kz][0] = (kz + 1) % 3, p.axes[2 * kz][1] = (kz + 2) % 3, p.axes[2 * kz][2] = kz;
    p.axes[2 * kz + 1][0] = (kz + 2) % 3, p.axes[2 * kz + 1][1] = (kz + 1) % 3, p.axes[2 * kz + 1][2] = kz;
  }
  p.plane = typename L::PacketPlane(r.o, r.d);
}

/// The rays of `rays` that enter child slot s of node before their tmax: the single-ray slab
/// test (its far distance widened by kRobustFarScale), one ray per lane.
template <class L>
PA_BVH_INLINE unsigned raysEnteringChild(const typename L::Node& node, int s, const Packet<L>& p,
                                         const typename L::Float& tmax, unsigned rays) {
  using Float = typename L::Float;
  const int* n = p.nearSide;
  const Float nx = (Float(node.bounds[n[0]][0][s]) - p.ox) * p.ix;
  const Float ny = (Float(node.bounds[n[1]][1][s]) - p.oy) * p.iy;
  const Float nz = (Float(node.bounds[n[2]][2][s]) - p.oz) * p.iz;
  const Float fx = (Float(node.bounds[1 - n[0]][0][s]) - p.ox) * p.ix;
  const Float fy = (Float(node.bounds[1 - n[1]][1][s]) - p.oy) * p.iy;
  const Float fz = (Float(node.bounds[1 - n[2]][2][s]) - p.oz) * p.iz;
  const Float tNear = maxKeep(nx, maxKeep(ny, maxKeep(nz, p.tmin)));
  const Float tFar = minKeep(fx, minKeep(fy, minKeep(fz, tmax))) * Float(kRobustFarScale);
  return static_cast<unsigned>((tNear <= tFar).mask()) & rays;
}

/// At an inner node: the children some ray of the packet may enter before tmaxHi (the largest
/// tmax of its rays), by the packet's interval test; with kPerRay, each of those is then tested
/// against each ray of currentRays and entered with the rays that enter it (any-hit packets:
/// shadow rays from one lamp to a pixel block's surfaces part at depth edges, and the interval
/// alone drags every ray through what one needs), else with currentRays (camera rays: nearly
/// every ray enters what the interval test lets through, and the leaves test each ray exactly;
/// on five maps at 1024x576, 6% more primary rays per second with AVX-512 and 16% with AVX2
/// than testing each child against each ray, `scripts/bench_maps.sh`). Goes on with the nearest
/// (current, currentRays) and defers the others farthest first: in the node's order for the
/// octant (L::kOctantOrder), else by their least entry distance. False when no child is entered.
template <class L, bool kPerRay>
PA_BVH_INLINE bool enterPacketChildren(const typename L::Node& node, const Packet<L>& p, float tmaxHi,
                                       const typename L::Float& tmax, PacketEntry* stack, int& top,
                                       uint32_t& current, unsigned& currentRays) {
  using NodeFloat = LayoutFloat<L, typename L::Node, WideNode>;
  constexpr int kChildren = int(std::extent_v<decltype(node.child)>);
  const NodeFloat lo[3] = {NodeFloat::load(node.bounds[0][0]), NodeFloat::load(node.bounds[0][1]),
                           NodeFloat::load(node.bounds[0][2])};
  const NodeFloat hi[3] = {NodeFloat::load(node.bounds[1][0]), NodeFloat::load(node.bounds[1][1]),
                           NodeFloat::load(node.bounds[1][2])};
  NodeFloat entries;
  unsigned candidates = packetMayEnterBoxes(lo, hi, p.box, p.nearSide, tmaxHi, &entries);
  if (!candidates) return false;
  unsigned raysOf[kChildren];
  const bool perRay = kPerRay && p.perRayChildren;
  if (perRay) {
    unsigned kept = 0;
    for (unsigned c = candidates; c; c &= c - 1) {
      const int slot = std::countr_zero(c);
      raysOf[slot] = raysEnteringChild(node, slot, p, tmax, currentRays);
      if (raysOf[slot]) kept |= 1u << slot;
    }
    candidates = kept;
    if (!candidates) return false;
  }
  const auto raysFor = [&](int slot) { return perRay ? raysOf[slot] : currentRays; };
  alignas(64) float entry[kChildren];
  entries.store(entry);
  if (std::has_single_bit(candidates)) {
    current = node.child[std::countr_zero(candidates)];
    currentRays = raysFor(std::countr_zero(candidates));
    return true;
  }
  if constexpr (L::kOctantOrder) {
    // Farthest first from the lowest bit; the last one is entered.
    unsigned ordered = L::octantOrder(node, candidates, p.orderShift);
    for (; ordered & (ordered - 1); ordered &= ordered - 1) {
      const int slot = L::octantSlot(node, std::countr_zero(ordered), p.orderShift);
      stack[top++] = {entry[slot], node.child[slot], raysFor(slot)};
    }
    const int slot = L::octantSlot(node, std::countr_zero(ordered), p.orderShift);
    current = node.child[slot];
    currentRays = raysFor(slot);
    return true;
  } else {
    int slots[kChildren];   // farthest first
    int count = 0;
    for (; candidates; candidates &= candidates - 1) {
      const int slot = std::countr_zero(candidates);
      int at = count++;
      for (; at > 0 && entry[slots[at - 1]] < entry[slot]; --at) slots[at] = slots[at - 1];
      slots[at] = slot;
    }
    for (int k = 0; k + 1 < count; ++k) stack[top++] = {entry[slots[k]], node.child[slots[k]], raysFor(slots[k])};
    current = node.child[slots[count - 1]];
    currentRays = raysFor(slots[count - 1]);
    return true;
  }
}

/// One triangle of a pack against the rays in `rays` (one shear class, axes = its kx, ky, kz),
/// one ray per lane: crossedEdges with triangles and rays swapped, so each ray's values are
/// those of its own single-ray test.
template <class L, class Pack>
PA_BVH_INLINE unsigned testTriangleAgainstRays(const Pack& pack, int lane, const int axes[3], const Packet<L>& p,
                                               unsigned rays, PackEdges<typename L::Float>& out) {
  using Float = typename L::Float;
  const Float origins[3] = {p.ox, p.oy, p.oz};
  Float coordinate[3][3];   // [axis kx, ky, kz][vertex]
  for (int k = 0; k < 3; ++k)
    for (int vertex = 0; vertex < 3; ++vertex) coordinate[k][vertex] = Float(pack.v[vertex][axes[k]][lane]);
  const Float origin[3] = {origins[axes[0]], origins[axes[1]], origins[axes[2]]};
  return crossedEdges<L>(coordinate[0], coordinate[1], coordinate[2], origin, p.sx, p.sy, p.sz, rays, out);
}

/// The triangles of a pack whose bounding boxes some ray of the packet may enter before tmaxHi
/// (packetMayEnterBoxes on boxes made from the vertices): a triangle a ray hits within
/// [tmin, tmax] lies in a box the ray enters, so the others are skipped for the whole packet.
template <class L, class Pack>
PA_BVH_INLINE unsigned trianglesPacketMayHit(const Pack& pack, const PacketBounds& b, const int nearSide[3],
                                             float tmaxHi) {
  using Float = LayoutFloat<L, Pack, TrianglePack>;
  Float lo[3], hi[3];
  for (int axis = 0; axis < 3; ++axis) {
    const Float v0 = Float::load(pack.v[0][axis]), v1 = Float::load(pack.v[1][axis]),
                v2 = Float::load(pack.v[2][axis]);
    lo[axis] = minKeep(v0, minKeep(v1, v2));
    hi[axis] = maxKeep(v0, maxKeep(v1, v2));
  }
  return packetMayEnterBoxes(lo, hi, b, nearSide, tmaxHi);
}

/// The nearest accepted hit of each ray (lane) of a packet so far: barycentrics and the
/// triangle's id (its bits in a float lane; only moved, never computed with). Its distance is the
/// lane's tmax. Written to the caller's hits when the traversal ends.
template <class Float>
struct PacketNearest {
  Float u, v, prim;
};

/// Relative margin of trianglesPacketMayCross: far above the float rounding of its own edge
/// functions and of the watertight test's (a few units in the last place of the same magnitudes).
inline constexpr float kCrossMargin = 1.0f / 4096.0f;

/// For a packet whose rays share their origin: the triangles of a pack whose edges may straddle
/// some ray's line. Each edge function of the watertight test is, up to a factor common to the
/// three edges of one ray, the triple product ((a - o) x (b - o)) . d; bounded over the box of the
/// packet's directions, an edge is surely negative or surely positive for every ray, and a ray
/// with edges of both signs misses. A triangle is skipped only where some edge is surely negative
/// and another surely positive by more than kCrossMargin of the product's magnitude, so every
/// triangle the single-ray test could accept is kept.
template <class L, class Pack>
PA_BVH_INLINE unsigned trianglesPacketMayCross(const Pack& pack, const Packet<L>& p) {
  using Float = LayoutFloat<L, Pack, TrianglePack>;
  Float v[3][3], size[3];   // vertices relative to the origin [vertex][axis]; their 1-norms
  for (int vertex = 0; vertex < 3; ++vertex) {
    for (int axis = 0; axis < 3; ++axis) v[vertex][axis] = Float::load(pack.v[vertex][axis]) - Float(p.box.oLo[axis]);
    size[vertex] = abs(v[vertex][0]) + abs(v[vertex][1]) + abs(v[vertex][2]);
  }
  const Float dLo[3] = {Float(p.dLo[0]), Float(p.dLo[1]), Float(p.dLo[2])};
  const Float dHi[3] = {Float(p.dHi[0]), Float(p.dHi[1]), Float(p.dHi[2])};
  const Float margin(kCrossMargin * p.dSize);
  unsigned negative = 0, positive = 0;
  for (int edge = 0; edge < 3; ++edge) {
    const Float* a = v[edge];
    const Float* b = v[(edge + 1) % 3];
    const Float n[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
    Float lo(0.0f), hi(0.0f);
    for (int axis = 0; axis < 3; ++axis) {
      const Float x = n[axis] * dLo[axis], y = n[axis] * dHi[axis];
      lo = lo + minKeep(x, y);
      hi = hi + maxKeep(x, y);
    }
    const Float bound = size[edge] * size[(edge + 1) % 3] * margin;
    negative |= static_cast<unsigned>((hi < Float(0.0f) - bound).mask());
    positive |= static_cast<unsigned>((lo > bound).mask());
  }
  return ~(negative & positive);
}

/// A pack's triangles against the rays in `rays` (shear class c), triangle by triangle in the
/// order the single-ray kernel accepts them (lane order): a ray takes a hit within [tmin, its
/// current tmax] on a face it does not cull (one-sided triangles) that its filter accepts
/// (filtered triangles only). Returns the rays that
/// took a hit; their tmax (lanes of tmax) and nearest hits are updated. Any hit (kAnyHit): a ray
/// that took one is tested no further.
template <class L, bool kAnyHit, class Pack>
PA_BVH_INLINE unsigned packOverRays(const Pack& pack, const Packet<L>& p, int c, unsigned rays,
                                    typename L::Float& tmax, PacketNearest<typename L::Float>& nearest,
                                    const HitFilter* filters, uint32_t instanceId) {
  using Float = typename L::Float;
  unsigned found = 0;
  unsigned candidates = pack.validBits & trianglesPacketMayHit<L>(pack, p.box, p.nearSide, maxOverLanes(tmax, rays));
  if (candidates && p.sharedOrigin) candidates &= trianglesPacketMayCross<L>(pack, p);
  for (unsigned triangles = candidates; triangles; triangles &= triangles - 1) {
    const int lane = std::countr_zero(triangles);
    PackEdges<Float> e;
    unsigned accepted = testTriangleAgainstRays<L>(pack, lane, p.axes[c], p, rays, e);
    if (!accepted) continue;
    if (p.cullsAFace && (pack.oneSidedBits >> lane & 1)) {   // the rays that cull the face they see skip it
      accepted = afterFaceCull(accepted, ~0u, e.det, p.cull);
      if (!accepted) continue;
    }
    const Float rcp = Float(1.0f) / e.det;
    const Float t = L::planeDistancesOverRays(pack, lane, p.plane, accepted, e.tScaled * rcp);
    accepted &= static_cast<unsigned>(((t >= p.tmin) & (t <= tmax)).mask());
    if (!accepted) continue;
    const Float u = e.u * rcp, v = e.v * rcp;
    if (pack.maskedBits >> lane & 1) {
      alignas(4 * L::kWidth) float us[L::kWidth], vs[L::kWidth], ts[L::kWidth];
      u.store(us);
      v.store(vs);
      t.store(ts);
      for (unsigned r = accepted; r; r &= r - 1) {
        const int ray = std::countr_zero(r);
        if (!filters[ray](instanceId, pack.prim[lane], us[ray], vs[ray], ts[ray])) accepted &= ~(1u << ray);
      }
      if (!accepted) continue;
    }
    if constexpr (kAnyHit) {
      found |= accepted;
      rays &= ~accepted;
      if (!rays) break;
      continue;
    }
    tmax = select(accepted, tmax, t);
    nearest.u = select(accepted, nearest.u, u);
    nearest.v = select(accepted, nearest.v, v);
    nearest.prim = select(accepted, nearest.prim, Float(std::bit_cast<float>(pack.prim[lane])));
    found |= accepted;
  }
  return found;
}

/// A leaf against the packet's rays in currentRays, shear class by shear class: a class of at
/// most kRayByRayLeaf rays ray by ray (testLeaf), a larger one triangle by triangle
/// (packOverRays). Returns the rays (lanes) that took a hit; closest hit (kAnyHit false): tmax
/// and hits are updated; any hit: hits is not used.
template <class L, bool kAnyHit>
PA_BVH_INLINE unsigned testPacketLeaf(const typename L::Bvh& bvh, uint32_t ref, Packet<L>& p, unsigned currentRays,
                                      typename L::Float& tmax, PacketNearest<typename L::Float>& nearest,
                                      const Ray* rays, Hit* hits, const HitFilter* filters, uint32_t instanceId) {
  using Float = typename L::Float;
  using S = typename SingleRayLanesOf<L>::type;
  unsigned found = 0;
  for (int c = 0; c < 6; ++c) {
    unsigned classRays = currentRays & p.classRays[c];
    if (!classRays) continue;
    if (std::popcount(classRays) <= kRayByRayLeaf) {
      if constexpr (kAnyHit) {
        for (unsigned r = classRays; r; r &= r - 1) {
          const int lane = std::countr_zero(r);
          const Ray& ray = rays[lane];
          Hit unused;
          if (testLeaf<S, true, false>(bvh, ref, TriangleRay<S>(ray, filters[lane].cull), ray, p.tmax[lane], unused,
                                       filters[lane], instanceId))
            found |= 1u << lane;
        }
        continue;
      }
      tmax.store(p.tmax);
      unsigned hitAlone = 0;
      for (unsigned r = classRays; r; r &= r - 1) {
        const int lane = std::countr_zero(r);
        const Ray& ray = rays[lane];
        if (testLeaf<S, false>(bvh, ref, TriangleRay<S>(ray, filters[lane].cull), ray, p.tmax[lane], hits[lane],
                               filters[lane], instanceId))
          hitAlone |= 1u << lane;
      }
      tmax = Float::load(p.tmax);
      if (hitAlone) {   // the lanes' nearest hits are those testLeaf wrote
        alignas(4 * L::kWidth) float us[L::kWidth], vs[L::kWidth], prims[L::kWidth];
        nearest.u.store(us), nearest.v.store(vs), nearest.prim.store(prims);
        for (unsigned r = hitAlone; r; r &= r - 1) {
          const Hit& hit = hits[std::countr_zero(r)];
          us[std::countr_zero(r)] = hit.u, vs[std::countr_zero(r)] = hit.v;
          prims[std::countr_zero(r)] = std::bit_cast<float>(hit.prim);
        }
        nearest = {Float::load(us), Float::load(vs), Float::load(prims)};
        found |= hitAlone;
      }
      continue;
    }
    if constexpr (L::kSmallLeaves) {
      if (ref & kSmallLeafBit) {
        found |= packOverRays<L, kAnyHit>(bvh.smallPacks[ref & kFirstPackMask], p, c, classRays, tmax, nearest,
                                          filters, instanceId);
        continue;
      }
    }
    uint32_t firstPack, packCount;
    leafPacks(ref, firstPack, packCount);
    for (uint32_t k = firstPack; k < firstPack + packCount; ++k) {
      const unsigned took = packOverRays<L, kAnyHit>(bvh.packs[k], p, c, classRays, tmax, nearest, filters, instanceId);
      found |= took;
      if constexpr (kAnyHit) {
        classRays &= ~took;
        if (!classRays) break;
      }
    }
  }
  return found;
}

/// The packet's rays in one traversal for all of them. Closest hit (kAnyHit false): returns the
/// lanes that hit; p.tmax holds their distances and hits (by caller index) their hits, written
/// once at the end. Any hit: returns the lanes that hit something (hits is not used); a ray
/// leaves the traversal at its first accepted hit, and the traversal ends when none is left.
template <class L, bool kAnyHit>
PA_BVH_KERNEL unsigned traversePacket(const typename L::Bvh& bvh, Packet<L>& p, const Ray* rays, Hit* hits,
                                      const HitFilter* filters, uint32_t instanceId) {
  using Float = typename L::Float;
  // At most children - 1 deferred entries per level, as in the single-ray stack.
  PacketEntry stack[kStackSizeFor<uint32_t(std::extent_v<decltype(L::Node::child)>)>];
  int top = 0;
  uint32_t current = 0;
  unsigned currentRays = p.lanes;
  unsigned found = 0;
  unsigned searching = p.lanes;   // any hit: the rays without one yet
  Float tmax = Float::load(p.tmax);
  float tmaxHi = maxOverLanes(tmax, p.lanes);   // updated where a leaf shortens some ray
  PacketNearest<Float> nearest{Float(0.0f), Float(0.0f), Float(0.0f)};
  for (;;) {
    if (!(current & kLeafBit)) {
      if (enterPacketChildren<L, kAnyHit>(bvh.nodes[current], p, tmaxHi, tmax, stack, top, current, currentRays))
        continue;
    } else if (const unsigned hit = testPacketLeaf<L, kAnyHit>(bvh, current, p, currentRays, tmax, nearest, rays,
                                                               hits, filters, instanceId)) {
      found |= hit;
      if constexpr (kAnyHit) {
        searching &= ~hit;
        if (!searching) return found;
      }
      tmaxHi = maxOverLanes(tmax, searching);
    }
    bool popped;
    do {
      popped = popLivePacketEntry(stack, top, tmax, current, currentRays);
      if constexpr (kAnyHit) currentRays &= searching;
    } while (kAnyHit && popped && !currentRays);
    if (!popped) {
      if constexpr (kAnyHit) return found;
      tmax.store(p.tmax);
      alignas(4 * L::kWidth) float us[L::kWidth], vs[L::kWidth], prims[L::kWidth];
      nearest.u.store(us), nearest.v.store(vs), nearest.prim.store(prims);
      for (unsigned r = found; r; r &= r - 1) {
        const int lane = std::countr_zero(r);
        hits[lane] = {p.tmax[lane], us[lane], vs[lane], std::bit_cast<uint32_t>(prims[lane]), instanceId};
      }
      return found;
    }
  }
}

/// The lanes of r whose rays are traceable (isTraceableRay: finite origin and direction, a
/// direction that is not zero, tmin <= tmax and neither NaN).
template <class Float>
PA_BVH_INLINE unsigned traceableLanes(const PacketRays<Float>& r) {
  const Float zero(0.0f);
  unsigned lanes = static_cast<unsigned>((r.tmin <= r.tmax).mask());
  for (int axis = 0; axis < 3; ++axis)   // x - x is 0 exactly where x is finite
    lanes &= static_cast<unsigned>((((r.o[axis] - r.o[axis]) == zero) & ((r.d[axis] - r.d[axis]) == zero)).mask());
  return lanes & ~static_cast<unsigned>(((r.d[0] == zero) & (r.d[1] == zero) & (r.d[2] == zero)).mask());
}

/// The lanes of r whose direction components are all normal floats (|d| >= FLT_MIN), so that
/// every inverse 1/d, and every bound of them the packet derives, is finite (at most 2^126), in
/// any floating-point mode. Zero and subnormal components (whose inverses overflow, or read as
/// zero where denormals are flushed) leave their rays to the single-ray kernel, which gives the
/// same answers. A comparison per axis instead of a division: primary rays 1.006 -> 1.046x
/// Embree's rtcIntersect16 on five maps with AVX-512, level with AVX2 (scripts/bench_maps.sh).
template <class Float>
PA_BVH_INLINE unsigned invertibleLanes(const PacketRays<Float>& r) {
  const Float least(std::numeric_limits<float>::min());
  unsigned lanes = ~0u;
  for (int axis = 0; axis < 3; ++axis) lanes &= static_cast<unsigned>((abs(r.d[axis]) >= least).mask());
  return lanes;
}

/// The traceable rays (isTraceableRay) in `active` (bit i: rays[i], filters[i] and, for closest
/// hits, hits[i]; at most kMaxPacketRays; the others are left as they are), L::kWidth
/// consecutive rays at a time: loaded into lanes at once (L::loadRays, lane i = the i-th of
/// them), traceability and octants decided for all lanes together, then each octant's rays traced
/// as one packet (the rays in its lanes, the others masked); rays with a zero or subnormal
/// direction component (invertibleLanes), and octants of one ray, by single(index) alone. Per ray
/// the single-ray contract: closest hit (kAnyHit false) shortens its tmax to its hit; any hit
/// leaves rays and hits as they are. Returns the rays that hit.
template <class L, bool kAnyHit, class RayArray, class SingleRay>
PA_BVH_INLINE unsigned tracePackets(const typename L::Bvh& bvh, RayArray* allRays, Hit* allHits, unsigned allActive,
                                    const HitFilter* allFilters, uint32_t instanceId, const SingleRay& single) {
  using Float = typename L::Float;
  static_assert(kMaxPacketRays % L::kWidth == 0);
  if (bvh.empty()) return 0;
  unsigned found = 0;
  for (uint32_t base = 0; base < kMaxPacketRays; base += L::kWidth) {
    const unsigned active = allActive >> base & ((1u << L::kWidth) - 1);
    if (!active) continue;
    RayArray* rays = allRays + base;
    Hit* hits = kAnyHit ? nullptr : allHits + base;
    const HitFilter* filters = allFilters + base;
    const PacketRays<Float> all = L::loadRays(rays, active);
    const unsigned traceable = active & traceableLanes(all);
    alignas(4 * L::kWidth) float culls[L::kWidth] = {};   // cullSign of each lane's filter
    bool cullsAFace = false;
    for (unsigned r = active; r; r &= r - 1) {
      culls[std::countr_zero(r)] = cullSign(filters[std::countr_zero(r)].cull);
      cullsAFace = cullsAFace || filters[std::countr_zero(r)].cull != FaceCull::None;
    }
    unsigned packetable = traceable & invertibleLanes(all);
    for (unsigned r = traceable & ~packetable; r; r &= r - 1)
      if (single(base + std::countr_zero(r))) found |= 1u << (base + std::countr_zero(r));
    unsigned negative[3];
    for (int axis = 0; axis < 3; ++axis) negative[axis] = static_cast<unsigned>((all.d[axis] < Float(0.0f)).mask());
    while (packetable) {
      const int first = std::countr_zero(packetable);
      unsigned octant = packetable;
      for (int axis = 0; axis < 3; ++axis) octant &= (negative[axis] >> first & 1) ? negative[axis] : ~negative[axis];
      packetable &= ~octant;
      if (std::popcount(octant) == 1) {
        if (single(base + first)) found |= 1u << (base + first);
        continue;
      }
      Packet<L> packet;
      // Lanes outside the packet must hold one of its rays: reload where other rays share them.
      finishPacket(octant == active ? all : L::loadRays(rays, octant), octant, packet, kAnyHit);
      packet.cull = Float::load(culls);
      packet.cullsAFace = cullsAFace;
      for (unsigned r = traversePacket<L, kAnyHit>(bvh, packet, rays, hits, filters, instanceId); r; r &= r - 1) {
        const int lane = std::countr_zero(r);
        if constexpr (!kAnyHit) rays[lane].tmax = packet.tmax[lane];
        found |= 1u << (base + lane);
      }
    }
  }
  return found;
}

/// Closest hits of packets of rays (tracePackets); kSingleRay traces the rays that go alone.
template <class L, bool (*kSingleRay)(const typename L::Bvh&, Ray&, Hit&, const HitFilter&, uint32_t)>
PA_BVH_INLINE unsigned intersectPacket(const typename L::Bvh& bvh, Ray* rays, Hit* hits, unsigned active,
                                       const HitFilter* filters, uint32_t instanceId) {
  return tracePackets<L, false>(bvh, rays, hits, active, filters, instanceId, [&](uint32_t i) {
    return kSingleRay(bvh, rays[i], hits[i], filters[i], instanceId);
  });
}

/// Any hits of packets of rays (tracePackets): the rays that hit something; kSingleRay traces the
/// rays that go alone.
template <class L, bool (*kSingleRay)(const typename L::Bvh&, const Ray&, const HitFilter&, uint32_t)>
PA_BVH_INLINE unsigned occludedPacket(const typename L::Bvh& bvh, const Ray* rays, unsigned active,
                                      const HitFilter* filters, uint32_t instanceId) {
  return tracePackets<L, true>(bvh, rays, nullptr, active, filters, instanceId,
                               [&](uint32_t i) { return kSingleRay(bvh, rays[i], filters[i], instanceId); });
}

}  // namespace pa::bvh_detail
