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

/// The call and object an error message names ("setInstance: instance 12"), made into text only
/// when an error is thrown, so that validating valid input allocates nothing.
struct CallContext {
  const char* call;              ///< The setter, e.g. "setInstance".
  const char* kind = nullptr;    ///< The object's kind, e.g. "instance"; nullptr: none.
  uint32_t id = 0;               ///< The object's id.
  /// "call: kind id".
  std::string str() const;
};

/// The context's text followed by `tail` (for SceneError messages).
inline std::string operator+(const CallContext& context, const char* tail) { return context.str() + tail; }

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
  static MeshGeometry fromDesc(const MeshDesc& desc, const CallContext& what);
  /// Throws SceneError naming `what` and the offending field/element when desc is invalid.
  static void validate(const MeshDesc& desc, const CallContext& what);
  /// Copies a validated desc into these arrays, reusing their memory.
  void assign(const MeshDesc& desc);
  /// Makes room for as many elements in each array as example's arrays hold (contents unchanged).
  void reserveLike(const MeshGeometry& example);
  /// Whether these arrays hold exactly desc's data.
  bool holds(const MeshDesc& desc) const;
  /// Triangles in the mesh.
  uint32_t triangleCount() const { return static_cast<uint32_t>(indices.size() / 3); }
  /// Material id of triangle `prim` (kNoId when the mesh has no per-triangle materials).
  MaterialId materialOf(uint32_t prim) const { return materials.empty() ? kNoId : materials[prim]; }
};

/// A committed mesh: geometry, the triangles' hit rules (which hits go through the HitFilter
/// callback, which are culled by face in the BVH) and its bottom-level BVH.
struct MeshRecord {
  MeshGeometry geometry;
  std::vector<HitRule> rules;   ///< Per triangle (materialHitRule of its materials).
  /// geometry.colors' RGB in display values (fastLinearToSrgb of each channel), encoded at commit
  /// for vertex-lit surfaces, whose baked light is interpolated in display values.
  std::vector<glm::vec3> displayColors;
  Blas blas;
  bool built = false;
  /// Changes (to a value unique within its SceneStore) whenever a commit changes the positions.
  uint64_t positionsStamp = 0;
  /// Changes whenever a commit changes the vertex count or the indices (and on the first commit).
  uint64_t topologyStamp = 0;
};

}  // namespace pa
