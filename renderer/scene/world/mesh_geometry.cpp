#include "renderer/scene/world/mesh_geometry.h"

#include <cmath>

namespace pa {

namespace {

template <typename Vec>
bool finite(const Vec& v) {
  for (int i = 0; i < Vec::length(); ++i) {
    if (!std::isfinite(v[i])) return false;
  }
  return true;
}

template <typename Vec>
std::vector<Vec> copyOptional(std::span<const Vec> src, size_t expected, const std::string& what, const char* field,
                              const char* perWhat) {
  if (src.empty()) return {};
  if (src.size() != expected) {
    throw SceneError(what + ": " + field + " has " + std::to_string(src.size()) + " entries, expected 0 or " +
                     std::to_string(expected) + " (one per " + perWhat + ")");
  }
  for (size_t i = 0; i < src.size(); ++i) {
    if (!finite(src[i])) {
      throw SceneError(what + ": " + field + "[" + std::to_string(i) + "] is not finite");
    }
  }
  return {src.begin(), src.end()};
}

}  // namespace

MeshGeometry MeshGeometry::fromDesc(const MeshDesc& desc, const std::string& what) {
  if (desc.positions.size() > kMaxMeshElements || desc.indices.size() / 3 > kMaxMeshElements) {
    throw SceneError(what + ": mesh too large (" + std::to_string(desc.positions.size()) + " vertices, " +
                     std::to_string(desc.indices.size()) + " indices)");
  }
  if (desc.indices.size() % 3 != 0) {
    throw SceneError(what + ": indices has " + std::to_string(desc.indices.size()) +
                     " entries, not a multiple of 3");
  }
  MeshGeometry g;
  g.dynamic = desc.dynamic;
  const size_t vertexCount = desc.positions.size();
  const size_t triangleCount = desc.indices.size() / 3;
  for (size_t i = 0; i < vertexCount; ++i) {
    if (!finite(desc.positions[i])) {
      throw SceneError(what + ": positions[" + std::to_string(i) + "] is not finite");
    }
  }
  for (size_t i = 0; i < desc.indices.size(); ++i) {
    if (desc.indices[i] >= vertexCount) {
      throw SceneError(what + ": indices[" + std::to_string(i) + "] = " + std::to_string(desc.indices[i]) +
                       " out of range (" + std::to_string(vertexCount) + " vertices)");
    }
  }
  g.positions.assign(desc.positions.begin(), desc.positions.end());
  g.indices.assign(desc.indices.begin(), desc.indices.end());
  g.normals = copyOptional(desc.normals, vertexCount, what, "normals", "vertex");
  g.uvs = copyOptional(desc.uvs, vertexCount, what, "uvs", "vertex");
  g.lightmapUvs = copyOptional(desc.lightmapUvs, vertexCount, what, "lightmapUvs", "vertex");
  g.colors = copyOptional(desc.colors, vertexCount, what, "colors", "vertex");
  if (!desc.materials.empty() && desc.materials.size() != triangleCount) {
    throw SceneError(what + ": materials has " + std::to_string(desc.materials.size()) +
                     " entries, expected 0 or " + std::to_string(triangleCount) + " (one per triangle)");
  }
  g.materials.assign(desc.materials.begin(), desc.materials.end());
  return g;
}

}  // namespace pa
