#pragma once
// Test data: a compiled map whose `light` entities were stripped, as IBSP 46 bytes. A closed
// box room [-256, 256] x [-256, 256] x [0, 256] of six lightmapped walls (one 128x128 lightmap
// page each), its lightmaps and light grid baked from known point lights by q3map2's formulas:
// texels value * pointScale * cos / max(d, 16)^2, grid points the same falloff as directed
// light towards the strongest light. Light recovery must find those lights again.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "port/light_recovery/tests/synthetic_lit_room.h"
#include "port/q3formats/bsp/tests/bsp_writer.h"

namespace pa::recovery::testing {

/// A point light the map was baked from: position (Quake units) and q3map2 light value.
struct BakedLight {
  glm::vec3 position;
  float value;
};

/// The room as a map (see the header comment), with one spawn point and no light entity.
inline q3::testing::BspWriter litRoomMap(const std::vector<BakedLight>& lights) {
  q3::testing::BspWriter w;
  w.entities =
      "{\n\"classname\" \"worldspawn\"\n}\n"
      "{\n\"classname\" \"info_player_deathmatch\"\n\"origin\" \"-160 0 24\"\n\"angle\" \"0\"\n}\n";
  w.shaders = {{"textures/test/wall", 0, 1}};
  const glm::vec3 lo(-kRoomHalfWidth, -kRoomHalfWidth, 0.0f), hi(kRoomHalfWidth, kRoomHalfWidth, kRoomHeight);
  const std::array<RoomWall, 6> walls = roomWalls();
  constexpr int kSize = q3::kLightmapSize;
  for (size_t page = 0; page < walls.size(); ++page) {
    RoomWall wall = walls[page];
    if (glm::dot(glm::cross(wall.u, wall.v), wall.normal) < 0.0f) std::swap(wall.u, wall.v);   // Quake winding
    const glm::vec3& o = wall.origin;
    const int surface = w.addQuad({o, o + wall.u, o + wall.v, o + wall.u + wall.v}, wall.normal);
    w.surfaces[size_t(surface)].lightmap = int32_t(page);
    for (int k = 0; k < 4; ++k) {
      q3::BspDrawVert& vertex = w.drawVerts[size_t(w.surfaces[size_t(surface)].firstVert + k)];
      vertex.lightmap = vertex.st;   // the wall spans its whole page
    }
    for (int y = 0; y < kSize; ++y)
      for (int x = 0; x < kSize; ++x) {
        const glm::vec3 p = o + wall.u * ((float(x) + 0.5f) / kSize) + wall.v * ((float(y) + 0.5f) / kSize);
        float lit = 0.0f;
        for (const BakedLight& l : lights) lit += q3mapPointLight(l.position, l.value, p, wall.normal);
        const uint8_t byte = uint8_t(std::clamp(std::lround(lit), 0l, 255l));
        w.lightmaps.insert(w.lightmaps.end(), {byte, byte, byte});
      }
  }
  w.finishWorld(lo, hi);
  // Grid points every 64 x 64 x 128 units over the world's bounds, x fastest (the engine's layout).
  const glm::vec3 cell(64.0f, 64.0f, 128.0f);
  const glm::ivec3 counts = glm::ivec3((hi - lo) / cell) + 1;
  for (int z = 0; z < counts.z; ++z)
    for (int y = 0; y < counts.y; ++y)
      for (int x = 0; x < counts.x; ++x) {
        const glm::vec3 p = lo + glm::vec3(x, y, z) * cell;
        glm::vec3 towards(0.0f, 0.0f, 1.0f);
        float strongest = 0.0f, directed = 0.0f;
        for (const BakedLight& l : lights) {
          const float value = q3mapPointLight(l.position, l.value, p, glm::vec3(0.0f));
          directed += value;
          if (value > strongest) strongest = value, towards = glm::normalize(l.position - p);
        }
        constexpr float kStep = 2.0f * std::numbers::pi_v<float> / 256.0f;   // 256 steps per turn
        float azimuth = std::atan2(towards.y, towards.x);
        if (azimuth < 0.0f) azimuth += 2.0f * std::numbers::pi_v<float>;
        const uint8_t polar = uint8_t(int(std::lround(std::acos(std::clamp(towards.z, -1.0f, 1.0f)) / kStep)) & 255);
        const uint8_t around = uint8_t(int(std::lround(azimuth / kStep)) & 255);
        const uint8_t d = uint8_t(std::clamp(std::lround(directed), 0l, 255l));
        w.lightGrid.insert(w.lightGrid.end(), {8, 8, 8, d, d, d, polar, around});
      }
  return w;
}

}  // namespace pa::recovery::testing
