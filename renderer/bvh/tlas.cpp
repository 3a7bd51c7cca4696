// Tlas: the instances' world bounds in an implicit 8-wide tree of 8-lane box groups (instances
// in Morton order of their boxes' centres, 8 to a group; each level above bounds 8 groups of the
// level below), tested a group at a time for a ray and for a packet of rays. Every ray takes the
// static world (the identity instance with the largest box) first, then walks the tree of the
// other instances, the movers, nearest box first: a shadow ray the world blocks needs no walk, a
// closest-hit ray enters only the movers in front of its world hit, and no ray enters the
// world's box, which holds every other, only to skip it. Where two instances meet at the same
// distance (a decal and the floor under it) the one entered last is kept: a mover over the world,
// as when the world's box, entered at the ray's start, came first in a tree of every instance.
// Each instance transforms the ray into object space (without normalising the
// direction, so t stays the world-space t; an instance placed by the identity, the static world,
// takes the ray as it is) and traces its Blas.
#include <algorithm>
#include <array>
#include <bit>
#include <limits>
#include <memory>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>

#include "renderer/bvh/bvh.h"
#include "renderer/bvh/simd.h"
#include "renderer/bvh/slab_test.h"
#include "renderer/bvh/triangle_mesh.h"

namespace pa {
namespace {

struct PlacedInstance {
  const Blas* blas = nullptr;
  glm::mat3 worldToObjectLinear{1.0f};
  glm::vec3 worldToObjectOffset{0.0f};
  uint32_t mask = 0;
  uint32_t index = 0;   // position in the span given to build()
  bool identity = false;   // objectToWorld is exactly the identity: rays enter untransformed
  // The transform's determinant is negative: a world-space winding is the opposite object-space
  // one (cross(M a, M b) = det(M) M^-T cross(a, b)), so the faces a ray culls swap.
  bool mirrored = false;
};

/// The filter a ray takes into an instance: its face culling seen from object space.
HitFilter objectSpaceFilter(const PlacedInstance& inst, const HitFilter& filter) {
  if (!inst.mirrored || filter.cull == FaceCull::None) return filter;
  HitFilter flipped = filter;
  flipped.cull = filter.cull == FaceCull::Back ? FaceCull::Front : FaceCull::Back;
  return flipped;
}

bool finiteMatrix(const glm::mat4x3& m) {
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 3; ++r)
      if (!std::isfinite(m[c][r])) return false;
  return true;
}

Bounds transformBounds(const glm::mat4x3& m, const Bounds& b) {
  Bounds out;
  for (int corner = 0; corner < 8; ++corner) {
    const glm::vec3 p{(corner & 1) ? b.max.x : b.min.x, (corner & 2) ? b.max.y : b.min.y,
                      (corner & 4) ? b.max.z : b.min.z};
    out.extend(glm::vec3(m * glm::vec4(p, 1.0f)));
  }
  return out;
}

using Lanes = float __attribute__((vector_size(32)));
using IntLanes = int32_t __attribute__((vector_size(32)));
constexpr uint32_t kLanes = 8;

/// Levels of the instance tree at most, the boxes of its root level at most (kLanes groups), the
/// instances it holds at most, and the traversal stack that takes (the root level's boxes, then
/// each group entered replaces itself by at most kLanes groups of the level below).
constexpr uint32_t kMaxLevels = 7;
constexpr uint32_t kRootLanes = kLanes * kLanes;
constexpr uint64_t kMaxInstances = uint64_t{kRootLanes} << (3 * (kMaxLevels - 1));
constexpr uint32_t kStackSize = kRootLanes + (kLanes - 1) * (kMaxLevels - 1);

/// Eight instance boxes, one per lane ([axis] = x, y, z), and which ray masks reach each lane
/// (0 for unused lanes).
struct BoxGroup {
  Lanes min[3];
  Lanes max[3];
  IntLanes mask;
};

/// Bit i set where lane i of `lanes` (all ones or zero, as comparisons give) is set
/// (simd::vfloat8::mask, the kernels' movemask).
uint32_t laneBits(const IntLanes& lanes) { return static_cast<uint32_t>(std::bit_cast<simd::vfloat8>(lanes).mask()); }

/// A ray's slab-test terms, per axis, as groupEntries reads them.
struct RaySlab {
  int nearSide[3];
  float origin[3];
  float invDir[3];
  explicit RaySlab(const Ray& ray) {
    const bvh_detail::SlabRay slab(ray.origin, ray.dir);
    const int near[3] = {slab.nearX, slab.nearY, slab.nearZ};
    for (int axis = 0; axis < 3; ++axis) {
      nearSide[axis] = near[axis];
      origin[axis] = slab.origin[axis];
      invDir[axis] = slab.invDir[axis];
    }
  }
};

/// The lanes of `group` that the ray enters within [tmin, tmax] and whose mask matches rayMask,
/// as bits, with each lane's entry distance in `entry`: bvh_detail::slabEntry's operations lane
/// by lane (same values).
uint32_t groupEntries(const BoxGroup& group, const RaySlab& ray, float tmin, float tmax, uint32_t rayMask,
                      float (&entry)[kLanes]) {
  Lanes tNear = Lanes{} + tmin;
  Lanes tFar = Lanes{} + tmax;
  // Innermost axis first, as slabEntry nests maxKeep(nx, maxKeep(ny, maxKeep(nz, tmin))).
  for (int axis = 2; axis >= 0; --axis) {
    const Lanes& nearBound = ray.nearSide[axis] ? group.max[axis] : group.min[axis];
    const Lanes& farBound = ray.nearSide[axis] ? group.min[axis] : group.max[axis];
    const Lanes n = (nearBound - ray.origin[axis]) * ray.invDir[axis];
    const Lanes f = (farBound - ray.origin[axis]) * ray.invDir[axis];
    tNear = n > tNear ? n : tNear;
    tFar = f < tFar ? f : tFar;
  }
  tFar = tFar * bvh_detail::kRobustFarScale;
  std::memcpy(entry, &tNear, sizeof entry);
  return laneBits((tNear <= tFar) & ((group.mask & static_cast<int32_t>(rayMask)) != 0));
}

/// A box a ray enters: its entry distance, its level, and its index there (lane index % kLanes of
/// group index / kLanes; at level 0 the instance, above it the group of the level below).
struct Pending {
  float entry;
  uint32_t level, index;
};

/// Lane `lane`'s box of a group.
Bounds laneBox(const BoxGroup& group, uint32_t lane) {
  Bounds box;
  for (int axis = 0; axis < 3; ++axis) {
    box.min[axis] = group.min[axis][lane];
    box.max[axis] = group.max[axis][lane];
  }
  return box;
}

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

/// Spreads the low 10 bits of v to every third bit (a Morton code's axis).
uint32_t spreadBits(uint32_t v) {
  v &= 0x3ffu;
  v = (v | v << 16) & 0x030000ffu;
  v = (v | v << 8) & 0x0300f00fu;
  v = (v | v << 4) & 0x030c30c3u;
  v = (v | v << 2) & 0x09249249u;
  return v;
}

/// The Morton code of a box's centre on a 1024^3 grid over `scene`.
uint32_t mortonCode(const Bounds& box, const Bounds& scene) {
  uint32_t code = 0;
  for (int axis = 0; axis < 3; ++axis) {
    const float extent = scene.max[axis] - scene.min[axis];
    const float at = extent > 0.0f ? (box.center()[axis] - scene.min[axis]) / extent * 1024.0f : 0.0f;
    const uint32_t cell = at >= 1023.0f ? 1023u : at > 0.0f ? static_cast<uint32_t>(at) : 0u;   // NaN: 0
    code |= spreadBits(cell) << (2 - axis);
  }
  return code;
}

}  // namespace

/// A tree over instances: levels[0] bounds the instances 8 to a group, levels[levelCount - 1] is
/// the root level (at most kLanes groups, tested one after the other); lane j of group g bounds
/// group 8g + j of the level below.
struct InstanceTree {
  std::vector<PlacedInstance> instances;   // in Morton order of their boxes
  std::vector<Bounds> bounds;              // their world boxes, in the same order
  std::array<std::vector<BoxGroup>, kMaxLevels> levels;
  uint32_t levelCount = 0;

  /// Builds the levels over `instances` and `bounds` (their memory kept from one build to the next).
  void buildLevels() {
    levelCount = 0;
    size_t items = bounds.size(), itemsBelow = 0;
    while (items > 0) {
      std::vector<BoxGroup>& level = levels[levelCount];
      level.assign((items + kLanes - 1) / kLanes, BoxGroup{});   // unused lanes: mask 0
      for (size_t i = 0; i < items; ++i) {
        Bounds box;
        uint32_t mask = 0;
        if (levelCount == 0) {
          box = bounds[i];
          mask = instances[i].mask;
        } else {
          const BoxGroup& below = levels[levelCount - 1][i];
          for (uint32_t lane = 0; lane < kLanes && i * kLanes + lane < itemsBelow; ++lane) {
            box.extend(laneBox(below, lane));
            mask |= static_cast<uint32_t>(below.mask[lane]);
          }
        }
        BoxGroup& group = level[i / kLanes];
        const size_t lane = i % kLanes;
        for (int axis = 0; axis < 3; ++axis) {
          group.min[axis][lane] = box.min[axis];
          group.max[axis][lane] = box.max[axis];
        }
        group.mask[lane] = static_cast<int32_t>(mask);
      }
      ++levelCount;
      if (level.size() <= kLanes) break;
      itemsBelow = items;
      items = level.size();
    }
  }
};

struct Tlas::Impl {
  // Every instance with geometry but the world, which rays trace before walking this tree: the
  // world's box holds every other, so in a tree with it each ray entered its group only to skip it.
  InstanceTree movers;
  std::vector<PlacedInstance> validated;   // build()'s inputs with their inverses, one per input
  std::vector<uint32_t> kept;              // build scratch: the inputs with geometry
  std::vector<Bounds> unsortedBounds;      // build scratch: the world boxes of `kept`
  std::vector<uint64_t> keys;              // build scratch: Morton code << 32 | position in `kept`
  Bounds bounds;
  // The static world: the instance placed by the identity with the largest box (not in
  // `movers`), which every ray traces before walking the movers.
  bool haveWorld = false;
  PlacedInstance world;

  /// True when the world takes rays of rayMask.
  bool worldTakes(uint32_t rayMask) const { return haveWorld && (world.mask & rayMask) != 0; }

  /// Where a walk takes the world: first, or not at all (the caller traced it already).
  enum class WorldVisit { First, Traced };

  /// Visits the world first (worldVisit First, where it takes rayMask), then the movers whose
  /// boxes the ray enters, nearest box first among the root level's and then within each group
  /// entered, while their entry is within the ray's current tmax; visit(instance) returns true
  /// to stop.
  template <typename Visit>
  void forEachEntered(const Ray& ray, uint32_t rayMask, Visit&& visit, WorldVisit worldVisit) const {
    if (worldVisit == WorldVisit::First && worldTakes(rayMask) && visit(world)) return;
    const uint32_t levelCount = movers.levelCount;
    if (levelCount == 0) return;
    const RaySlab slab(ray);
    std::array<Pending, kStackSize> stack;
    uint32_t depth = 0;
    // Enters `groupCount` groups of `level` from `firstGroup`: visits the instances their boxes
    // hold (level 0) or stacks the groups below, nearest on top. True when visit() stopped.
    const auto enter = [&](uint32_t level, uint32_t firstGroup, uint32_t groupCount) {
      std::array<Pending, kRootLanes> entered;   // nearest first
      uint32_t count = 0;
      for (uint32_t g = firstGroup; g < firstGroup + groupCount; ++g) {
        float entry[kLanes];
        for (uint32_t bits = groupEntries(movers.levels[level][g], slab, ray.tmin, ray.tmax, rayMask, entry); bits;
             bits &= bits - 1) {
          const uint32_t lane = std::countr_zero(bits);
          uint32_t at = count++;
          for (; at > 0 && entered[at - 1].entry > entry[lane]; --at) entered[at] = entered[at - 1];
          entered[at] = {entry[lane], level, g * kLanes + lane};
        }
      }
      if (level == 0) {
        for (uint32_t i = 0; i < count; ++i) {
          // Every other box starts beyond the hit found (the far bound widened as slabEntry widens it).
          if (entered[i].entry > ray.tmax * bvh_detail::kRobustFarScale) break;
          if (visit(movers.instances[entered[i].index])) return true;
        }
        return false;
      }
      for (uint32_t i = count; i-- > 0;) stack[depth++] = entered[i];
      return false;
    };
    if (enter(levelCount - 1, 0, static_cast<uint32_t>(movers.levels[levelCount - 1].size()))) return;
    while (depth > 0) {
      const Pending node = stack[--depth];
      if (node.entry > ray.tmax * bvh_detail::kRobustFarScale) continue;   // nothing nearer inside
      if (enter(node.level - 1, node.index, 1)) return;
    }
  }

  Ray toObject(const PlacedInstance& inst, const Ray& ray) const {
    if (inst.identity) return ray;
    Ray r;
    toObject(inst, ray, r);
    return r;
  }
  /// toObject() of an instance that is not the identity, written into `out` in place (a packet's
  /// rays: a copy of a Ray just built on the stack reads its fields back wider than they were
  /// written, and stalls).
  void toObject(const PlacedInstance& inst, const Ray& ray, Ray& out) const {
    out.origin = inst.worldToObjectLinear * ray.origin + inst.worldToObjectOffset;
    out.tmin = ray.tmin;
    out.dir = inst.worldToObjectLinear * ray.dir;
    out.tmax = ray.tmax;
  }

  /// Any hit of a traceable ray over the instances of rayMask, the world as `worldVisit` says.
  bool occludedBy(const Ray& ray, uint32_t rayMask, const HitFilter& filter, WorldVisit worldVisit) const {
    bool found = false;
    forEachEntered(
        ray, rayMask,
        [&](const PlacedInstance& inst) {
          found = inst.blas->occluded(toObject(inst, ray), objectSpaceFilter(inst, filter), inst.index);
          return found;
        },
        worldVisit);
    return found;
  }
};

Tlas::Tlas() : impl_(std::make_unique<Impl>()) {}
Tlas::~Tlas() = default;
Tlas::Tlas(Tlas&&) noexcept = default;
Tlas& Tlas::operator=(Tlas&&) noexcept = default;

void Tlas::build(std::span<const TlasInstance> instances) {
  // Every input is checked (its inverse kept for the fill) before anything else changes: a throw
  // leaves the Tlas as it was but for that scratch.
  const auto fail = [](size_t i, const char* what) {
    throw std::invalid_argument("TlasInstance[" + std::to_string(i) + "]" + what);
  };
  if (instances.size() > kMaxInstances) throw std::invalid_argument("Tlas: more instances than it can hold");
  if (!impl_) impl_ = std::make_unique<Impl>();
  Impl& next = *impl_;
  std::vector<PlacedInstance>& placed = next.validated;   // each input with its inverse
  placed.clear();
  for (size_t i = 0; i < instances.size(); ++i) {
    const TlasInstance& in = instances[i];
    if (in.blas == nullptr) fail(i, ".blas is null");
    if (!finiteMatrix(in.objectToWorld)) fail(i, ".objectToWorld is not finite");
    const glm::mat3 linear(in.objectToWorld);
    const float det = glm::determinant(linear);
    if (!(std::fabs(det) > 0.0f) || !std::isfinite(det)) fail(i, ".objectToWorld is singular");
    const glm::mat3 inverse = glm::inverse(linear);
    const glm::vec3 offset = -(inverse * in.objectToWorld[3]);
    if (!std::isfinite(inverse[0][0] + inverse[1][1] + inverse[2][2] + offset.x + offset.y + offset.z))
      fail(i, ".objectToWorld has a non-finite inverse");
    placed.push_back({in.blas, inverse, offset, in.mask, static_cast<uint32_t>(i),
                      in.objectToWorld == glm::mat4x3(1.0f), det < 0.0f});
  }
  // Refilled in place: a rebuild over as many instances as the last allocates nothing.
  next.kept.clear();
  next.unsortedBounds.clear();
  next.bounds = Bounds{};
  for (size_t i = 0; i < instances.size(); ++i) {
    const TlasInstance& in = instances[i];
    const Bounds objectBounds = in.blas->bounds();
    if (objectBounds.empty()) continue;   // no geometry: never hit
    next.kept.push_back(static_cast<uint32_t>(i));
    next.unsortedBounds.push_back(transformBounds(in.objectToWorld, objectBounds));
    next.bounds.extend(next.unsortedBounds.back());
  }
  next.haveWorld = false;
  size_t worldAt = next.kept.size();
  for (size_t k = 0; k < next.kept.size(); ++k)
    if (placed[next.kept[k]].identity &&
        (worldAt == next.kept.size() || next.unsortedBounds[k].halfArea() > next.unsortedBounds[worldAt].halfArea()))
      worldAt = k;
  if (worldAt < next.kept.size()) {
    next.haveWorld = true;
    next.world = placed[next.kept[worldAt]];
  }
  // Instances in Morton order of their boxes' centres (equal codes in input order).
  next.keys.clear();
  for (uint32_t k = 0; k < next.kept.size(); ++k)
    next.keys.push_back(uint64_t{mortonCode(next.unsortedBounds[k], next.bounds)} << 32 | k);
  std::sort(next.keys.begin(), next.keys.end());
  next.movers.instances.clear();
  next.movers.bounds.clear();
  for (const uint64_t key : next.keys) {
    const uint32_t k = static_cast<uint32_t>(key);
    if (next.haveWorld && k == worldAt) continue;
    next.movers.instances.push_back(placed[next.kept[k]]);
    next.movers.bounds.push_back(next.unsortedBounds[k]);
  }
  next.movers.buildLevels();
}

bool Tlas::intersect(Ray& ray, Hit& hit, uint32_t rayMask, const HitFilter& filter) const {
  if (!impl_ || !bvh_detail::isTraceableRay(ray)) return false;
  bool found = false;
  const Impl& self = *impl_;
  // ray.tmax shrinks with each hit: forEachEntered reads it before entering the next instance.
  self.forEachEntered(
      ray, rayMask,
      [&](const PlacedInstance& inst) {
        Ray local = self.toObject(inst, ray);
        if (inst.blas->intersect(local, hit, objectSpaceFilter(inst, filter), inst.index)) {
          ray.tmax = local.tmax;
          found = true;
        }
        return false;
      },
      Impl::WorldVisit::First);
  return found;
}

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
  const auto traceInstance = [&](const PlacedInstance& inst, uint32_t live) {
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

bool Tlas::occluded(const Ray& ray, uint32_t rayMask, const HitFilter& filter) const {
  if (!impl_ || !bvh_detail::isTraceableRay(ray)) return false;
  return impl_->occludedBy(ray, rayMask, filter, Impl::WorldVisit::First);
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

Bounds Tlas::bounds() const { return impl_ ? impl_->bounds : Bounds{}; }

}  // namespace pa
