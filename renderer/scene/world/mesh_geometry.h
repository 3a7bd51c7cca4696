#pragma once
// Owned, validated copies of MeshDesc arrays, and the per-mesh record with its BLAS.
#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "renderer/bvh/bvh.h"
#include "renderer/scene/scene_types.h"

namespace pa {

/// Largest accepted vertex or triangle count per mesh (hostile-input guard).
inline constexpr uint32_t kMaxMeshElements = 1u << 26;

/// Validated mesh arrays (optional arrays are empty or full length).
struct MeshGeometry {
  std::vector<glm::vec3> positions;
  std::vector<uint32_t> indices;
  std::vector<glm::vec3> normals;
  std::vector<glm::vec2> uvs;
  std::vector<glm::vec2> lightmapUvs;
  std::vector<glm::vec4> colors;
  std::vector<MaterialId> materials;
  bool dynamic = false;

  bool operator==(const MeshGeometry&) const = default;
  /// Copies and validates; throws SceneError naming `what` and the offending field/element.
  /// Material ids are range-checked later, at commit (materials may be added after meshes).
  static MeshGeometry fromDesc(const MeshDesc& desc, const std::string& what);
  /// Triangles in the mesh.
  uint32_t triangleCount() const { return static_cast<uint32_t>(indices.size() / 3); }
  /// Material id of triangle `prim` (kNoId when the mesh has no per-triangle materials).
  MaterialId materialOf(uint32_t prim) const { return materials.empty() ? kNoId : materials[prim]; }
};

/// A committed mesh: geometry, the triangle flags that route hits through the HitFilter,
/// and its bottom-level BVH.
struct MeshRecord {
  MeshGeometry geometry;
  std::vector<uint8_t> filtered;   ///< Per triangle: non-zero = hits go through the HitFilter.
  Blas blas;
  bool built = false;
};

}  // namespace pa
