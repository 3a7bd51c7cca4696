#pragma once
// What the Tlas's two files share (tlas.cpp: the build and single rays; tlas_packet.cpp: packets
// and their cull): the placed instances, the 8-lane box groups of the instance tree and the
// state a build leaves. Internal to renderer/bvh.
#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <cstring>
#include <vector>

#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>

#include "renderer/bvh/bvh.h"
#include "renderer/bvh/simd.h"
#include "renderer/bvh/slab_test.h"

namespace pa::tlas_detail {

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
  // kWholeInstance, or which scattered instance this is (Blas::pieceBounds): such an instance is
  // in the tree once per piece's box, and a query traces it once, at the first piece it enters.
  uint8_t pieceGroup = 0xff;
};

/// PlacedInstance::pieceGroup of an instance in the tree by its whole box.
constexpr uint8_t kWholeInstance = 0xff;
/// Scattered instances at most that a build puts in the tree by their pieces (a query keeps
/// which it traced in one bit or one lane mask each).
constexpr uint32_t kMaxPieceGroups = 32;

/// The filter a ray takes into an instance: its face culling seen from object space.
inline HitFilter objectSpaceFilter(const PlacedInstance& inst, const HitFilter& filter) {
  if (!inst.mirrored || filter.cull == FaceCull::None) return filter;
  HitFilter flipped = filter;
  flipped.cull = filter.cull == FaceCull::Back ? FaceCull::Front : FaceCull::Back;
  return flipped;
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
inline uint32_t laneBits(const IntLanes& lanes) { return static_cast<uint32_t>(std::bit_cast<simd::vfloat8>(lanes).mask()); }

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
inline uint32_t groupEntries(const BoxGroup& group, const RaySlab& ray, float tmin, float tmax, uint32_t rayMask,
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
inline Bounds laneBox(const BoxGroup& group, uint32_t lane) {
  Bounds box;
  for (int axis = 0; axis < 3; ++axis) {
    box.min[axis] = group.min[axis][lane];
    box.max[axis] = group.max[axis][lane];
  }
  return box;
}

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

/// What a build leaves for the queries (Tlas::Impl).
struct TlasState {
  // Every instance with geometry but the world, which rays trace before walking this tree: the
  // world's box holds every other, so in a tree with it each ray entered its group only to skip it.
  InstanceTree movers;
  std::vector<PlacedInstance> validated;   // build()'s inputs with their inverses, one per input
  std::vector<uint32_t> kept;              // build scratch: the inputs with geometry
  std::vector<Bounds> unsortedBounds;      // build scratch: the world boxes of `kept`
  std::vector<uint64_t> keys;              // build scratch: Morton code << 32 | position in `kept`
  std::vector<uint8_t> pieceGroups;        // build scratch: each of `kept`'s pieceGroup
  Bounds bounds;
  // The static world: the instance placed by the identity with the largest box (not in
  // `movers`), which every ray traces before walking the movers.
  bool haveWorld = false;
  PlacedInstance world;

  /// Room in the build's arrays for a tree of `leaves` boxes.
  void reserveLeaves(size_t leaves) {
    kept.reserve(leaves);
    unsortedBounds.reserve(leaves);
    keys.reserve(leaves);
    pieceGroups.reserve(leaves);
    movers.instances.reserve(leaves);
    movers.bounds.reserve(leaves);
    for (size_t level = 0, items = leaves; level < kMaxLevels && items > 0; ++level) {
      items = (items + kLanes - 1) / kLanes;
      movers.levels[level].reserve(items);
      if (items <= kLanes) break;
    }
  }

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
    uint32_t piecesVisited = 0;   // the scattered instances visited, by pieceGroup
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
          const PlacedInstance& inst = movers.instances[entered[i].index];
          if (inst.pieceGroup != kWholeInstance) {
            if (piecesVisited >> inst.pieceGroup & 1) continue;
            piecesVisited |= 1u << inst.pieceGroup;
          }
          if (visit(inst)) return true;
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

}  // namespace pa::tlas_detail

namespace pa {

struct Tlas::Impl : tlas_detail::TlasState {};

}  // namespace pa
