// Tlas packet queries: a packet of rays walks the instance tree together (tlas.cpp's comment says
// how the tree is ordered and walked), each box culled for the whole packet by interval
// arithmetic before its rays are tested one by one; and raysMayHit, the cheap cull before a
// packet query that few rays need.
#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <span>

#include <glm/common.hpp>
#include <glm/mat3x3.hpp>

#include "renderer/bvh/bvh.h"
#include "renderer/bvh/simd.h"
#include "renderer/bvh/slab_test.h"
#include "renderer/bvh/tlas_impl.h"
#include "renderer/bvh/triangle_mesh.h"

namespace pa {

using namespace tlas_detail;

namespace {

// A packet's kMaxPacketRays lanes are worked on as kHalves vectors of kLanes (the helpers below
// are inlined, never passed across an ABI boundary, whatever the ISA).
#pragma GCC diagnostic ignored "-Wpsabi"
constexpr uint32_t kHalves = kMaxPacketRays / kLanes;

Lanes loadLanes(const float* p) {
  Lanes v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
IntLanes loadLanes(const int32_t* p) {
  IntLanes v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
void storeLanes(float* p, const Lanes& v) { std::memcpy(p, &v, sizeof v); }
void storeLanes(int32_t* p, const IntLanes& v) { std::memcpy(p, &v, sizeof v); }

/// All ones in lane i where bit i of `bits` is set (simd::laneMask; bits above the eighth ignored).
IntLanes laneMask(uint32_t bits) { return std::bit_cast<IntLanes>(simd::laneMask(bits & 0xffu)); }

/// The smallest / largest lane (two folds, then the last pair).
float minOf(const Lanes& lanes) {
  Lanes v = lanes;
  v = v < __builtin_shuffle(v, IntLanes{4, 5, 6, 7, 0, 1, 2, 3}) ? v : __builtin_shuffle(v, IntLanes{4, 5, 6, 7, 0, 1, 2, 3});
  v = v < __builtin_shuffle(v, IntLanes{2, 3, 0, 1, 6, 7, 4, 5}) ? v : __builtin_shuffle(v, IntLanes{2, 3, 0, 1, 6, 7, 4, 5});
  return std::min(v[0], v[1]);
}
float maxOf(const Lanes& lanes) {
  Lanes v = lanes;
  v = v > __builtin_shuffle(v, IntLanes{4, 5, 6, 7, 0, 1, 2, 3}) ? v : __builtin_shuffle(v, IntLanes{4, 5, 6, 7, 0, 1, 2, 3});
  v = v > __builtin_shuffle(v, IntLanes{2, 3, 0, 1, 6, 7, 4, 5}) ? v : __builtin_shuffle(v, IntLanes{2, 3, 0, 1, 6, 7, 4, 5});
  return std::max(v[0], v[1]);
}

/// Interval bounds of a packet of rays that share one octant (finite inverse directions): a box
/// that no origin in [oLo, oHi] along no inverse direction in [iLo, iHi] enters is culled for
/// the whole packet before any ray is tested on its own.
struct PacketInterval {
  float oLo[3], oHi[3], iLo[3], iHi[3];
  float tminLo = std::numeric_limits<float>::infinity();
  float tmaxHi = -std::numeric_limits<float>::infinity();   ///< The rays' largest tmax.
  int nearSide[3] = {0, 0, 0};
  bool valid = false;   ///< False when the rays span octants or run along an axis plane.
};

/// The bits of a group's boxes that some ray of the packet may enter before its tmaxHi and whose mask
/// matches rayMask. A box is culled only when no origin in [oLo, oHi] along no inverse direction
/// in [iLo, iHi] enters it: (bound - origin) * inverse bounded over the intervals' corners, as each
/// ray's slab test rounds it (rounding is monotonic, so the bounds hold for the rounded per-ray
/// values too).
uint32_t groupMayEnter(const PacketInterval& p, const BoxGroup& group, uint32_t rayMask) {
  const auto lesser = [](const Lanes& a, const Lanes& b) { return a < b ? a : b; };
  const auto greater = [](const Lanes& a, const Lanes& b) { return a > b ? a : b; };
  Lanes tNear = Lanes{} + p.tminLo, tFar = Lanes{} + p.tmaxHi;
  for (int axis = 0; axis < 3; ++axis) {
    const Lanes& nearBound = p.nearSide[axis] ? group.max[axis] : group.min[axis];
    const Lanes& farBound = p.nearSide[axis] ? group.min[axis] : group.max[axis];
    const Lanes n0 = nearBound - p.oHi[axis], n1 = nearBound - p.oLo[axis];
    const Lanes f0 = farBound - p.oHi[axis], f1 = farBound - p.oLo[axis];
    tNear = greater(tNear, lesser(lesser(n0 * p.iLo[axis], n0 * p.iHi[axis]), lesser(n1 * p.iLo[axis], n1 * p.iHi[axis])));
    tFar = lesser(tFar, greater(greater(f0 * p.iLo[axis], f0 * p.iHi[axis]), greater(f1 * p.iLo[axis], f1 * p.iHi[axis])));
  }
  return laneBits((tNear <= tFar * bvh_detail::kRobustFarScale) & ((group.mask & static_cast<int32_t>(rayMask)) != 0));
}

/// A packet's rays as lanes (structure of arrays), with their inverse directions and near box
/// sides, and which of them can be traced; idle lanes (inactive or untraceable rays) hold a ray
/// that enters no box (tmin > tmax).
struct PacketLanes {
  alignas(64) float origin[3][kMaxPacketRays];
  alignas(64) float inverse[3][kMaxPacketRays];
  alignas(64) int32_t nearSide[3][kMaxPacketRays];   ///< 1: the box's max is the near plane.
  alignas(64) float tmin[kMaxPacketRays], tmax[kMaxPacketRays];
  uint32_t traceable = 0;   ///< The active rays bvh_detail::isTraceableRay accepts (same test, in lanes).
};

/// The `active` rays of a packet (rays holds at least the highest active one) as lanes.
PacketLanes packetLanes(std::span<const Ray> rays, uint32_t active) {
  constexpr float kInf = std::numeric_limits<float>::infinity();
  const Ray idle{};   // read for the inactive lanes, so the loads need no branch
  PacketLanes p;
  alignas(64) float direction[3][kMaxPacketRays];
  for (uint32_t lane = 0; lane < kMaxPacketRays; ++lane) {
    const Ray& ray = active >> lane & 1 ? rays[lane] : idle;
    for (int axis = 0; axis < 3; ++axis) {
      p.origin[axis][lane] = ray.origin[axis];
      direction[axis][lane] = ray.dir[axis];
    }
    p.tmin[lane] = ray.tmin;
    p.tmax[lane] = ray.tmax;
  }
  // isTraceableRay: finite origin and direction, a non-zero direction, tmin <= tmax (false
  // with a NaN).
  const Lanes kInfs = Lanes{} + kInf;
  for (uint32_t h = 0; h < kHalves; ++h) {
    const uint32_t at = h * kLanes;
    const Lanes tmin = loadLanes(p.tmin + at), tmax = loadLanes(p.tmax + at);
    IntLanes ok = laneMask(active >> at) & (tmin <= tmax);
    IntLanes nonZero{};
    for (int axis = 0; axis < 3; ++axis) {
      const Lanes o = loadLanes(p.origin[axis] + at), d = loadLanes(direction[axis] + at);
      ok &= (o < kInfs) & (o > -kInfs) & (d < kInfs) & (d > -kInfs);
      nonZero |= d != Lanes{};
    }
    const IntLanes live = ok & nonZero;
    p.traceable |= laneBits(live) << at;
    for (int axis = 0; axis < 3; ++axis) {
      const Lanes d = live ? loadLanes(direction[axis] + at) : Lanes{} + 1.0f;
      storeLanes(p.origin[axis] + at, live ? loadLanes(p.origin[axis] + at) : Lanes{});
      storeLanes(p.inverse[axis] + at, 1.0f / d);
      storeLanes(p.nearSide[axis] + at, std::bit_cast<IntLanes>(d) >> 31 & 1);   // signbit
    }
    storeLanes(p.tmin + at, live ? tmin : Lanes{} + 1.0f);
    storeLanes(p.tmax + at, live ? tmax : Lanes{});
  }
  return p;
}

/// The interval bounds of the packet's `live` lanes, and their largest tmax.
PacketInterval packetInterval(const PacketLanes& lanes, uint32_t live) {
  constexpr float kInf = std::numeric_limits<float>::infinity();
  const IntLanes on[kHalves] = {laneMask(live), laneMask(live >> kLanes)};
  // Each lane's value where it is live, else `otherwise`, the two halves folded into one.
  const auto folded = [&](const float* values, float otherwise, bool smallest) {
    const Lanes a = on[0] ? loadLanes(values) : Lanes{} + otherwise;
    const Lanes b = on[1] ? loadLanes(values + kLanes) : Lanes{} + otherwise;
    return smallest ? minOf(a < b ? a : b) : maxOf(a > b ? a : b);
  };
  PacketInterval p;
  bool sameOctant = live != 0, finite = true;
  for (int axis = 0; axis < 3; ++axis) {
    p.oLo[axis] = folded(lanes.origin[axis], kInf, true);
    p.oHi[axis] = folded(lanes.origin[axis], -kInf, false);
    p.iLo[axis] = folded(lanes.inverse[axis], kInf, true);
    p.iHi[axis] = folded(lanes.inverse[axis], -kInf, false);
    // A zero direction component has an infinite inverse: such packets are not bounded.
    finite = finite && std::fabs(p.iLo[axis]) < kInf && std::fabs(p.iHi[axis]) < kInf;
    uint32_t near = 0;
    for (uint32_t h = 0; h < kHalves; ++h)
      near |= laneBits(loadLanes(lanes.nearSide[axis] + h * kLanes) != IntLanes{}) << (h * kLanes);
    sameOctant = sameOctant && ((near & live) == 0 || (near & live) == live);
    p.nearSide[axis] = (near & live) != 0;
  }
  p.tminLo = folded(lanes.tmin, kInf, true);
  p.tmaxHi = folded(lanes.tmax, -kInf, false);
  p.valid = sameOctant && finite;
  return p;
}

/// bvh_detail::slabEntry of every lane's ray against one box (the same operations lane by lane,
/// in a loop the compiler vectorises).
void slabEntries(const PacketLanes& p, const Bounds& box, std::array<float, kMaxPacketRays>& entry) {
  using bvh_detail::maxKeep, bvh_detail::minKeep;
  for (uint32_t lane = 0; lane < kMaxPacketRays; ++lane) {
    float tNear = p.tmin[lane], tFar = p.tmax[lane];
    float n[3], f[3];
    for (int axis = 0; axis < 3; ++axis) {
      const float nearBound = p.nearSide[axis][lane] ? box.max[axis] : box.min[axis];
      const float farBound = p.nearSide[axis][lane] ? box.min[axis] : box.max[axis];
      n[axis] = (nearBound - p.origin[axis][lane]) * p.inverse[axis][lane];
      f[axis] = (farBound - p.origin[axis][lane]) * p.inverse[axis][lane];
    }
    tNear = maxKeep(n[0], maxKeep(n[1], maxKeep(n[2], tNear)));
    tFar = minKeep(f[0], minKeep(f[1], minKeep(f[2], tFar))) * bvh_detail::kRobustFarScale;
    entry[lane] = tNear <= tFar ? tNear : std::numeric_limits<float>::infinity();
  }
}

/// A box some rays of a packet enter (its index at its level, as Pending's): each ray's entry
/// distance (inf: not entered), the rays that enter, and the nearest entry among them.
struct PacketCandidate {
  float nearest;
  uint32_t index;
  uint32_t rays;
  std::array<float, kMaxPacketRays> entry;
};

/// A group the packet walk has yet to enter: the rays that entered its box, with their entries.
struct PacketPending {
  uint32_t level, group;
  uint32_t rays;
  std::array<float, kMaxPacketRays> entry;
};

/// The rays of `candidates` whose entry is within their current tmax (widened as slabEntry widens
/// the far bound): the others found a nearer hit since.
uint32_t raysWithin(uint32_t candidates, const std::array<float, kMaxPacketRays>& entry, std::span<const Ray> rays) {
  uint32_t within = 0;
  for (uint32_t r = candidates; r; r &= r - 1) {
    const int lane = std::countr_zero(r);
    if (!(entry[lane] > rays[lane].tmax * bvh_detail::kRobustFarScale)) within |= 1u << lane;
  }
  return within;
}

/// Instances up to which raysMayHit tests each one's own box in its object space (beyond, the
/// world box of them all).
constexpr size_t kOwnBoxInstances = 4;

/// The largest magnitude of v's components.
float largestMagnitude(const glm::vec3& v) { return std::max({std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)}); }

/// Up to kMaxPacketRays rays as lanes for raysMayHit's box tests, in world or object space.
struct CullLanes {
  float origin[3][kMaxPacketRays], dir[3][kMaxPacketRays];
  float size[kMaxPacketRays];   ///< The largest magnitude of the ray's origin (and what made it).
};

/// The rays' intervals as lanes; an inactive lane's enters no box.
struct CullIntervals {
  float tmin[kMaxPacketRays], tmax[kMaxPacketRays];
};

/// The lanes whose ray enters `box` widened on each side by 2^-16 x (the box's and the lane's
/// size): far more than the rounding by which any kernel's slab test or a copy of a transform
/// may differ from this one, so no ray one of them lets into the box is left out. The slab test
/// itself is bvh_detail::slabEntry's, in a loop the compiler vectorises.
uint32_t widenedBoxEntered(const CullLanes& r, const CullIntervals& t, const Bounds& box) {
  using bvh_detail::maxKeep, bvh_detail::minKeep;
  const float boxSize = std::max(largestMagnitude(box.min), largestMagnitude(box.max));
  uint32_t entered = 0;
  for (uint32_t lane = 0; lane < kMaxPacketRays; ++lane) {
    const float widen = 0x1p-16f * (boxSize + r.size[lane]);
    float tNear = t.tmin[lane], tFar = t.tmax[lane];
    for (int axis = 0; axis < 3; ++axis) {
      const float inverse = 1.0f / r.dir[axis][lane];
      const float t0 = (box.min[axis] - widen - r.origin[axis][lane]) * inverse;
      const float t1 = (box.max[axis] + widen - r.origin[axis][lane]) * inverse;
      tNear = maxKeep(inverse < 0.0f ? t1 : t0, tNear);
      tFar = minKeep(inverse < 0.0f ? t0 : t1, tFar);
    }
    entered |= static_cast<uint32_t>(tNear <= tFar * bvh_detail::kRobustFarScale) << lane;
  }
  return entered;
}

}  // namespace

uint32_t Tlas::intersectPacket(std::span<Ray> rays, std::span<Hit> hits, uint32_t active, uint32_t rayMask,
                               std::span<const HitFilter> filters) const {
  active = bvh_detail::activePacketLanes(active, std::min({rays.size(), hits.size(), filters.size()}),
                                         "Tlas::intersectPacket");
  if (!impl_) return 0;
  const Impl& self = *impl_;
  const PacketLanes lanes = packetLanes(rays, active);
  const uint32_t traceable = lanes.traceable;
  uint32_t found = 0;
  if (std::popcount(traceable) < 2) {   // at most one ray: as a ray alone
    for (uint32_t r = traceable; r; r &= r - 1) {
      const int lane = std::countr_zero(r);
      if (intersect(rays[lane], hits[lane], rayMask, filters[lane])) found |= 1u << lane;
    }
    return found;
  }
  // The tree is walked with the whole packet: at each group the packet's interval culls the boxes
  // no ray can enter, then each box left is tested ray by ray (each ray's own slab test, as
  // forEachEntered's, over the lanes built above: inverse directions divided once). Groups are
  // entered nearest first; a ray goes on into a box only while its entry is within its current
  // tmax, as forEachEntered stops a single ray.
  const PacketInterval interval = packetInterval(lanes, traceable);
  std::array<PacketPending, kStackSize> stack;
  uint32_t depth = 0;
  std::array<Ray, kMaxPacketRays> local;
  std::array<HitFilter, kMaxPacketRays> mirroredFilters;   // filled at the first mirrored instance
  bool haveMirroredFilters = false;
  uint32_t piecesSeen = 0;                              // the scattered instances entered, by pieceGroup
  std::array<uint32_t, kMaxPieceGroups> piecesTraced;   // and the rays traced into each (set when seen)
  const auto traceInstance = [&](const PlacedInstance& inst, uint32_t live) {
    if (inst.pieceGroup != kWholeInstance) {   // traced once per ray, at the first piece it enters
      if (!(piecesSeen >> inst.pieceGroup & 1)) piecesTraced[inst.pieceGroup] = 0;
      piecesSeen |= 1u << inst.pieceGroup;
      live &= ~piecesTraced[inst.pieceGroup];
      if (live == 0) return;
      piecesTraced[inst.pieceGroup] |= live;
    }
    if (inst.identity) {   // placed by the identity, as the world is: its rays as they are
      found |= inst.blas->intersectPacket(rays, hits, live, filters, inst.index);
      return;
    }
    for (uint32_t r = live; r; r &= r - 1) self.toObject(inst, rays[std::countr_zero(r)], local[std::countr_zero(r)]);
    std::span<const HitFilter> instanceFilters = filters;
    if (inst.mirrored) {
      if (!haveMirroredFilters) {
        for (uint32_t r = traceable; r; r &= r - 1)
          mirroredFilters[std::countr_zero(r)] = objectSpaceFilter(inst, filters[std::countr_zero(r)]);
        haveMirroredFilters = true;
      }
      instanceFilters = mirroredFilters;
    }
    const uint32_t hitLanes = inst.blas->intersectPacket(local, hits, live, instanceFilters, inst.index);
    for (uint32_t r = hitLanes; r; r &= r - 1) rays[std::countr_zero(r)].tmax = local[std::countr_zero(r)].tmax;
    found |= hitLanes;
  };
  const Lanes kInfs = Lanes{} + std::numeric_limits<float>::infinity();
  const IntLanes noBox{};
  std::array<PacketCandidate, kRootLanes> entered;
  std::array<uint8_t, kRootLanes> order;   // `entered` nearest first over the packet's rays
  // Enters `groupCount` groups of `level` from `firstGroup` with the `live` rays: traces the
  // instances their boxes hold (level 0) or stacks the groups below, nearest on top.
  const auto enter = [&](uint32_t level, uint32_t firstGroup, uint32_t groupCount, uint32_t live) {
    const IntLanes liveLanes[kHalves] = {laneMask(live), laneMask(live >> kLanes)};
    uint32_t count = 0;
    for (uint32_t g = firstGroup; g < firstGroup + groupCount; ++g) {
      const BoxGroup& group = self.movers.levels[level][g];
      const uint32_t boxes = interval.valid ? groupMayEnter(interval, group, rayMask)
                                            : laneBits((group.mask & static_cast<int32_t>(rayMask)) != noBox);
      for (uint32_t b = boxes; b; b &= b - 1) {
        const uint32_t lane = std::countr_zero(b);
        PacketCandidate& c = entered[count];
        c.index = g * kLanes + lane;
        slabEntries(lanes, laneBox(group, lane), c.entry);
        const Lanes entryA = loadLanes(c.entry.data()), entryB = loadLanes(c.entry.data() + kLanes);
        c.rays = (laneBits(entryA != kInfs) | laneBits(entryB != kInfs) << kLanes) & live;
        const Lanes nearA = liveLanes[0] ? entryA : kInfs, nearB = liveLanes[1] ? entryB : kInfs;
        c.nearest = minOf(nearA < nearB ? nearA : nearB);
        if (!c.rays) continue;
        uint32_t at = count++;   // equal ones in the order found
        for (; at > 0 && entered[order[at - 1]].nearest > c.nearest; --at) order[at] = order[at - 1];
        order[at] = static_cast<uint8_t>(&c - entered.data());
      }
    }
    if (level == 0) {
      for (uint32_t i = 0; i < count; ++i) {
        const PacketCandidate& c = entered[order[i]];
        const uint32_t entering = raysWithin(c.rays, c.entry, rays);
        if (entering) traceInstance(self.movers.instances[c.index], entering);
      }
      return;
    }
    for (uint32_t i = count; i-- > 0;) {
      const PacketCandidate& c = entered[order[i]];
      PacketPending& next = stack[depth++];
      next.level = level - 1;
      next.group = c.index;
      next.rays = c.rays;
      next.entry = c.entry;
    }
  };
  // The world first, its rays as they are (a hit shortens their tmax, and the movers' boxes
  // beyond it are not entered), then the movers' tree.
  if (self.worldTakes(rayMask))
    found |= self.world.blas->intersectPacket(rays, hits, traceable, filters, self.world.index);
  if (self.movers.levelCount == 0) return found;
  enter(self.movers.levelCount - 1, 0,
        static_cast<uint32_t>(self.movers.levels[self.movers.levelCount - 1].size()), traceable);
  while (depth > 0) {
    const PacketPending& node = stack[--depth];
    const uint32_t live = raysWithin(node.rays, node.entry, rays);
    if (live) enter(node.level, node.group, 1, live);   // reads the node before stacking over it
  }
  return found;
}

uint32_t Tlas::occludedPacket(std::span<const Ray> rays, uint32_t active, uint32_t rayMask,
                              std::span<const HitFilter> filters) const {
  active = bvh_detail::activePacketLanes(active, std::min(rays.size(), filters.size()), "Tlas::occludedPacket");
  if (!impl_) return 0;
  const Impl& self = *impl_;
  // The static world first, with the packet's rays as they are (it stops most that stop); the
  // rays it lets through then walk the tree past it one by one (the movers are small and few).
  uint32_t found =
      self.worldTakes(rayMask) ? self.world.blas->occludedPacket(rays, active, filters, self.world.index) : 0u;
  for (uint32_t r = active & ~found; r; r &= r - 1) {
    const int lane = std::countr_zero(r);
    if (bvh_detail::isTraceableRay(rays[lane]) &&
        self.occludedBy(rays[lane], rayMask, filters[lane], Impl::WorldVisit::Traced))
      found |= 1u << lane;
  }
  return found;
}

uint32_t Tlas::raysMayHit(std::span<const Ray> rays, uint32_t active) const {
  active = bvh_detail::activePacketLanes(active, rays.size(), "Tlas::raysMayHit");
  if (!impl_ || impl_->bounds.empty() || active == 0) return 0;
  const Impl& self = *impl_;
  const Ray& first = rays[std::countr_zero(active)];
  CullLanes world;
  CullIntervals intervals;
  bool sharedOrigin = true;   // a camera's rays: each instance transforms the origin once
  for (uint32_t lane = 0; lane < kMaxPacketRays; ++lane) {
    const bool on = active >> lane & 1;
    const Ray& ray = on ? rays[lane] : first;
    for (int axis = 0; axis < 3; ++axis) world.dir[axis][lane] = ray.dir[axis];
    intervals.tmin[lane] = on ? ray.tmin : 1.0f;
    intervals.tmax[lane] = on ? ray.tmax : 0.0f;
    sharedOrigin &= (ray.origin.x == first.origin.x) & (ray.origin.y == first.origin.y) &
                    (ray.origin.z == first.origin.z);
  }
  const float firstSize = largestMagnitude(first.origin);
  for (uint32_t lane = 0; lane < kMaxPacketRays; ++lane) {
    const glm::vec3& origin = sharedOrigin || !(active >> lane & 1) ? first.origin : rays[lane].origin;
    for (int axis = 0; axis < 3; ++axis) world.origin[axis][lane] = origin[axis];
    world.size[lane] = sharedOrigin ? firstSize : largestMagnitude(origin);
  }
  const size_t instanceCount = self.movers.instances.size() + (self.haveWorld ? 1 : 0);
  if (instanceCount > kOwnBoxInstances) return widenedBoxEntered(world, intervals, self.bounds) & active;
  // Few instances: each one's own box in its object space (the world box of a turned model, as
  // the view weapon close to the eye, takes in much of the view around it).
  uint32_t entered = 0;
  CullLanes local;
  const auto test = [&](const PlacedInstance& inst) {
    if (inst.identity) {
      entered |= widenedBoxEntered(world, intervals, inst.blas->bounds());
      return;
    }
    const glm::mat3& m = inst.worldToObjectLinear;
    const float scale = largestMagnitude(glm::abs(m[0]) + glm::abs(m[1]) + glm::abs(m[2]));
    const float offset = largestMagnitude(inst.worldToObjectOffset);
    if (sharedOrigin) {
      Ray out;
      self.toObject(inst, first, out);
      const float size = scale * firstSize + offset + largestMagnitude(out.origin);
      for (uint32_t lane = 0; lane < kMaxPacketRays; ++lane) {
        for (int axis = 0; axis < 3; ++axis) {
          local.origin[axis][lane] = out.origin[axis];
          local.dir[axis][lane] =
              m[0][axis] * world.dir[0][lane] + m[1][axis] * world.dir[1][lane] + m[2][axis] * world.dir[2][lane];
        }
        local.size[lane] = size;
      }
    } else {
      for (uint32_t lane = 0; lane < kMaxPacketRays; ++lane) {
        Ray out;
        self.toObject(inst, active >> lane & 1 ? rays[lane] : first, out);
        for (int axis = 0; axis < 3; ++axis) {
          local.origin[axis][lane] = out.origin[axis];
          local.dir[axis][lane] = out.dir[axis];
        }
        local.size[lane] = scale * world.size[lane] + offset + largestMagnitude(out.origin);
      }
    }
    entered |= widenedBoxEntered(local, intervals, inst.blas->bounds());
  };
  if (self.haveWorld) test(self.world);
  for (const PlacedInstance& inst : self.movers.instances) test(inst);
  return entered & active;
}

}  // namespace pa
