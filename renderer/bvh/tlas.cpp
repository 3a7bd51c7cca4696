// Tlas: the instances' world bounds, tested all at once in 8-lane groups when there are at most
// kFlatInstances of them (a game frame's movers, items and effect batches), else through a binary
// BVH over them. Either way instances are entered nearest box first; each transforms the ray into
// object space (without normalising the direction, so t stays the world-space t; an instance placed
// by the identity, the static world, takes the ray as it is) and traces its Blas.
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

#include "renderer/bvh/binary_bvh.h"
#include "renderer/bvh/binary_traversal.h"
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

/// Instance counts up to this are tested without a hierarchy (8 groups of 8 lanes).
constexpr size_t kFlatInstances = 64;

using Lanes = float __attribute__((vector_size(32)));
using IntLanes = int32_t __attribute__((vector_size(32)));
constexpr uint32_t kLanes = 8;

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

/// A box the ray enters: its entry distance and its instance.
struct Candidate {
  float entry;
  uint32_t instance;
};

/// The boxes of `groups` that the ray enters within [tmin, tmax] and whose mask matches, with
/// their entry distances: bvh_detail::slabEntry's operations lane by lane (same values).
uint32_t enteredBoxes(std::span<const BoxGroup> groups, const Ray& ray, float tmax, uint32_t rayMask,
                      std::array<Candidate, kFlatInstances>& out) {
  const bvh_detail::SlabRay slab(ray.origin, ray.dir);
  const int nearSide[3] = {slab.nearX, slab.nearY, slab.nearZ};
  const float origin[3] = {slab.origin.x, slab.origin.y, slab.origin.z};
  const float invDir[3] = {slab.invDir.x, slab.invDir.y, slab.invDir.z};
  uint32_t count = 0;
  for (uint32_t g = 0; g < groups.size(); ++g) {
    const BoxGroup& group = groups[g];
    Lanes tNear = Lanes{} + ray.tmin;
    Lanes tFar = Lanes{} + tmax;
    // Innermost axis first, as slabEntry nests maxKeep(nx, maxKeep(ny, maxKeep(nz, tmin))).
    for (int axis = 2; axis >= 0; --axis) {
      const Lanes& nearBound = nearSide[axis] ? group.max[axis] : group.min[axis];
      const Lanes& farBound = nearSide[axis] ? group.min[axis] : group.max[axis];
      const Lanes n = (nearBound - origin[axis]) * invDir[axis];
      const Lanes f = (farBound - origin[axis]) * invDir[axis];
      tNear = n > tNear ? n : tNear;
      tFar = f < tFar ? f : tFar;
    }
    tFar = tFar * bvh_detail::kRobustFarScale;
    const IntLanes entered = (tNear <= tFar) & ((group.mask & static_cast<int32_t>(rayMask)) != 0);
    // The entered lanes as bits (no branch per lane: a ray enters one to three boxes of 64).
    for (uint32_t bits = laneBits(entered); bits; bits &= bits - 1) {
      const uint32_t lane = std::countr_zero(bits);
      out[count++] = {tNear[lane], g * kLanes + lane};
    }
  }
  return count;
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

/// An instance some rays of a packet enter: each ray's entry distance (inf: not entered).
struct PacketCandidate {
  float nearest;
  uint32_t instance;
  uint32_t rays;
  std::array<float, kMaxPacketRays> entry;
};

/// Removes and returns the nearest candidate (the first of equal ones).
Candidate takeNearest(std::array<Candidate, kFlatInstances>& candidates, uint32_t& count) {
  uint32_t best = 0;
  for (uint32_t i = 1; i < count; ++i)
    if (candidates[i].entry < candidates[best].entry) best = i;
  const Candidate nearest = candidates[best];
  for (uint32_t i = best + 1; i < count; ++i) candidates[i - 1] = candidates[i];
  --count;
  return nearest;
}

}  // namespace

struct Tlas::Impl {
  std::vector<PlacedInstance> instances;   // only instances with geometry, in BVH leaf order source
  bvh_detail::BinaryBvh bvh;               // built when there are more than kFlatInstances
  std::vector<BoxGroup> groups;            // the instances' boxes, 8 to a group, when at most kFlatInstances
  std::vector<Bounds> worldBounds;         // the instances' boxes (the BVH's input beyond kFlatInstances)
  bvh_detail::BinaryBuildScratch scratch;  // the BVH builder's memory, kept between builds
  std::vector<PlacedInstance> validated;   // build()'s inputs with their inverses, one per input
  Bounds bounds;

  /// Visits the instances whose boxes the ray enters, nearest box first, while their entry is
  /// within the ray's current tmax; visit(instance) returns true to stop.
  template <typename Visit>
  void forEachEntered(const Ray& ray, uint32_t rayMask, Visit&& visit) const {
    if (groups.empty()) {
      bvh_detail::traverseBinary(bvh, ray, ray.tmax, [&](uint32_t first, uint32_t count) {
        for (uint32_t k = first; k < first + count; ++k) {
          const PlacedInstance& inst = instances[bvh.primIndices[k]];
          if ((inst.mask & rayMask) != 0 && visit(inst)) return true;
        }
        return false;
      });
      return;
    }
    std::array<Candidate, kFlatInstances> candidates;
    uint32_t count = enteredBoxes(groups, ray, ray.tmax, rayMask, candidates);
    while (count > 0) {
      const Candidate next = takeNearest(candidates, count);
      // Every other box starts beyond the hit found (the far bound widened as slabEntry widens it).
      if (next.entry > ray.tmax * bvh_detail::kRobustFarScale) return;
      if (visit(instances[next.instance])) return;
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
  next.instances.clear();
  next.worldBounds.clear();
  next.groups.clear();
  next.bounds = Bounds{};
  for (size_t i = 0; i < instances.size(); ++i) {
    const TlasInstance& in = instances[i];
    const Bounds objectBounds = in.blas->bounds();
    if (objectBounds.empty()) continue;   // no geometry: never hit
    next.instances.push_back(placed[i]);
    next.worldBounds.push_back(transformBounds(in.objectToWorld, objectBounds));
    next.bounds.extend(next.worldBounds.back());
  }
  const std::vector<Bounds>& worldBounds = next.worldBounds;
  if (worldBounds.size() <= kFlatInstances) {
    next.bvh.nodes.clear();
    next.bvh.primIndices.clear();
    next.bvh.nodeCount = next.bvh.leafCount = 0;
    next.groups.resize((worldBounds.size() + kLanes - 1) / kLanes);
    for (BoxGroup& group : next.groups) group = BoxGroup{};   // unused lanes: mask 0
    for (size_t i = 0; i < worldBounds.size(); ++i) {
      BoxGroup& group = next.groups[i / kLanes];
      const size_t lane = i % kLanes;
      for (int axis = 0; axis < 3; ++axis) {
        group.min[axis][lane] = worldBounds[i].min[axis];
        group.max[axis][lane] = worldBounds[i].max[axis];
      }
      group.mask[lane] = static_cast<int32_t>(next.instances[i].mask);
    }
  } else {
    BvhBuildConfig config;
    config.maxLeafTriangles = 1;
    bvh_detail::buildBinaryBvh(worldBounds, config, next.scratch, next.bvh);
  }
}

bool Tlas::intersect(Ray& ray, Hit& hit, uint32_t rayMask, const HitFilter& filter) const {
  if (!impl_ || !bvh_detail::isTraceableRay(ray)) return false;
  bool found = false;
  const Impl& self = *impl_;
  // ray.tmax shrinks with each hit: forEachEntered reads it before entering the next instance.
  self.forEachEntered(ray, rayMask, [&](const PlacedInstance& inst) {
    Ray local = self.toObject(inst, ray);
    if (inst.blas->intersect(local, hit, objectSpaceFilter(inst, filter), inst.index)) {
      ray.tmax = local.tmax;
      found = true;
    }
    return false;
  });
  return found;
}

uint32_t Tlas::intersectPacket(std::span<Ray> rays, std::span<Hit> hits, uint32_t active, uint32_t rayMask,
                               std::span<const HitFilter> filters) const {
  active &= (1u << kMaxPacketRays) - 1;
  const uint32_t highest = active ? 32 - std::countl_zero(active) : 0;
  if (rays.size() < highest || hits.size() < highest || filters.size() < highest)
    throw std::invalid_argument("Tlas::intersectPacket: spans shorter than the active rays");
  if (!impl_) return 0;
  const Impl& self = *impl_;
  const PacketLanes lanes = packetLanes(rays, active);
  const uint32_t traceable = lanes.traceable;
  uint32_t found = 0;
  if (self.groups.empty() || std::popcount(traceable) < 2) {   // many instances, or one ray: ray by ray
    for (uint32_t r = traceable; r; r &= r - 1) {
      const int lane = std::countr_zero(r);
      if (intersect(rays[lane], hits[lane], rayMask, filters[lane])) found |= 1u << lane;
    }
    return found;
  }
  // Which rays enter which instance box (each ray's own slab test, as forEachEntered's), after
  // the packet's interval test has culled the boxes no ray can enter; both over the lanes built
  // above (inverse directions divided once), each box against all rays at once.
  const PacketInterval interval = packetInterval(lanes, traceable);
  const IntLanes tracedLanes[kHalves] = {laneMask(traceable), laneMask(traceable >> kLanes)};
  std::array<PacketCandidate, kFlatInstances> candidates;
  uint32_t count = 0;
  // The packet's interval culls eight boxes at a time; the boxes left are tested ray by ray.
  const IntLanes noBox{};
  for (uint32_t g = 0; g < self.groups.size(); ++g) {
    const BoxGroup& group = self.groups[g];
    const uint32_t boxes = interval.valid ? groupMayEnter(interval, group, rayMask)
                                          : laneBits((group.mask & static_cast<int32_t>(rayMask)) != noBox);
    for (uint32_t b = boxes; b; b &= b - 1) {
      const uint32_t k = g * kLanes + std::countr_zero(b);
      PacketCandidate& c = candidates[count];
      c.instance = k;
      slabEntries(lanes, self.worldBounds[k], c.entry);
      const Lanes kInfs = Lanes{} + std::numeric_limits<float>::infinity();
      const Lanes entryA = loadLanes(c.entry.data()), entryB = loadLanes(c.entry.data() + kLanes);
      c.rays = (laneBits(entryA != kInfs) | laneBits(entryB != kInfs) << kLanes) & traceable;
      const Lanes nearA = tracedLanes[0] ? entryA : kInfs, nearB = tracedLanes[1] ? entryB : kInfs;
      c.nearest = minOf(nearA < nearB ? nearA : nearB);
      if (c.rays) ++count;
    }
  }
  // Nearest box first (over the packet's rays); each ray enters only while its entry is within
  // its current tmax, as forEachEntered stops a single ray.
  std::sort(candidates.begin(), candidates.begin() + count, [](const PacketCandidate& a, const PacketCandidate& b) {
    return a.nearest < b.nearest || (a.nearest == b.nearest && a.instance < b.instance);
  });
  std::array<Ray, kMaxPacketRays> local;
  std::array<HitFilter, kMaxPacketRays> mirroredFilters;   // filled at the first mirrored instance
  bool haveMirroredFilters = false;
  for (uint32_t i = 0; i < count; ++i) {
    const PacketCandidate& c = candidates[i];
    uint32_t live = 0;
    for (uint32_t r = c.rays; r; r &= r - 1) {
      const int lane = std::countr_zero(r);
      if (c.entry[lane] > rays[lane].tmax * bvh_detail::kRobustFarScale) continue;
      live |= 1u << lane;
    }
    if (!live) continue;
    const PlacedInstance& inst = self.instances[c.instance];
    if (inst.identity) {   // the static world: its rays as they are (a hit shortens their tmax)
      found |= inst.blas->intersectPacket(rays, hits, live, filters, inst.index);
      continue;
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
  }
  return found;
}

bool Tlas::occluded(const Ray& ray, uint32_t rayMask, const HitFilter& filter) const {
  if (!impl_ || !bvh_detail::isTraceableRay(ray)) return false;
  bool found = false;
  const Impl& self = *impl_;
  self.forEachEntered(ray, rayMask, [&](const PlacedInstance& inst) {
    found = inst.blas->occluded(self.toObject(inst, ray), objectSpaceFilter(inst, filter), inst.index);
    return found;
  });
  return found;
}

Bounds Tlas::bounds() const { return impl_ ? impl_->bounds : Bounds{}; }

}  // namespace pa
