#pragma once
// The entity lump: a key/value parser and typed views (worldspawn, lights, spawn points).
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <glm/common.hpp>
#include <glm/vec3.hpp>

namespace q3 {

/// One "{ "key" "value" ... }" block. Keys keep file order; lookups return the first match.
struct Entity {
  std::vector<std::pair<std::string, std::string>> keys;

  /// Value of `key` (case-insensitive), or nullptr.
  const std::string* find(std::string_view key) const;
  /// Value of `key`, or `fallback` when absent.
  std::string_view get(std::string_view key, std::string_view fallback = {}) const;
  /// The "classname" value.
  std::string_view className() const { return get("classname"); }
  /// `key` as a float, or `fallback` when absent or not a number.
  float getFloat(std::string_view key, float fallback) const;
  /// `key` as three floats ("x y z"), or nullopt when absent or malformed.
  std::optional<glm::vec3> getVec3(std::string_view key) const;
};

/// Limits on the entity text (hostile input); exceeded limits throw FormatError.
struct EntityParseLimits {
  size_t maxTokenLength = 16384;  ///< longest key or value
  size_t maxEntities = 1 << 16;
  size_t maxKeysPerEntity = 4096;
};

/// Parses entity text: blocks of quoted key/value pairs, with // and /* */ comments.
/// Throws FormatError naming `fileName` on unterminated quotes/blocks or exceeded limits.
std::vector<Entity> parseEntities(std::string_view text, const std::string& fileName,
                                  const EntityParseLimits& limits = {});

/// The first entity whose classname is "worldspawn", or nullopt.
std::optional<Entity> findWorldspawn(const std::vector<Entity>& entities);

/// Worldspawn "gridsize" (default 64 64 128); malformed or non-positive values add a warning
/// and fall back to the default.
glm::vec3 worldspawnGridSize(const Entity& worldspawn, std::vector<std::string>& warnings);

/// Typed worldspawn keys that affect lighting.
struct WorldspawnInfo {
  std::string message;            ///< map title ("message")
  glm::vec3 gridSize{64, 64, 128};
  glm::vec3 ambient{0};           ///< "_ambient"/"ambient" intensity times "_color"
  glm::vec3 minlight{0};          ///< "_minlight"/"minlight" (q3map2's per-luxel floor) times "_color"
  glm::vec3 color{1};             ///< "_color" (normalised so the largest channel is 1)
  std::vector<std::string> warnings;
};
/// Reads worldspawn keys; a missing worldspawn gives defaults.
WorldspawnInfo readWorldspawn(const std::vector<Entity>& entities);

/// A map "light" entity (q3map point or spot light).
struct LightEntity {
  glm::vec3 origin{0};
  float intensity = 300;        ///< "light" or "_light" (q3map units)
  glm::vec3 color{1};           ///< "_color", normalised so the largest channel is 1
  bool linearFalloff = false;   ///< spawnflags & 1
  bool noIncidence = false;     ///< spawnflags & 2 (no angle attenuation)
  bool isSpot = false;          ///< has a "target" that resolves to an entity with an origin
  glm::vec3 spotDirection{0, 0, -1};  ///< unit vector towards the target
  float spotConeHalfAngleDeg = 0;     ///< "_cone" or atan(target "radius" (64) / distance)
};
/// All "light" entities; spot targets are resolved through "targetname".
std::vector<LightEntity> readLights(const std::vector<Entity>& entities);

/// Standing eye height above a spawn point's origin (9 spawn lift + 26 view height).
inline constexpr float kSpawnEyeHeight = 35.0f;

/// A spawn point turned into a camera (Quake axes: forward, left, up; Z is up).
struct SpawnCamera {
  std::string className;  ///< info_player_deathmatch/start/intermission or team_CTF_{red,blue}{spawn,player}
  glm::vec3 origin{0};    ///< entity origin
  glm::vec3 eye{0};       ///< origin + kSpawnEyeHeight (intermission: origin itself)
  glm::vec3 angles{0};    ///< pitch, yaw, roll in degrees ("angles", or "angle" = yaw)
  glm::vec3 forward{1, 0, 0}, left{0, 1, 0}, up{0, 0, 1};
};
/// Spawn points: deathmatch, start and intermission ones in entity order, then the CTF team
/// spawns (team_CTF_redspawn/bluespawn/redplayer/blueplayer) in entity order, so CTF-only maps
/// have cameras too.
std::vector<SpawnCamera> readSpawnCameras(const std::vector<Entity>& entities);

/// Quake angle convention: pitch (down positive), yaw (about +Z), roll -> forward, left, up.
void anglesToAxes(const glm::vec3& anglesDeg, glm::vec3& forward, glm::vec3& left, glm::vec3& up);

}  // namespace q3
