#pragma once
// Renderable triangle lists produced from BSP surfaces (see tessellate.h).
#include <array>
#include <cstdint>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "port/q3formats/bsp/bsp_file.h"

namespace q3 {

/// One output vertex: world position, unit normal, texture and lightmap coordinates, RGBA colour.
struct MeshVertex {
  glm::vec3 position{};
  glm::vec3 normal{};
  glm::vec2 uv{};
  glm::vec2 lightmapUv{};
  std::array<uint8_t, 4> color{255, 255, 255, 255};
};

/// Triangles of one BSP surface. Triangles are counter-clockwise seen from the front
/// (the side the surface normal points to), i.e. glTF winding; Quake's files store clockwise.
struct SurfaceMesh {
  uint32_t surfaceIndex = 0;  ///< index into BspFile::surfaces
  SurfaceType type = SurfaceType::Planar;
  int32_t shader = 0;              ///< index into BspFile::shaders
  int32_t lightmap = kLightmapNone;  ///< lightmap page, negative for none
  int32_t fog = -1;                ///< index into BspFile::fogs, -1 for none
  int32_t model = 0;               ///< 0 = world, 1..N = brush model "*N", -1 = unreferenced
  std::vector<MeshVertex> vertices;
  std::vector<uint32_t> indices;   ///< three per triangle
};

}  // namespace q3
