#pragma once
// What the all-maps check needs to know about a map before rendering it: its first player
// spawn point (as pa-render numbers cameras) and whether that point lies inside the level.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>

#include <glm/vec3.hpp>

namespace q3 {
struct BspFile;
}

namespace pa::allmaps {

/// The spawn point a map is rendered from.
struct SpawnPoint {
  std::string cameraName;      ///< As pa-render names it: "info_player_deathmatch 12" (classname, entity index).
  uint32_t cameraIndex = 0;    ///< pa-render --camera index.
  glm::vec3 origin{0.0f};      ///< Entity origin (Quake units).
  glm::vec3 eye{0.0f};         ///< Where the camera stands: origin + 35 (spawn lift + view height).
};

/// One map, surveyed from its .bsp.
struct MapSurvey {
  std::optional<SpawnPoint> spawn;   ///< First player spawn point; nullopt when the map has none.
  int32_t eyeCluster = -1;           ///< PVS cluster of the leaf holding the eye; -1 = solid/outside.
  size_t lightEntities = 0;          ///< `light` entities left in the BSP (q3map2 usually strips them).
  /// True when the eye is in a leaf of the playable volume (cluster >= 0).
  bool eyeInsideLevel() const { return eyeCluster >= 0; }
};

/// Finds the first player spawn point the way pa-render's .bsp importer numbers cameras
/// (entity order; info_player_deathmatch/start, CTF spawns and info_player_intermission with a
/// valid origin are cameras; the first that is not an intermission point is chosen) and the
/// cluster of its eye. Throws q3::FormatError for a malformed entity lump.
MapSurvey surveyMap(const q3::BspFile& bsp);

/// Cluster of the BSP leaf containing `point` (walks the node tree from the root; a point on a
/// plane goes to the front child, as the engine's CM_PointLeafnum does). -1 for a map without
/// nodes or a point in an opaque leaf.
int32_t clusterAtPoint(const q3::BspFile& bsp, const glm::vec3& point);

}  // namespace pa::allmaps
