// Lights and cameras from map entities, with q3map2's semantics for `light` entities and the
// worldspawn's ambient light keys.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <numbers>
#include <optional>
#include <string_view>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "port/q3formats/world/world_lights.h"
#include "port/q3formats/world/world_source.h"

namespace q3 {
namespace {

/// Case-insensitive key lookup (Quake keys are case-insensitive); last value wins as in the game.
const std::string* findKey(const SourceEntity& entity, std::string_view key) {
  const std::string* found = nullptr;
  for (const auto& [k, v] : entity) {
    if (k.size() == key.size() &&
        std::equal(k.begin(), k.end(), key.begin(), [](char a, char b) { return std::tolower(a) == std::tolower(b); }))
      found = &v;
  }
  return found;
}

/// Parses up to N whitespace-separated floats; nullopt unless exactly N finite numbers were read.
template <size_t N>
std::optional<std::array<float, N>> parseFloats(const std::string& text) {
  std::array<float, N> out{};
  const char* p = text.data();
  const char* end = p + text.size();
  for (size_t i = 0; i < N; ++i) {
    while (p < end && (*p == ' ' || *p == '\t')) ++p;
    if (p < end && *p == '+') ++p;
    auto [next, ec] = std::from_chars(p, end, out[i]);
    if (ec != std::errc() || !std::isfinite(out[i])) return std::nullopt;
    p = next;
  }
  return out;
}

std::optional<float> floatKey(const SourceEntity& e, std::string_view key) {
  const std::string* v = findKey(e, key);
  if (!v) return std::nullopt;
  auto f = parseFloats<1>(*v);
  return f ? std::optional<float>((*f)[0]) : std::nullopt;
}

std::optional<glm::vec3> vecKey(const SourceEntity& e, std::string_view key) {
  const std::string* v = findKey(e, key);
  if (!v) return std::nullopt;
  auto f = parseFloats<3>(*v);
  return f ? std::optional<glm::vec3>(glm::vec3((*f)[0], (*f)[1], (*f)[2])) : std::nullopt;
}

std::string describe(const SourceEntity& e, size_t index) {
  const std::string* cls = findKey(e, "classname");
  return "entity " + std::to_string(index) + " (" + (cls ? *cls : std::string("?")) + ")";
}

/// Quake's AngleVectors for (pitch, yaw, roll) in degrees: forward, left, up.
void angleVectors(glm::vec3 angles, WorldCamera& cam) {
  float p = glm::radians(angles.x), y = glm::radians(angles.y), r = glm::radians(angles.z);
  float sp = std::sin(p), cp = std::cos(p), sy = std::sin(y), cy = std::cos(y), sr = std::sin(r), cr = std::cos(r);
  cam.forward = {cp * cy, cp * sy, -sp};
  glm::vec3 right = {-sr * sp * cy + cr * sy, -sr * sp * sy - cr * cy, -sr * cp};
  cam.left = -right;
  cam.up = {cr * sp * cy + sr * sy, cr * sp * sy - sr * cy, cr * cp};
}

glm::vec3 normalisedColor(glm::vec3 c) {
  float peak = std::max({c.r, c.g, c.b});
  if (!(peak > 0.0f)) return glm::vec3(1.0f);
  return glm::max(c / peak, glm::vec3(0.0f));
}

bool isSpawnPoint(std::string_view cls) {
  return cls == "info_player_deathmatch" || cls == "info_player_start" || cls == "team_CTF_redspawn" ||
         cls == "team_CTF_bluespawn" || cls == "team_CTF_redplayer" || cls == "team_CTF_blueplayer" ||
         cls == "info_player_intermission";
}

/// A non-negative light value of the worldspawn (q3map2 reads it with atof: malformed = 0).
float worldspawnLightValue(const SourceEntity& e, size_t index, std::string_view key, WorldScene& scene) {
  const std::string* text = findKey(e, key);
  if (!text) return 0.0f;
  const std::optional<float> value = floatKey(e, key);
  if (!value || *value < 0.0f) {
    scene.warnings.push_back(describe(e, index) + ": " + std::string(key) + " \"" + *text +
                             "\" is not a non-negative number, ignored");
    return 0.0f;
  }
  return *value;
}

/// q3map2's LightWorld: `_color` (raw, white when its length is 0) times `_ambient` (else
/// `ambient`), added to every texel, and times `_minlight`, every texel's floor.
void readWorldspawnLight(const SourceEntity& e, size_t index, WorldScene& scene) {
  glm::vec3 color = vecKey(e, "_color").value_or(glm::vec3(0.0f));
  color = glm::max(color, glm::vec3(0.0f));
  if (!(glm::length(color) > 0.0f)) color = glm::vec3(1.0f);
  float ambient = worldspawnLightValue(e, index, "_ambient", scene);
  if (ambient == 0.0f) ambient = worldspawnLightValue(e, index, "ambient", scene);
  scene.ambientLight = color * ambient;
  scene.minimumLight = color * worldspawnLightValue(e, index, "_minlight", scene);
}

}  // namespace

void addEntityLightsAndCameras(const std::vector<SourceEntity>& entities, WorldScene& scene) {
  auto findTarget = [&](const std::string& name) -> std::optional<glm::vec3> {
    for (const auto& e : entities)
      if (const std::string* t = findKey(e, "targetname"); t && *t == name) return vecKey(e, "origin");
    return std::nullopt;
  };

  bool worldspawnRead = false;
  for (size_t i = 0; i < entities.size(); ++i) {
    const SourceEntity& e = entities[i];
    const std::string* cls = findKey(e, "classname");
    if (!cls) continue;

    if (*cls == "worldspawn" && !worldspawnRead) {
      readWorldspawnLight(e, i, scene);
      worldspawnRead = true;
      continue;
    }

    if (*cls == "light") {
      auto origin = vecKey(e, "origin");
      if (!origin) {
        scene.warnings.push_back(describe(e, i) + ": missing or malformed origin, light skipped");
        continue;
      }
      WorldLight light;
      light.source = describe(e, i);
      light.position = *origin;
      // q3map2: "_light" else "light" else 300, times "scale".
      float value = floatKey(e, "_light").value_or(0.0f);
      if (value == 0.0f) value = floatKey(e, "light").value_or(0.0f);
      if (value == 0.0f) value = kQ3DefaultLight;
      value *= floatKey(e, "scale").value_or(1.0f);
      if (!(value > 0.0f)) {
        scene.warnings.push_back(light.source + ": non-positive intensity " + std::to_string(value) +
                                 " (negative light is not modelled), skipped");
        continue;
      }
      light.quakeIntensity = value;
      light.color = normalisedColor(vecKey(e, "_color").value_or(glm::vec3(1.0f)));
      const int spawnflags = int(floatKey(e, "spawnflags").value_or(0.0f));
      light.linearFalloff = (spawnflags & 1) != 0;
      if (light.linearFalloff) {
        light.intensity = linearLightIntensity(value);
        light.range = linearLightRange(value);
      } else {
        light.intensity = pointLightIntensity(value);
      }
      if (const std::string* target = findKey(e, "target")) {
        auto aim = findTarget(*target);
        if (!aim) {
          scene.warnings.push_back(light.source + ": target '" + *target + "' not found, kept as a point light");
        } else if (float dist = glm::length(*aim - *origin); dist > 1e-3f) {
          light.direction = (*aim - *origin) / dist;
          if (floatKey(e, "_sun").value_or(0.0f) != 0.0f) {
            // q3map2 "_sun": a spot light with a target is a sun along that direction.
            light.type = WorldLightType::Sun;
            light.intensity = sunIrradiance(value);
            light.range = 0.0f;
          } else {
            // q3map2: cone radius at the target = radius + 16, soft over the outer 32 units.
            light.type = WorldLightType::Spot;
            float radius = floatKey(e, "radius").value_or(kQ3DefaultSpotRadius);
            if (!(radius > 0.0f)) radius = kQ3DefaultSpotRadius;
            float outer = (radius + 16.0f) / dist;
            float inner = std::max(0.0f, (radius + 16.0f - 32.0f) / dist);
            light.cosOuterAngle = std::cos(std::atan(outer));
            light.cosInnerAngle = std::cos(std::atan(inner));
          }
        }
      }
      scene.lights.push_back(light);
      continue;
    }

    if (isSpawnPoint(*cls)) {
      auto origin = vecKey(e, "origin");
      if (!origin) {
        scene.warnings.push_back(describe(e, i) + ": missing or malformed origin, camera skipped");
        continue;
      }
      WorldCamera cam;
      cam.name = *cls + " " + std::to_string(i);
      glm::vec3 angles(0.0f);
      if (auto a = vecKey(e, "angles")) angles = *a;
      else if (auto yaw = floatKey(e, "angle")) angles.y = *yaw;
      const bool intermission = *cls == "info_player_intermission";
      cam.eye = intermission ? *origin : *origin + glm::vec3(0.0f, 0.0f, 9.0f + 26.0f);
      angleVectors(angles, cam);
      if (const std::string* target = findKey(e, "target"); intermission && target) {
        if (auto aim = findTarget(*target); aim && glm::length(*aim - cam.eye) > 1e-3f) {
          glm::vec3 dir = glm::normalize(*aim - cam.eye);
          float pitch = -glm::degrees(std::asin(std::clamp(dir.z, -1.0f, 1.0f)));
          float yaw = glm::degrees(std::atan2(dir.y, dir.x));
          angleVectors({pitch, yaw, 0.0f}, cam);
        }
      }
      scene.cameras.push_back(cam);
    }
  }
}

}  // namespace q3
