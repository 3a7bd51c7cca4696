#pragma once
// Test helper: a closed box room lit by q3map2 point lights, with lightmaps synthesised the
// way q3map2 computes them (value * pointScale * cos / max(d, 16)^2, plus a constant standing
// for bounced light), one 64x64 lightmap per wall.
#include <algorithm>
#include <array>
#include <cmath>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>

#include "port/q3formats/world/world_lights.h"
#include "port/q3formats/world/world_scene.h"

namespace pa::recovery::testing {

using q3::kQ3mapPointScale;
using q3::pointLightIntensity;
using q3::WorldImage;
using q3::WorldLight;
using q3::WorldMaterial;
using q3::WorldMesh;
using q3::WorldScene;

/// Half width and height of the test room (Quake units).
inline constexpr float kRoomHalfWidth = 256.0f, kRoomHeight = 256.0f;

/// One wall of the test room: corner, u edge, v edge, inward normal.
struct RoomWall {
  glm::vec3 origin, u, v, normal;
};

/// The six walls of the room [-256, 256] x [-256, 256] x [0, 256], floor first.
inline std::array<RoomWall, 6> roomWalls() {
  const glm::vec3 lo(-kRoomHalfWidth, -kRoomHalfWidth, 0.0f), hi(kRoomHalfWidth, kRoomHalfWidth, kRoomHeight);
  return {{
      {{lo.x, lo.y, lo.z}, {hi.x - lo.x, 0, 0}, {0, hi.y - lo.y, 0}, {0, 0, 1}},    // floor
      {{lo.x, lo.y, hi.z}, {hi.x - lo.x, 0, 0}, {0, hi.y - lo.y, 0}, {0, 0, -1}},   // ceiling
      {{lo.x, lo.y, lo.z}, {hi.x - lo.x, 0, 0}, {0, 0, hi.z - lo.z}, {0, 1, 0}},
      {{lo.x, hi.y, lo.z}, {hi.x - lo.x, 0, 0}, {0, 0, hi.z - lo.z}, {0, -1, 0}},
      {{lo.x, lo.y, lo.z}, {0, hi.y - lo.y, 0}, {0, 0, hi.z - lo.z}, {1, 0, 0}},
      {{hi.x, lo.y, lo.z}, {0, hi.y - lo.y, 0}, {0, 0, hi.z - lo.z}, {-1, 0, 0}},
  }};
}

/// Light value a q3map2 point light (value at `light`) gives point `p` facing `normal`, no
/// shadows; a zero normal counts the light as facing (the light grid's directed light).
inline float q3mapPointLight(const glm::vec3& light, float value, const glm::vec3& p, const glm::vec3& normal) {
  const glm::vec3 toLight = light - p;
  const float d = glm::length(toLight);
  const float cosine = normal == glm::vec3(0.0f) ? 1.0f : std::max(0.0f, glm::dot(normal, toLight) / d);
  const float clamped = std::max(d, 16.0f);
  return value * kQ3mapPointScale * cosine / (clamped * clamped);
}

/// Builds the room [-256, 256] x [-256, 256] x [0, 256] lit by the (position, value) lights.
inline WorldScene syntheticLitRoom(const std::vector<std::pair<glm::vec3, float>>& lights, float bounce) {
  constexpr uint32_t kSize = 64;
  WorldScene scene;
  scene.materials.push_back(WorldMaterial{});
  scene.materials[0].shaderName = "textures/test/wall";
  scene.models.emplace_back();
  for (const RoomWall& w : roomWalls()) {
    WorldImage image;
    image.width = image.height = kSize;
    image.rgba8.resize(size_t(kSize) * kSize * 4);
    for (uint32_t y = 0; y < kSize; ++y)
      for (uint32_t x = 0; x < kSize; ++x) {
        const glm::vec3 p = w.origin + w.u * ((float(x) + 0.5f) / kSize) + w.v * ((float(y) + 0.5f) / kSize);
        float lit = bounce;
        for (const auto& [light, value] : lights) lit += q3mapPointLight(light, value, p, w.normal);
        const uint8_t byte = uint8_t(std::clamp(std::lround(lit), 0l, 255l));
        uint8_t* texel = &image.rgba8[(size_t(y) * kSize + x) * 4];
        texel[0] = texel[1] = texel[2] = byte;
        texel[3] = 255;
      }
    WorldMesh mesh;
    mesh.material = 0;
    mesh.lightmap = int32_t(scene.lightmaps.size());
    scene.lightmaps.push_back(std::move(image));
    const std::array<glm::vec2, 4> uv{{{0, 0}, {1, 0}, {1, 1}, {0, 1}}};
    for (const glm::vec2& c : uv) {
      mesh.positions.push_back(w.origin + w.u * c.x + w.v * c.y);
      mesh.normals.push_back(w.normal);
      mesh.uvs.push_back(c);
      mesh.lightmapUvs.push_back(c);
      mesh.colors.emplace_back(1.0f);
    }
    // Counter-clockwise seen from the side the normal points to (the inside).
    if (glm::dot(glm::cross(w.u, w.v), w.normal) > 0.0f) mesh.indices = {0, 1, 2, 0, 2, 3};
    else mesh.indices = {0, 2, 1, 0, 3, 2};
    scene.models[0].meshes.push_back(std::move(mesh));
  }
  return scene;
}

/// Builds the room [-256, 256] x [-256, 256] x [0, 256] lit by `value` at `light`.
inline WorldScene syntheticLitRoom(const glm::vec3& light, float value, float bounce) {
  return syntheticLitRoom({{light, value}}, bounce);
}

/// Adds a closed, outward-facing cube (a solid block, no lightmap) centred at `centre`.
inline void addSolidCube(WorldScene& scene, const glm::vec3& centre, float half) {
  WorldMesh mesh;
  mesh.material = 0;
  mesh.lightmap = -1;
  for (int i = 0; i < 8; ++i) {
    mesh.positions.push_back(centre + half * glm::vec3(i & 1 ? 1 : -1, i & 2 ? 1 : -1, i & 4 ? 1 : -1));
    mesh.normals.push_back(glm::normalize(mesh.positions.back() - centre));
    mesh.uvs.emplace_back(0.0f);
    mesh.lightmapUvs.emplace_back(0.0f);
    mesh.colors.emplace_back(1.0f);
  }
  // Two triangles per face, wound counter-clockwise seen from outside.
  const std::array<std::array<uint32_t, 4>, 6> faces{{
      {0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}}};
  for (const auto& f : faces) mesh.indices.insert(mesh.indices.end(), {f[0], f[1], f[2], f[0], f[2], f[3]});
  scene.models[0].meshes.push_back(std::move(mesh));
}

/// A light as the grid estimator returns it (estimated, inverse-square, white).
inline WorldLight estimatedLight(const glm::vec3& position, float value) {
  WorldLight l;
  l.position = position;
  l.quakeIntensity = value;
  l.intensity = pointLightIntensity(value);
  l.estimated = true;
  l.source = "test estimate";
  return l;
}

}  // namespace pa::recovery::testing
