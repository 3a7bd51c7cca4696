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
// takes the ray as it is) and traces its Blas. A scattered instance (Blas::pieceBounds: a frame's
// marks and sprites over the whole map in one mesh) is in the tree once per piece's box, and a
// query traces it once, at the first of its pieces it enters. Packets: tlas_packet.cpp.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>

#include "renderer/bvh/bvh.h"
#include "renderer/bvh/slab_test.h"
#include "renderer/bvh/tlas_impl.h"
#include "renderer/bvh/triangle_mesh.h"

namespace pa {

using namespace tlas_detail;

namespace {

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
  // Refilled in place, with room for every piece a build may add: a rebuild over as many
  // instances as the last allocates nothing.
  next.reserveLeaves(instances.size() + kMaxPieceGroups * (kMaxBlasPieces - 1));
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
  // Scattered instances (a frame's marks and sprites over the whole map, in one mesh) by their
  // pieces' boxes: by its whole box such an instance was entered by most rays and hit by few.
  next.pieceGroups.assign(next.kept.size(), kWholeInstance);
  std::array<Bounds, kMaxBlasPieces> pieces;
  uint32_t groups = 0;
  for (size_t k = 0, whole = next.kept.size(); k < whole && groups < kMaxPieceGroups; ++k) {
    if (k == worldAt) continue;
    const uint32_t input = next.kept[k];
    const size_t count = instances[input].blas->pieceBounds(pieces);
    if (count == 0) continue;
    const auto group = static_cast<uint8_t>(groups++);
    next.unsortedBounds[k] = transformBounds(instances[input].objectToWorld, pieces[0]);
    next.pieceGroups[k] = group;
    for (size_t p = 1; p < count; ++p) {
      next.kept.push_back(input);
      next.unsortedBounds.push_back(transformBounds(instances[input].objectToWorld, pieces[p]));
      next.pieceGroups.push_back(group);
    }
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
    next.movers.instances.back().pieceGroup = next.pieceGroups[k];
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

bool Tlas::occluded(const Ray& ray, uint32_t rayMask, const HitFilter& filter) const {
  if (!impl_ || !bvh_detail::isTraceableRay(ray)) return false;
  return impl_->occludedBy(ray, rayMask, filter, Impl::WorldVisit::First);
}

Bounds Tlas::bounds() const { return impl_ ? impl_->bounds : Bounds{}; }

}  // namespace pa
