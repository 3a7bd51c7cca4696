// Shared by the portal tests: the cgame's portal entity and the portal views of a map whose
// floor is a portal surface.
#pragma once

#include <glm/vec3.hpp>

#include "port/engine_glue/portals.h"
#include "port/q3formats/bsp/tests/bsp_writer.h"
#include "port/q3formats/world/world_scene.h"

namespace glue::testing {

/// An RT_PORTALSURFACE entity at `origin` whose camera stands at `camera`, looking along +x
/// (left +y, up +z).
inline q3abi::refEntity_t portalEntity(const glm::vec3& origin, const glm::vec3& camera) {
  q3abi::refEntity_t e{};
  e.reType = q3abi::RT_PORTALSURFACE;
  for (int k = 0; k < 3; ++k) {
    e.origin[k] = origin[k];
    e.oldorigin[k] = camera[k];
    e.axis[k][k] = 1.0f;
  }
  return e;
}

/// The portal views of q3::testing::sampleMap() with its floor (shader 0, "textures/test/floor",
/// z = 0) a portal surface: one plane.
inline PortalViews mirrorFloorViews() {
  auto w = q3::testing::sampleMap();
  const q3::BspFile bsp = q3::parseBsp(w.build(), "maps/portals.bsp");
  q3::WorldScene scene;
  scene.materials.resize(2);
  scene.materials[0].shaderName = "textures/test/floor";
  scene.materials[0].mirror = true;
  scene.materials[1].shaderName = "textures/test/fog";
  PortalViews views;
  views.load(bsp, scene);
  return views;
}

}  // namespace glue::testing
