#pragma once
// Texture coordinates of TexCoordSource::ReflectionSphere (scene_types.h): a sphere map indexed
// by the view direction mirrored about the surface normal, evaluated per hit.
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace pa {

/// Sphere-map coordinates of the view reflection. `normal` and `toViewer` (from the surface
/// point toward the viewer) are in the same frame, need not be unit length and must be non-zero.
/// With n, v their unit vectors, r = 2 dot(n, v) n - v and uv = (0.5 + 0.5 r.y, 0.5 - 0.5 r.z):
/// looking head-on along -X at a surface facing +X gives (0.5, 0.5); r does not depend on which
/// side n points to. Returns (0.5, 0.5) for a zero or non-finite input.
inline glm::vec2 reflectionSphereUv(const glm::vec3& normal, const glm::vec3& toViewer) {
  const float nn = glm::dot(normal, normal), vv = glm::dot(toViewer, toViewer);
  if (!(nn > 0.0f) || !(vv > 0.0f) || !(nn < 3.0e38f) || !(vv < 3.0e38f)) return glm::vec2(0.5f);
  const glm::vec3 n = normal / std::sqrt(nn);
  const glm::vec3 v = toViewer / std::sqrt(vv);
  const glm::vec3 r = 2.0f * glm::dot(n, v) * n - v;
  return glm::vec2(0.5f + 0.5f * r.y, 0.5f - 0.5f * r.z);
}

}  // namespace pa
