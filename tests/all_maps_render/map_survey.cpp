// Spawn point and point-in-leaf lookup on the parsed BSP.
#include "tests/all_maps_render/map_survey.h"

#include <array>
#include <string_view>

#include <glm/geometric.hpp>

#include "port/q3formats/bsp/bsp_file.h"
#include "port/q3formats/bsp/entities.h"

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

MapSurvey surveyMap(const q3::BspFile& bsp) {
  MapSurvey survey;
  const std::vector<q3::Entity> entities = q3::parseEntities(bsp.entities, bsp.fileName);
  uint32_t cameraIndex = 0;
  for (size_t i = 0; i < entities.size(); ++i) {
    const q3::Entity& e = entities[i];
    const std::string_view cls = e.className();
    if (cls == "light") ++survey.lightEntities;
    if (!isCameraClass(cls)) continue;
    const std::optional<glm::vec3> origin = e.getVec3("origin");
    if (!origin) continue;   // the importer skips it too (no camera index)
    if (!survey.spawn && cls != "info_player_intermission") {
      SpawnPoint spawn;
      spawn.cameraName = std::string(cls) + " " + std::to_string(i);
      spawn.cameraIndex = cameraIndex;
      spawn.origin = *origin;
      spawn.eye = *origin + glm::vec3(0.0f, 0.0f, q3::kSpawnEyeHeight);
      survey.spawn = spawn;
    }
    ++cameraIndex;
  }
  if (survey.spawn) survey.eyeCluster = clusterAtPoint(bsp, survey.spawn->eye);
  return survey;
}

}  // namespace pa::allmaps
