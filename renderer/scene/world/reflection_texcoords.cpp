// RenderScene::surfaceAt along a ray: base and shine texture coordinates of TexCoordSource::ReflectionSphere.
#include <cmath>
#include <cstddef>

#include <glm/geometric.hpp>
#include <glm/mat2x2.hpp>
#include <glm/mat3x3.hpp>

#include "renderer/scene/textures/reflection_uv.h"
#include "renderer/scene/world/render_scene.h"

namespace pa {

SurfaceHit RenderScene::surfaceAt(const Hit& hit, bool overlayHit, const Ray& ray, SurfaceParts parts,
                                  TriangleMemo* memo) const {
  SurfaceHit s = surfaceAt(hit, overlayHit, parts, memo);
  if (s.material == nullptr || s.instance == nullptr) return s;
  const MaterialDesc& desc = s.material->desc;
  const bool baseReflects = desc.baseTexCoords == TexCoordSource::ReflectionSphere;
  const bool shineReflects = s.material->shine != nullptr && desc.stock.shineTexCoords == TexCoordSource::ReflectionSphere;
  if (!baseReflects && !shineReflects) return s;
  const RenderInstance& inst = *s.instance;
  const MeshGeometry& g = inst.mesh->geometry;
  const size_t first = 3 * size_t{hit.prim};
  const uint32_t corner[3] = {g.indices[first], g.indices[first + 1], g.indices[first + 2]};

  // World to object space: normalToWorld is the inverse transpose of the linear part, so its
  // transpose is that part's inverse.
  const glm::mat3 worldToObject = glm::transpose(inst.normalToWorld);
  const glm::vec3 objectOrigin = worldToObject * (ray.origin - glm::vec3(inst.objectToWorld[3]));
  const glm::vec3 toViewer = worldToObject * -ray.dir;

  const glm::vec3& p0 = g.positions[corner[0]];
  const glm::vec3 winding = glm::cross(g.positions[corner[1]] - p0, g.positions[corner[2]] - p0);
  auto cornerNormal = [&](int k) { return g.normals.empty() ? winding : g.normals[corner[k]]; };
  glm::vec3 normal = (1.0f - hit.u - hit.v) * cornerNormal(0) + hit.u * cornerNormal(1) + hit.v * cornerNormal(2);
  if (!(glm::dot(normal, normal) > 0.0f)) normal = winding;

  // The reflection uv through `transform`, and for the mip level the uv area of the triangle
  // whose corners carry their own reflections seen from the ray's origin (how fast the
  // reflection sweeps the texture across the triangle).
  auto reflectionUv = [&](const glm::mat3x2& transform, glm::vec2& uvOut, float& areaOut) {
    uvOut = transform * glm::vec3(reflectionSphereUv(normal, toViewer), 1.0f);
    const glm::mat2 linear(transform[0], transform[1]);
    glm::vec2 uv[3];
    for (int k = 0; k < 3; ++k)
      uv[k] = linear * reflectionSphereUv(cornerNormal(k), objectOrigin - g.positions[corner[k]]);
    const glm::vec2 d1 = uv[1] - uv[0], d2 = uv[2] - uv[0];
    areaOut = 0.5f * std::abs(d1.x * d2.y - d1.y * d2.x);
  };
  if (baseReflects) reflectionUv(desc.uvTransform, s.uv, s.uvArea);
  if (shineReflects) reflectionUv(desc.stock.shineUvTransform, s.shineUv, s.shineUvArea);
  return s;
}

}  // namespace pa
