#pragma once
// What the all-maps check needs to know about a map before rendering it: its first player
// spawn point (as pa-render numbers cameras) and whether that point lies inside the level.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "tests/all_maps_render/arena_info.h"

namespace q3 {
struct BspFile;
}

namespace pa::allmaps {

/// Farthest a spawn point's origin may be above the floor for a player spawned there to land
/// without falling damage (README.md "Spawn"): the game lifts the spawn by 9 units, the feet are
/// 24 below the origin, and a fall of h units at gravity 800 lands with delta = 2 * 800 * h * 1e-4,
/// which hurts above 40: h <= 250, floor <= 250 + 24 - 9 = 265 units below the origin.
inline constexpr float kMaxSpawnFloorDistance = 265.0f;

/// The spawn point a map is rendered from.
struct SpawnPoint {
  std::string className;       ///< "info_player_deathmatch", "team_CTF_redplayer", ...
  std::string cameraName;      ///< As pa-render names it: "info_player_deathmatch 12" (classname, entity index).
  uint32_t cameraIndex = 0;    ///< pa-render --camera index.
  glm::vec3 origin{0.0f};      ///< Entity origin (Quake units).
  glm::vec3 eye{0.0f};         ///< Where the camera stands: origin + 35 (spawn lift + view height).
  std::optional<float> floorDistance;  ///< Origin height above the floor below it (floorBelow); nullopt = none.
  /// True when a floor lies at most kMaxSpawnFloorDistance below the origin (the player lands unhurt).
  bool standsOnFloor() const { return floorDistance && *floorDistance <= kMaxSpawnFloorDistance; }
};

/// One map, surveyed from its .bsp.
struct MapSurvey {
  std::optional<SpawnPoint> spawn;        ///< The spawn point rendered (chooseSpawn); nullopt when the map has none.
  std::optional<SpawnPoint> firstSpawn;   ///< First player spawn point in file order (the choice before the floor rule).
  std::optional<SpawnFamily> family;      ///< Spawn family asked for (the map's first game type); nullopt = none.
  bool familyFound = false;               ///< `spawn` is of the family asked for (false: the fallback rule chose it).
  size_t spawnsWithoutFloor = 0;          ///< Player spawn points of any class before `spawn` that stand on no floor.
  int32_t eyeCluster = -1;                ///< PVS cluster of the leaf holding the eye; -1 = solid/outside.
  size_t lightEntities = 0;               ///< `light` entities left in the BSP (q3map2 usually strips them).
  /// True when the eye is in a leaf of the playable volume (cluster >= 0).
  bool eyeInsideLevel() const { return eyeCluster >= 0; }
};

/// Surveys a map. Player spawn points are numbered the way pa-render's .bsp importer numbers
/// cameras (entity order; info_player_deathmatch/start, CTF spawns and info_player_intermission
/// with a valid origin are cameras; intermission points are not player spawns). The rendered
/// spawn is the first, in file order, that stands on a floor (standsOnFloor) of the classes a
/// player of `family` starts at: Team: team_CTF_redplayer/blueplayer, then team_CTF_redspawn/
/// bluespawn; Deathmatch: info_player_deathmatch/start. When there is no such spawn (or no
/// family), the first player spawn of any class that stands on a floor; when none does, the
/// first player spawn. Throws q3::FormatError for a malformed entity lump.
MapSurvey surveyMap(const q3::BspFile& bsp, std::optional<SpawnFamily> family = std::nullopt);

/// What a player stands on in a map: brushes and curved patches with solid or playerclip
/// contents, of the world and of the brush entities where the map places them (a func_static or
/// a lowered platform is a floor); triangle soups (misc_model) do not collide and do not count.
class FloorProbe {
 public:
  /// Tessellates the solid patches (q3::tessellateSurfaces); throws q3::FormatError
  /// when they exceed its budget.
  explicit FloorProbe(const q3::BspFile& bsp);
  /// Distance from `point` straight down (-Z) to the first such brush or patch triangle,
  /// searched up to `maxDistance`; 0 when the point is inside a brush; nullopt when nothing is hit.
  std::optional<float> below(const glm::vec3& point, float maxDistance) const;

 private:
  const q3::BspFile& bsp_;
  std::vector<glm::vec3> patchTriangles_;   ///< Three corners per triangle.
};

/// Cluster of the BSP leaf containing `point` (walks the node tree from the root; a point on a
/// plane goes to the front child, as the engine's CM_PointLeafnum does). -1 for a map without
/// nodes or a point in an opaque leaf.
int32_t clusterAtPoint(const q3::BspFile& bsp, const glm::vec3& point);

}  // namespace pa::allmaps
