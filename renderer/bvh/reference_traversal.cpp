#include "renderer/bvh/reference_traversal.h"

#include <limits>

#include "renderer/bvh/binary_traversal.h"
#include "renderer/bvh/watertight.h"

namespace pa::bvh_detail {

bool intersectReference(const TriangleMesh& mesh, const BinaryBvh& bvh, Ray& ray, Hit& hit,
                        const HitFilter& filter, uint32_t instanceId) {
  const RayShear shear(ray.dir);
  bool found = false;
  traverseBinary(bvh, ray, ray.tmax, [&](uint32_t first, uint32_t count) {
    for (uint32_t k = first; k < first + count; ++k) {
      const uint32_t tri = bvh.primIndices[k];
      if (mesh.degenerate[tri]) continue;
      TriangleHit th;
      if (!intersectTriangleWatertight(ray.origin, ray.dir, shear, ray.tmin, ray.tmax, mesh.vertex(tri, 0),
                                       mesh.vertex(tri, 1), mesh.vertex(tri, 2), th))
        continue;
      if (mesh.isMasked(tri) && !filter(instanceId, tri, th.u, th.v)) continue;
      ray.tmax = th.t;
      hit = {th.t, th.u, th.v, tri, instanceId};
      found = true;
    }
    return false;
  });
  return found;
}

bool occludedReference(const TriangleMesh& mesh, const BinaryBvh& bvh, const Ray& ray,
                       const HitFilter& filter, uint32_t instanceId) {
  const RayShear shear(ray.dir);
  bool found = false;
  traverseBinary(bvh, ray, ray.tmax, [&](uint32_t first, uint32_t count) {
    for (uint32_t k = first; k < first + count; ++k) {
      const uint32_t tri = bvh.primIndices[k];
      if (mesh.degenerate[tri]) continue;
      TriangleHit th;
      if (!intersectTriangleWatertight(ray.origin, ray.dir, shear, ray.tmin, ray.tmax, mesh.vertex(tri, 0),
                                       mesh.vertex(tri, 1), mesh.vertex(tri, 2), th))
        continue;
      if (mesh.isMasked(tri) && !filter(instanceId, tri, th.u, th.v)) continue;
      found = true;
      return true;
    }
    return false;
  });
  return found;
}

}  // namespace pa::bvh_detail
