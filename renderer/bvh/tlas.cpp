// Tlas: binary BVH over instance world bounds; leaves transform the ray into object space
// (without normalising the direction, so t stays the world-space t) and trace the Blas.
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>

#include "renderer/bvh/binary_bvh.h"
#include "renderer/bvh/binary_traversal.h"
#include "renderer/bvh/bvh.h"
#include "renderer/bvh/triangle_mesh.h"

namespace pa {
namespace {

struct PlacedInstance {
  const Blas* blas = nullptr;
  glm::mat3 worldToObjectLinear{1.0f};
  glm::vec3 worldToObjectOffset{0.0f};
  uint32_t mask = 0;
  uint32_t index = 0;   // position in the span given to build()
};

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

}  // namespace

struct Tlas::Impl {
  std::vector<PlacedInstance> instances;   // only instances with geometry, in BVH leaf order source
  bvh_detail::BinaryBvh bvh;
  Bounds bounds;

  Ray toObject(const PlacedInstance& inst, const Ray& ray) const {
    Ray r = ray;
    r.origin = inst.worldToObjectLinear * ray.origin + inst.worldToObjectOffset;
    r.dir = inst.worldToObjectLinear * ray.dir;
    return r;
  }
};

Tlas::Tlas() : impl_(std::make_unique<Impl>()) {}
Tlas::~Tlas() = default;
Tlas::Tlas(Tlas&&) noexcept = default;
Tlas& Tlas::operator=(Tlas&&) noexcept = default;

void Tlas::build(std::span<const TlasInstance> instances) {
  auto next = std::make_unique<Impl>();
  std::vector<Bounds> worldBounds;
  for (size_t i = 0; i < instances.size(); ++i) {
    const TlasInstance& in = instances[i];
    const std::string where = "TlasInstance[" + std::to_string(i) + "]";
    if (in.blas == nullptr) throw std::invalid_argument(where + ".blas is null");
    if (!finiteMatrix(in.objectToWorld)) throw std::invalid_argument(where + ".objectToWorld is not finite");
    const glm::mat3 linear(in.objectToWorld);
    const float det = glm::determinant(linear);
    if (!(std::fabs(det) > 0.0f) || !std::isfinite(det))
      throw std::invalid_argument(where + ".objectToWorld is singular");
    const glm::mat3 inverse = glm::inverse(linear);
    const glm::vec3 offset = -(inverse * in.objectToWorld[3]);
    if (!std::isfinite(inverse[0][0] + inverse[1][1] + inverse[2][2] + offset.x + offset.y + offset.z))
      throw std::invalid_argument(where + ".objectToWorld has a non-finite inverse");
    const Bounds objectBounds = in.blas->bounds();
    if (objectBounds.empty()) continue;   // no geometry: never hit
    next->instances.push_back({in.blas, inverse, offset, in.mask, static_cast<uint32_t>(i)});
    worldBounds.push_back(transformBounds(in.objectToWorld, objectBounds));
    next->bounds.extend(worldBounds.back());
  }
  BvhBuildConfig config;
  config.maxLeafTriangles = 1;
  next->bvh = bvh_detail::buildBinaryBvh(worldBounds, config);
  impl_ = std::move(next);
}

bool Tlas::intersect(Ray& ray, Hit& hit, uint32_t rayMask, const HitFilter& filter) const {
  if (!impl_ || !bvh_detail::isTraceableRay(ray)) return false;
  bool found = false;
  const Impl& self = *impl_;
  bvh_detail::traverseBinary(self.bvh, ray, ray.tmax, [&](uint32_t first, uint32_t count) {
    for (uint32_t k = first; k < first + count; ++k) {
      const PlacedInstance& inst = self.instances[self.bvh.primIndices[k]];
      if ((inst.mask & rayMask) == 0) continue;
      Ray local = self.toObject(inst, ray);
      if (inst.blas->intersect(local, hit, filter, inst.index)) {
        ray.tmax = local.tmax;
        found = true;
      }
    }
    return false;
  });
  return found;
}

bool Tlas::occluded(const Ray& ray, uint32_t rayMask, const HitFilter& filter) const {
  if (!impl_ || !bvh_detail::isTraceableRay(ray)) return false;
  bool found = false;
  const Impl& self = *impl_;
  bvh_detail::traverseBinary(self.bvh, ray, ray.tmax, [&](uint32_t first, uint32_t count) {
    for (uint32_t k = first; k < first + count; ++k) {
      const PlacedInstance& inst = self.instances[self.bvh.primIndices[k]];
      if ((inst.mask & rayMask) == 0) continue;
      if (inst.blas->occluded(self.toObject(inst, ray), filter, inst.index)) {
        found = true;
        return true;
      }
    }
    return false;
  });
  return found;
}

Bounds Tlas::bounds() const { return impl_ ? impl_->bounds : Bounds{}; }

}  // namespace pa
