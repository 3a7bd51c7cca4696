// The converter exports the lights the game renders: on maps whose light entities were stripped
// (a lit room written by code, port/light_recovery/tests/lit_room_map.h, and oa_dm1 when the game
// data is installed), the .glb's KHR_lights_punctual lights are the lights pa-render's importer
// uploads (recovered by port/light_recovery, made renderer lights by pa::bridge::lightDesc), one
// for one: type, position, colour, intensity.
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "assets_converter/gltf_axes.h"
#include "assets_converter/map_conversion.h"
#include "port/light_recovery/tests/lit_room_map.h"
#include "port/q3formats/world/world_game.h"
#include "port/scene_bridge/bsp_importer.h"
#include "port/scene_bridge/scene_bridge.h"

namespace pa::converter {
namespace {

namespace fs = std::filesystem;

/// A light as the .glb holds it, back in Quake units and renderer intensity units.
struct GlbLight {
  glm::vec3 position{0.0f};
  glm::vec3 color{0.0f};
  float intensity = 0.0f;
  std::string type;
};

/// The JSON chunk of a .glb file.
nlohmann::json glbJson(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  const std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (bytes.size() < 20) return {};
  uint32_t length = 0;
  std::memcpy(&length, bytes.data() + 12, 4);
  if (20 + size_t(length) > bytes.size()) return {};
  return nlohmann::json::parse(bytes.begin() + 20, bytes.begin() + 20 + length);
}

/// Every KHR_lights_punctual light of a .glb with its node's translation, in node order.
std::vector<GlbLight> glbLights(const nlohmann::json& gltf, float metresPerUnit) {
  std::vector<GlbLight> out;
  const nlohmann::json& lights = gltf["extensions"]["KHR_lights_punctual"]["lights"];
  for (const nlohmann::json& node : gltf["nodes"]) {
    if (!node.contains("extensions") || !node["extensions"].contains("KHR_lights_punctual")) continue;
    const nlohmann::json& light = lights.at(node["extensions"]["KHR_lights_punctual"]["light"].get<size_t>());
    GlbLight l;
    l.type = light["type"].get<std::string>();
    l.color = {light["color"][0].get<float>(), light["color"][1].get<float>(), light["color"][2].get<float>()};
    l.intensity = light["intensity"].get<float>();
    if (l.type != "directional") {
      const nlohmann::json& t = node["translation"];
      const glm::vec3 gltf(t[0].get<float>(), t[1].get<float>(), t[2].get<float>());
      l.position = glm::vec3(gltf.x, -gltf.z, gltf.y) / metresPerUnit;   // inverse of toGltfPosition
      l.intensity /= metresPerUnit * metresPerUnit;                        // per metre^2 -> per unit^2
    }
    out.push_back(l);
  }
  return out;
}

/// Converts `map` of `gameDir` into `outDir` and checks its .glb lights against the lights
/// pa-render's importer uploads for the same map, one for one; returns how many there are.
size_t expectTheSameLights(const fs::path& gameDir, const std::string& map, const fs::path& outDir) {
  // What pa-render's .bsp importer (and, by the same calls, the engine module) lights the map with.
  bridge::MapLocation where;
  where.gameDir = gameDir;
  where.mapPath = q3::mapGamePath(map);
  const q3::WorldScene scene = bridge::loadMapScene(where);
  std::vector<LightDesc> rendered;
  for (const q3::WorldLight& l : scene.lights)
    if (l.intensity > 0.0f && std::isfinite(l.intensity)) rendered.push_back(bridge::lightDesc(l));

  // What the converter exports.
  const q3::GameWorlds game(gameDir);
  ExportOptions options;
  const MapResult result = convertMap(game, map, outDir, options);
  EXPECT_TRUE(result.error.empty()) << result.error;
  if (!result.error.empty()) return 0;
  const std::vector<GlbLight> exported = glbLights(glbJson(result.output), options.metresPerUnit);

  EXPECT_EQ(exported.size(), rendered.size());
  EXPECT_EQ(result.stats.lights, rendered.size());
  for (size_t i = 0; i < std::min(rendered.size(), exported.size()); ++i) {
    const LightDesc& r = rendered[i];
    const GlbLight& e = exported[i];
    if (r.type == LightType::Directional) {
      EXPECT_EQ(e.type, "directional") << i;
    } else {
      EXPECT_EQ(e.type, r.type == LightType::Spot ? "spot" : "point") << i;
      EXPECT_LT(glm::length(e.position - r.position), 1e-3f * std::max(1.0f, glm::length(r.position))) << i;
    }
    EXPECT_LT(glm::length(e.color - glm::clamp(r.color, 0.0f, 1.0f)), 1e-6f) << i;
    EXPECT_NEAR(e.intensity, r.intensity, 1e-5f * r.intensity) << i;
  }
  return rendered.size();
}

TEST(ConverterLights, TheGlbCarriesTheLightsPaRenderUploads) {
  const fs::path dir = fs::temp_directory_path() / ("pa_converter_lights_" + std::to_string(::getpid()));
  const fs::path game = dir / "game";
  fs::create_directories(game / "maps");
  {
    const std::vector<std::byte> bsp =
        recovery::testing::litRoomMap({{{40.0f, -30.0f, 150.0f}, 300.0f}, {{-150.0f, 120.0f, 90.0f}, 150.0f}}).build();
    std::ofstream out(game / "maps/lit_room.bsp", std::ios::binary);
    out.write(reinterpret_cast<const char*>(bsp.data()), std::streamsize(bsp.size()));
  }
  EXPECT_GE(expectTheSameLights(game, "lit_room", dir / "out"), 2u);   // both baked lights recovered
  fs::remove_all(dir);
}

TEST(ConverterLights, Oa_dm1GlbCarriesTheLightsPaRenderUploads) {
  const fs::path game = "/usr/share/games/openarena/baseoa";
  if (!fs::exists(game / "pak1-maps.pk3")) GTEST_SKIP() << "OpenArena data not installed at " << game;
  const fs::path dir = fs::temp_directory_path() / ("pa_converter_lights_dm1_" + std::to_string(::getpid()));
  EXPECT_GE(expectTheSameLights(game, "oa_dm1", dir), 40u);   // all recovered (it kept no light entity)
  fs::remove_all(dir);
}

}  // namespace
}  // namespace pa::converter
