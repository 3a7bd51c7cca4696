// Real-data check: on maps lit by q3map_sun, sky light and surface lights, the Direct
// integrator is about as bright as the baked lightmaps. Skipped when the data is absent.
#include <cstdio>
#include <filesystem>
#include <string>

#include <glm/common.hpp>
#include <gtest/gtest.h>

#include "port/light_recovery/recover_lights.h"
#include "port/q3formats/world/world_game.h"
#include "port/scene_bridge/scene_bridge.h"

namespace pa::bridge {
namespace {

constexpr const char* kGameDir = "/usr/share/games/openarena/baseoa";

/// Mean luminance of a small render of the map from its first spawn point. The lightmap can
/// show at most "full bright" (Quake's overbright shift saturates at 255), so each pixel's
/// radiance is capped at its albedo, what a lightmap texel of 64 shows.
double meanLuminance(Renderer& renderer, const Camera& camera, Integrator integrator) {
  RenderSettings settings;
  settings.width = 64;
  settings.height = 36;
  settings.integrator = integrator;
  settings.samplesPerPixel = 4;
  settings.maxBounces = integrator == Integrator::Direct ? 1 : 0;
  FrameView frame = renderer.render(camera, settings);
  double sum = 0.0;
  for (size_t i = 0; i < frame.radiance.size(); ++i) {
    const glm::vec3 r = i < frame.albedo.size() ? glm::min(frame.radiance[i], frame.albedo[i]) : frame.radiance[i];
    sum += 0.2126 * r.r + 0.7152 * r.g + 0.0722 * r.b;
  }
  return sum / double(frame.radiance.size());
}

class OpenArenaLighting : public ::testing::TestWithParam<std::string> {};

TEST_P(OpenArenaLighting, DirectIsWithinAFactorFourOfTheLightmap) {
  if (!std::filesystem::exists(std::string(kGameDir) + "/pak1-maps.pk3")) GTEST_SKIP() << "OpenArena data not installed";
  q3::GameWorlds game(kGameDir);
  q3::WorldScene scene = game.load(GetParam());
  scene.lights = recovery::recoverLights(scene).lights;
  ASSERT_FALSE(scene.cameras.empty());
  Renderer renderer;
  showSkyAndFog(uploadWorld(scene, renderer), renderer);
  renderer.commit();
  const Camera camera = cameraFromSpawn(scene.cameras.front(), 16.0f / 9.0f);
  const double baked = meanLuminance(renderer, camera, Integrator::Lightmap);
  const double direct = meanLuminance(renderer, camera, Integrator::Direct);
  std::printf("%s: lightmap %.4f direct %.4f\n", GetParam().c_str(), baked, direct);
  ASSERT_GT(baked, 0.01);
  EXPECT_GT(direct, baked / 4.0);
  EXPECT_LT(direct, baked * 4.0);
}

// Maps whose light survives in the BSP (q3map_sun, sky light, surface lights). Maps whose
// compiler stripped their `light` entities (oa_dm1, oa_dm3, oa_dm4, oa_dm5) cannot match.
INSTANTIATE_TEST_SUITE_P(Maps, OpenArenaLighting, ::testing::Values("oa_dm6", "oa_shine", "islanddm"));

}  // namespace
}  // namespace pa::bridge
