#include "renderer/scene/world/mesh_geometry.h"

#include <algorithm>
#include <cmath>
#include "renderer/core/reuse.h"

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
void checkOptional(std::span<const Vec> src, size_t expected, const CallContext& what, const char* field,
                   const char* perWhat) {
  if (src.empty()) return;
  if (src.size() != expected) {
    throw SceneError(what + ": " + field + " has " + std::to_string(src.size()) + " entries, expected 0 or " +
                     std::to_string(expected) + " (one per " + perWhat + ")");
  }
  for (size_t i = 0; i < src.size(); ++i) {
    if (!finite(src[i])) {
      throw SceneError(what + ": " + field + "[" + std::to_string(i) + "] is not finite");
    }
  }
}

template <typename T>
bool sameElements(const std::vector<T>& held, std::span<const T> given) {
  return std::equal(held.begin(), held.end(), given.begin(), given.end());
}

}  // namespace

std::string CallContext::str() const {
  std::string text = call;
  if (kind != nullptr) text += std::string(": ") + kind + " " + std::to_string(id);
  return text;
}

MeshGeometry MeshGeometry::fromDesc(const MeshDesc& desc, const CallContext& what) {
  validate(desc, what);
  MeshGeometry g;
  g.assign(desc);
  return g;
}

void MeshGeometry::validate(const MeshDesc& desc, const CallContext& what) {
  if (desc.positions.size() > kMaxMeshElements || desc.indices.size() / 3 > kMaxMeshElements) {
    throw SceneError(what + ": mesh too large (" + std::to_string(desc.positions.size()) + " vertices, " +
                     std::to_string(desc.indices.size()) + " indices)");
  }
  if (desc.indices.size() % 3 != 0) {
    throw SceneError(what + ": indices has " + std::to_string(desc.indices.size()) +
                     " entries, not a multiple of 3");
  }
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
  checkOptional(desc.normals, vertexCount, what, "normals", "vertex");
  checkOptional(desc.uvs, vertexCount, what, "uvs", "vertex");
  checkOptional(desc.lightmapUvs, vertexCount, what, "lightmapUvs", "vertex");
  checkOptional(desc.colors, vertexCount, what, "colors", "vertex");
  if (!desc.materials.empty() && desc.materials.size() != triangleCount) {
    throw SceneError(what + ": materials has " + std::to_string(desc.materials.size()) +
                     " entries, expected 0 or " + std::to_string(triangleCount) + " (one per triangle)");
  }
}

void MeshGeometry::assign(const MeshDesc& desc) {
  dynamic = desc.dynamic;
  assignReusing(positions, desc.positions.begin(), desc.positions.end());
  assignReusing(indices, desc.indices.begin(), desc.indices.end());
  assignReusing(normals, desc.normals.begin(), desc.normals.end());
  assignReusing(uvs, desc.uvs.begin(), desc.uvs.end());
  assignReusing(lightmapUvs, desc.lightmapUvs.begin(), desc.lightmapUvs.end());
  assignReusing(colors, desc.colors.begin(), desc.colors.end());
  assignReusing(materials, desc.materials.begin(), desc.materials.end());
}

void MeshGeometry::reserveLike(const MeshGeometry& example) {
  const auto atLeast = [](auto& v, const auto& other) {
    if (other.capacity() > v.capacity()) v.reserve(other.capacity());
  };
  atLeast(positions, example.positions);
  atLeast(indices, example.indices);
  atLeast(normals, example.normals);
  atLeast(uvs, example.uvs);
  atLeast(lightmapUvs, example.lightmapUvs);
  atLeast(colors, example.colors);
  atLeast(materials, example.materials);
}

bool MeshGeometry::holds(const MeshDesc& desc) const {
  return dynamic == desc.dynamic && sameElements(positions, desc.positions) && sameElements(indices, desc.indices) &&
         sameElements(normals, desc.normals) && sameElements(uvs, desc.uvs) &&
         sameElements(lightmapUvs, desc.lightmapUvs) && sameElements(colors, desc.colors) &&
         sameElements(materials, desc.materials);
}

}  // namespace pa
