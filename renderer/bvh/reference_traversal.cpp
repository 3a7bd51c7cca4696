#include "renderer/bvh/reference_traversal.h"

#include <limits>

#include "renderer/bvh/binary_traversal.h"
#include "renderer/bvh/watertight.h"

namespace pa::bvh_detail {
namespace {

/// The reference query, closest hit or any hit: the binary tree front to back, each leaf's
/// triangles with the scalar watertight test. Closest hit (kAnyHit false) shortens tmax and
/// writes hit for every accepted hit; any hit stops at the first one and writes nothing.
template <bool kAnyHit>
bool traceReference(const TriangleMesh& mesh, const BinaryBvh& bvh, const Ray& ray, float& tmax, Hit& hit,
                    const HitFilter& filter, uint32_t instanceId) {
  const RayShear shear(ray.dir);
  const float cull = cullSign(filter.cull);
  bool found = false;
  traverseBinary(bvh, ray, tmax, [&](uint32_t first, uint32_t count) {
    for (uint32_t k = first; k < first + count; ++k) {
      const uint32_t tri = bvh.primIndices[k];
      if (mesh.degenerate[tri]) continue;
      TriangleHit th;
      if (!intersectTriangleWatertight(ray.origin, ray.dir, shear, ray.tmin, tmax, mesh.vertex(tri, 0),
                                       mesh.vertex(tri, 1), mesh.vertex(tri, 2), th))
        continue;
      if (mesh.isOneSided(tri) && th.det * cull < 0.0f) continue;   // the face the ray culls
      if (mesh.isFiltered(tri) && !filter(instanceId, tri, th.u, th.v, th.t)) continue;
      found = true;
      if constexpr (kAnyHit) return true;
      tmax = th.t;
      hit = {th.t, th.u, th.v, tri, instanceId};
    }
    return false;
  });
  return found;
}

}  // namespace

bool intersectReference(const TriangleMesh& mesh, const BinaryBvh& bvh, Ray& ray, Hit& hit,
                        const HitFilter& filter, uint32_t instanceId) {
  return traceReference<false>(mesh, bvh, ray, ray.tmax, hit, filter, instanceId);
}

bool occludedReference(const TriangleMesh& mesh, const BinaryBvh& bvh, const Ray& ray,
                       const HitFilter& filter, uint32_t instanceId) {
  float tmax = ray.tmax;
  Hit unused;
  return traceReference<true>(mesh, bvh, ray, tmax, unused, filter, instanceId);
}

}  // namespace pa::bvh_detail
