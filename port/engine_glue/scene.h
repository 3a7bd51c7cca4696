#pragma once
// What the game adds to a scene between ClearScene and RenderScene: entities, polygons
// (decals, particles) and dynamic lights. Copied, validated, capped like the stock renderer.
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "port/engine_glue/ioq3_abi.h"

namespace glue {

/// A dynamic light (AddLightToScene / AddAdditiveLightToScene).
struct DynamicLight {
  glm::vec3 origin{0.0f};
  float radius = 0.0f;       ///< The engine's "intensity": reach in world units.
  glm::vec3 color{1.0f};
  bool additive = false;
};

/// One AddPolyToScene polygon: its shader and a range of `SceneFrame::polyVerts`.
struct ScenePoly {
  q3abi::qhandle_t shader = 0;
  uint32_t firstVert = 0;
  uint32_t numVerts = 0;
};

/// The contents of the scene being built.
class SceneFrame {
 public:
  /// Stock limits (MAX_REFENTITIES, MAX_DLIGHTS, MAX_POLYS, MAX_POLYVERTS).
  static constexpr size_t kMaxEntities = q3abi::kMaxRefEntities;
  static constexpr size_t kMaxLights = q3abi::kMaxDlights;
  static constexpr size_t kMaxPolys = 600;
  static constexpr size_t kMaxPolyVerts = 3000;

  /// Forgets everything added.
  void clear();
  /// Adds an entity; false (and nothing added) when it is invalid or the scene is full.
  bool addEntity(const q3abi::refEntity_t& entity);
  /// Adds `count` polygons of `vertsPerPoly` vertices each (stored back to back).
  bool addPolys(q3abi::qhandle_t shader, int vertsPerPoly, const q3abi::polyVert_t* verts,
                int count);
  /// Adds a dynamic light; ignored when radius <= 0 or the scene has MAX_DLIGHTS already.
  void addLight(const float* origin, float radius, float r, float g, float b, bool additive);

  const std::vector<q3abi::refEntity_t>& entities() const { return entities_; }
  const std::vector<ScenePoly>& polys() const { return polys_; }
  const std::vector<q3abi::polyVert_t>& polyVerts() const { return polyVerts_; }
  const std::vector<DynamicLight>& lights() const { return lights_; }

 private:
  std::vector<q3abi::refEntity_t> entities_;
  std::vector<ScenePoly> polys_;
  std::vector<q3abi::polyVert_t> polyVerts_;
  std::vector<DynamicLight> lights_;
};

/// True when every float of the entity's placement is finite.
bool entityIsFinite(const q3abi::refEntity_t& entity);

}  // namespace glue
