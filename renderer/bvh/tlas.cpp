// Tlas: the instances' world bounds, tested all at once in 8-lane groups when there are at most
// kFlatInstances of them (a game frame's movers, items and effect batches), else through a binary
// BVH over them. Either way instances are entered nearest box first; each transforms the ray into
// object space (without normalising the direction, so t stays the world-space t) and traces its Blas.
#include <algorithm>
#include <array>
#include <bit>
#include <limits>
#include <memory>
#include <cmath>
#include <cstdint>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>

#include "renderer/bvh/binary_bvh.h"
#include "renderer/bvh/binary_traversal.h"
#include "renderer/bvh/bvh.h"
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
    for (uint32_t lane = 0; lane < kLanes; ++lane)
      if (entered[lane]) out[count++] = {tNear[lane], g * kLanes + lane};
  }
  return count;
}

/// Interval bounds of a packet of rays that share one octant (finite inverse directions): a box
/// that no origin in [oLo, oHi] along no inverse direction in [iLo, iHi] enters is culled for
/// the whole packet before any ray is tested on its own.
struct PacketInterval {
  float oLo[3], oHi[3], iLo[3], iHi[3];
  float tminLo = std::numeric_limits<float>::infinity();
  int nearSide[3] = {0, 0, 0};
  bool valid = false;   ///< False when the rays span octants or run along an axis plane.
};

/// inverse[axis][lane]: 1 / rays[lane].dir[axis] for the lanes given.
PacketInterval packetInterval(std::span<const Ray> rays, uint32_t lanes, const float (&inverse)[3][kMaxPacketRays]) {
  PacketInterval p;
  for (int axis = 0; axis < 3; ++axis) {
    p.oLo[axis] = p.iLo[axis] = std::numeric_limits<float>::infinity();
    p.oHi[axis] = p.iHi[axis] = -std::numeric_limits<float>::infinity();
  }
  int octant = -1;
  for (uint32_t r = lanes; r; r &= r - 1) {
    const Ray& ray = rays[std::countr_zero(r)];
    const int o = std::signbit(ray.dir.x) | std::signbit(ray.dir.y) << 1 | std::signbit(ray.dir.z) << 2;
    if (octant >= 0 && o != octant) return p;
    octant = o;
    for (int axis = 0; axis < 3; ++axis) {
      const float inv = inverse[axis][std::countr_zero(r)];
      if (ray.dir[axis] == 0.0f || !std::isfinite(inv)) return p;
      p.oLo[axis] = std::min(p.oLo[axis], ray.origin[axis]);
      p.oHi[axis] = std::max(p.oHi[axis], ray.origin[axis]);
      p.iLo[axis] = std::min(p.iLo[axis], inv);
      p.iHi[axis] = std::max(p.iHi[axis], inv);
    }
    p.tminLo = std::min(p.tminLo, ray.tmin);
  }
  for (int axis = 0; axis < 3; ++axis) p.nearSide[axis] = (octant >> axis) & 1;
  p.valid = octant >= 0;
  return p;
}

/// False only when no ray of the packet can enter the box before tmaxHi: (bound - origin) *
/// inverse bounded over the intervals' corners, as each ray's slab test rounds it (rounding is
/// monotonic, so the bounds hold for the rounded per-ray values too).
bool packetMayEnter(const PacketInterval& p, const Bounds& box, float tmaxHi) {
  float tNear = p.tminLo, tFar = tmaxHi;
  for (int axis = 0; axis < 3; ++axis) {
    const float nearBound = p.nearSide[axis] ? box.max[axis] : box.min[axis];
    const float farBound = p.nearSide[axis] ? box.min[axis] : box.max[axis];
    const float n0 = nearBound - p.oHi[axis], n1 = nearBound - p.oLo[axis];
    const float f0 = farBound - p.oHi[axis], f1 = farBound - p.oLo[axis];
    tNear = std::max({tNear, std::min({n0 * p.iLo[axis], n0 * p.iHi[axis], n1 * p.iLo[axis], n1 * p.iHi[axis]})});
    tFar = std::min({tFar, std::max({f0 * p.iLo[axis], f0 * p.iHi[axis], f1 * p.iLo[axis], f1 * p.iHi[axis]})});
  }
  return tNear <= tFar * bvh_detail::kRobustFarScale;
}

/// A packet's rays as lanes (structure of arrays), with their inverse directions and near box
/// sides; idle lanes hold a ray that enters no box (tmin > tmax).
struct PacketLanes {
  alignas(64) float origin[3][kMaxPacketRays];
  alignas(64) float inverse[3][kMaxPacketRays];
  alignas(64) int nearSide[3][kMaxPacketRays];   ///< 1: the box's max is the near plane.
  alignas(64) float tmin[kMaxPacketRays], tmax[kMaxPacketRays];
};

PacketLanes packetLanes(std::span<const Ray> rays, uint32_t traceable) {
  PacketLanes p;
  alignas(64) float direction[3][kMaxPacketRays];
  for (uint32_t lane = 0; lane < kMaxPacketRays; ++lane) {
    const bool live = traceable >> lane & 1;
    for (int axis = 0; axis < 3; ++axis) {
      p.origin[axis][lane] = live ? rays[lane].origin[axis] : 0.0f;
      direction[axis][lane] = live ? rays[lane].dir[axis] : 1.0f;
      p.nearSide[axis][lane] = std::signbit(direction[axis][lane]);
    }
    p.tmin[lane] = live ? rays[lane].tmin : 1.0f;
    p.tmax[lane] = live ? rays[lane].tmax : 0.0f;
  }
  for (int axis = 0; axis < 3; ++axis)
    for (uint32_t lane = 0; lane < kMaxPacketRays; ++lane) p.inverse[axis][lane] = 1.0f / direction[axis][lane];
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
    Ray r;
    toObject(inst, ray, r);
    return r;
  }
  /// toObject() written into `out` in place (a packet's rays: a copy of a Ray just built on the
  /// stack reads its fields back wider than they were written, and stalls).
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
    placed.push_back({in.blas, inverse, offset, in.mask, static_cast<uint32_t>(i), det < 0.0f});
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
  uint32_t traceable = 0;
  for (uint32_t r = active; r; r &= r - 1)
    if (bvh_detail::isTraceableRay(rays[std::countr_zero(r)])) traceable |= 1u << std::countr_zero(r);
  uint32_t found = 0;
  if (self.groups.empty() || std::popcount(traceable) < 2) {   // many instances, or one ray: ray by ray
    for (uint32_t r = traceable; r; r &= r - 1) {
      const int lane = std::countr_zero(r);
      if (intersect(rays[lane], hits[lane], rayMask, filters[lane])) found |= 1u << lane;
    }
    return found;
  }
  // Which rays enter which instance box (each ray's own slab test, as forEachEntered's), after
  // the packet's interval test has culled the boxes no ray can enter.
  // The rays as lanes (idle lanes: a ray along +1 that enters nothing), so the loops below
  // vectorise: the inverse directions are divided once for the packet's interval and the slab
  // tests, and each instance box is tested against all rays at once.
  const PacketLanes lanes = packetLanes(rays, traceable);
  const PacketInterval interval = packetInterval(rays, traceable, lanes.inverse);
  float tmaxHi = -std::numeric_limits<float>::infinity();
  for (uint32_t r = traceable; r; r &= r - 1) tmaxHi = std::max(tmaxHi, rays[std::countr_zero(r)].tmax);
  std::array<PacketCandidate, kFlatInstances> candidates;
  uint32_t count = 0;
  for (uint32_t k = 0; k < self.instances.size(); ++k) {
    if ((self.instances[k].mask & rayMask) == 0) continue;
    const Bounds& box = self.worldBounds[k];
    if (interval.valid && !packetMayEnter(interval, box, tmaxHi)) continue;
    PacketCandidate& c = candidates[count];
    c.instance = k;
    slabEntries(lanes, box, c.entry);
    uint32_t entered = 0;   // in registers, not through c (a chain of stores and reloads)
    float nearest = std::numeric_limits<float>::infinity();
    for (uint32_t lane = 0; lane < kMaxPacketRays; ++lane) {
      const float entry = c.entry[lane];
      entered |= uint32_t{entry != std::numeric_limits<float>::infinity()} << lane;
      nearest = std::min(nearest, traceable >> lane & 1 ? entry : std::numeric_limits<float>::infinity());
    }
    c.rays = entered & traceable;
    c.nearest = nearest;
    if (c.rays) ++count;
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
