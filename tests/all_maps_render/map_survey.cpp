// Spawn point and point-in-leaf lookup on the parsed BSP.
#include "tests/all_maps_render/map_survey.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <string_view>

#include <glm/geometric.hpp>

#include "port/q3formats/bsp/bsp_file.h"
#include "port/q3formats/bsp/entities.h"
#include "port/q3formats/bsp/tessellate.h"

namespace pa::allmaps {
namespace {

/// Classnames pa-render's .bsp importer turns into cameras (port/q3formats/world/world_entities.cpp).
constexpr std::array<std::string_view, 7> kCameraClasses = {
    "info_player_deathmatch", "info_player_start",   "team_CTF_redspawn",       "team_CTF_bluespawn",
    "team_CTF_redplayer",     "team_CTF_blueplayer", "info_player_intermission"};

bool isCameraClass(std::string_view name) {
  for (std::string_view c : kCameraClasses)
    if (c == name) return true;
  return false;
}

/// Brush contents a player stands on (q3 CONTENTS_SOLID, CONTENTS_PLAYERCLIP).
constexpr int32_t kStandableContents = 0x1 | 0x10000;

/// How far below a spawn the floor is searched (the figure is reported even when it is far).
constexpr float kFloorSearchDistance = 65536.0f;

/// Where the segment point + t * (0, 0, -1), t in [0, maxDistance], enters a convex brush
/// (0 when the point is inside it); nullopt when it misses.
std::optional<float> downwardEntry(const q3::BspFile& bsp, const q3::BspBrush& brush, const glm::vec3& point,
                                   float maxDistance) {
  float enter = 0.0f, exit = maxDistance;
  for (int32_t k = 0; k < brush.numSides; ++k) {
    const q3::BspPlane& plane = bsp.planes[static_cast<size_t>(bsp.brushSides[static_cast<size_t>(brush.firstSide + k)].plane)];
    const float height = glm::dot(plane.normal, point) - plane.dist;   // > 0: outside this side
    const float rate = -plane.normal.z;                                 // d(height)/dt along -Z
    if (rate == 0.0f) {
      if (height > 0.0f) return std::nullopt;
      continue;
    }
    const float t = -height / rate;
    if (rate < 0.0f) enter = std::max(enter, t);   // height falls: the segment comes in
    else exit = std::min(exit, t);                 // height rises: the segment goes out
    if (enter > exit) return std::nullopt;
  }
  return enter;
}

/// Distance t >= 0 at which point + t * (0, 0, -1) crosses triangle (a, b, c), either side; nullopt when it misses.
std::optional<float> downwardTriangleHit(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c,
                                         const glm::vec3& point) {
  // Barycentric coordinates of the point's (x, y) in the triangle's projection on the XY plane.
  const glm::vec2 p(point), pa(a), pb(b), pc(c);
  const auto cross = [](glm::vec2 u, glm::vec2 v) { return u.x * v.y - u.y * v.x; };
  const float area = cross(pb - pa, pc - pa);
  if (std::abs(area) < 1e-6f) return std::nullopt;   // vertical or degenerate: no floor
  const float wb = cross(p - pa, pc - pa) / area, wc = cross(pb - pa, p - pa) / area, wa = 1.0f - wb - wc;
  if (wa < 0.0f || wb < 0.0f || wc < 0.0f) return std::nullopt;
  const float t = point.z - (wa * a.z + wb * b.z + wc * c.z);
  return t >= 0.0f ? std::optional<float>(t) : std::nullopt;
}

}  // namespace

int32_t clusterAtPoint(const q3::BspFile& bsp, const glm::vec3& point) {
  if (bsp.nodes.empty() || bsp.leafs.empty()) return -1;
  // parseBsp checked that every child index is in range and that children follow their parent,
  // so this walk ends.
  int32_t index = 0;
  while (index >= 0) {
    const q3::BspNode& node = bsp.nodes[static_cast<size_t>(index)];
    const q3::BspPlane& plane = bsp.planes[static_cast<size_t>(node.plane)];
    index = glm::dot(plane.normal, point) - plane.dist >= 0.0f ? node.children[0] : node.children[1];
  }
  return bsp.leafs[static_cast<size_t>(-(index + 1))].cluster;
}

FloorProbe::FloorProbe(const q3::BspFile& bsp) : bsp_(bsp) {
  for (const q3::SurfaceMesh& mesh : q3::tessellateSurfaces(bsp)) {
    if (mesh.type != q3::SurfaceType::Patch || mesh.model < 0) continue;
    if ((bsp.shaders[static_cast<size_t>(mesh.shader)].contentFlags & kStandableContents) == 0) continue;
    for (const uint32_t index : mesh.indices)   // tessellateSurfaces keeps indices in range
      patchTriangles_.push_back(mesh.vertices[index].position);
  }
}

std::optional<float> FloorProbe::below(const glm::vec3& point, float maxDistance) const {
  if (!(maxDistance >= 0.0f)) return std::nullopt;
  // parseBsp checked every brush, side, plane and shader index.
  std::optional<float> nearest;
  auto consider = [&](std::optional<float> t) {
    if (t && *t <= maxDistance && (!nearest || *t < *nearest)) nearest = t;
  };
  for (const q3::BspBrush& brush : bsp_.brushes) {
    if ((bsp_.shaders[static_cast<size_t>(brush.shader)].contentFlags & kStandableContents) == 0) continue;
    consider(downwardEntry(bsp_, brush, point, nearest.value_or(maxDistance)));
  }
  for (size_t t = 0; t + 2 < patchTriangles_.size(); t += 3)
    consider(downwardTriangleHit(patchTriangles_[t], patchTriangles_[t + 1], patchTriangles_[t + 2], point));
  return nearest;
}

MapSurvey surveyMap(const q3::BspFile& bsp, std::optional<SpawnFamily> family) {
  MapSurvey survey;
  survey.family = family;
  const FloorProbe floor(bsp);
  const std::vector<q3::Entity> entities = q3::parseEntities(bsp.entities, bsp.fileName);
  std::vector<SpawnPoint> spawns;   // player spawns in file order
  uint32_t cameraIndex = 0;
  for (size_t i = 0; i < entities.size(); ++i) {
    const q3::Entity& e = entities[i];
    const std::string_view cls = e.className();
    if (cls == "light") ++survey.lightEntities;
    if (!isCameraClass(cls)) continue;
    const std::optional<glm::vec3> origin = e.getVec3("origin");
    if (!origin) continue;   // the importer skips it too (no camera index)
    if (cls != "info_player_intermission") {
      SpawnPoint& spawn = spawns.emplace_back();
      spawn.className = std::string(cls);
      spawn.cameraName = std::string(cls) + " " + std::to_string(i);
      spawn.cameraIndex = cameraIndex;
      spawn.origin = *origin;
      spawn.eye = *origin + glm::vec3(0.0f, 0.0f, q3::kSpawnEyeHeight);
      spawn.floorDistance = floor.below(*origin, kFloorSearchDistance);
    }
    ++cameraIndex;
  }
  if (spawns.empty()) return survey;
  survey.firstSpawn = spawns.front();

  // The classes a player of the family starts at, most preferred first (OpenArena's
  // SelectCTFSpawnPoint: the team's *player spawns at the start, *spawn after a death).
  std::vector<std::vector<std::string_view>> tiers;
  if (family == SpawnFamily::Team)
    tiers = {{"team_CTF_redplayer", "team_CTF_blueplayer"}, {"team_CTF_redspawn", "team_CTF_bluespawn"}};
  else if (family == SpawnFamily::Deathmatch)
    tiers = {{"info_player_deathmatch", "info_player_start"}};
  const auto firstOnFloor = [&](auto accepts) -> const SpawnPoint* {
    for (const SpawnPoint& s : spawns)
      if (accepts(s.className) && s.standsOnFloor()) return &s;
    return nullptr;
  };
  const SpawnPoint* chosen = nullptr;
  for (const auto& tier : tiers) {
    chosen = firstOnFloor([&](std::string_view cls) { return std::find(tier.begin(), tier.end(), cls) != tier.end(); });
    if (chosen) break;
  }
  survey.familyFound = chosen != nullptr;
  // Fallback: the first player spawn of any class that stands on a floor, else the first.
  if (!chosen) chosen = firstOnFloor([](std::string_view) { return true; });
  if (!chosen) chosen = &spawns.front();
  survey.spawn = *chosen;
  for (const SpawnPoint* s = spawns.data(); s != chosen; ++s) survey.spawnsWithoutFloor += s->standsOnFloor() ? 0 : 1;
  survey.eyeCluster = clusterAtPoint(bsp, survey.spawn->eye);
  return survey;
}

}  // namespace pa::allmaps
