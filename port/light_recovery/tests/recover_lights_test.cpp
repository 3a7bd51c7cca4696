// Known-answer tests of recoverLights on a compiled map baked from a known light, and of its
// calibration step with BVH shadow rays (calibrateWithShadowRays): a room whose lightmaps were
// synthesised from a known light gives its value back.
#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include "port/light_recovery/recover_lights.h"
#include "port/light_recovery/tests/lit_room_map.h"
#include "port/light_recovery/tests/synthetic_lit_room.h"
#include "port/q3formats/bsp/bsp_file.h"
#include "port/q3formats/shader/shader_library.h"

namespace pa::recovery {
namespace {

TEST(ShadowRayCalibration, RecoversTheLightThroughTheBvh) {
  const glm::vec3 light(20.0f, 40.0f, 140.0f);
  q3::WorldScene scene = testing::syntheticLitRoom(light, 400.0f, 6.0f);
  scene.lights.push_back(testing::estimatedLight(light, 1500.0f));
  ASSERT_TRUE(hasEstimatedLights(scene.lights, {}));
  LightCalibrationStats stats;
  const std::vector<q3::WorldLight> lights = calibrateWithShadowRays(scene, scene.lights, {}, {}, &stats);
  ASSERT_EQ(lights.size(), 1u);
  EXPECT_NEAR(lights[0].quakeIntensity, 400.0f, 400.0f * 0.05f);
  EXPECT_GT(stats.shadowRays, stats.samples / 2);
}

TEST(ShadowRayCalibration, DropsLightsInsideSolid) {
  const glm::vec3 light(0.0f, 0.0f, 128.0f);
  q3::WorldScene scene = testing::syntheticLitRoom(light, 300.0f, 0.0f);
  scene.lights.push_back(testing::estimatedLight(light, 300.0f));
  testing::addSolidCube(scene, glm::vec3(150.0f, 150.0f, 60.0f), 40.0f);
  const std::vector<q3::WorldLight> candidates = {testing::estimatedLight(glm::vec3(150.0f, 150.0f, 60.0f), 300.0f)};  // inside it
  LightCalibrationStats stats;
  const std::vector<q3::WorldLight> lights = calibrateWithShadowRays(scene, scene.lights, candidates, {}, &stats);
  ASSERT_EQ(lights.size(), 1u);
  EXPECT_EQ(lights[0].position, light);
  EXPECT_EQ(stats.inSolid, 1u);
  EXPECT_EQ(stats.admitted, 0u);
}

TEST(ShadowRayCalibration, MapsWithoutEstimatesKeepTheirLights) {
  // The authored light explains the bake: no lightmap candidate either.
  q3::WorldScene scene = testing::syntheticLitRoom(glm::vec3(0.0f, 0.0f, 128.0f), 300.0f, 0.0f);
  q3::WorldLight authored = testing::estimatedLight(glm::vec3(0.0f, 0.0f, 128.0f), 300.0f);
  authored.estimated = false;
  scene.lights.push_back(authored);
  EXPECT_FALSE(hasEstimatedLights(scene.lights, {}));
  LightCalibrationStats stats;
  const std::vector<q3::WorldLight> lights = calibrateWithShadowRays(scene, scene.lights, {}, {}, &stats);
  ASSERT_EQ(lights.size(), 1u);
  EXPECT_EQ(lights[0].quakeIntensity, 300.0f);
  EXPECT_EQ(stats.lightmapCandidates, 0u);
}

TEST(ShadowRayCalibration, FindsTheLightOfAStrippedMapInItsLightmaps) {
  // No light entity, no grid: the lightmaps alone give the light back.
  const glm::vec3 light(-70.0f, 50.0f, 150.0f);
  q3::WorldScene scene = testing::syntheticLitRoom(light, 350.0f, 0.0f);
  LightCalibrationStats stats;
  const std::vector<q3::WorldLight> lights = calibrateWithShadowRays(scene, scene.lights, {}, {}, &stats);
  ASSERT_GE(lights.size(), 1u);
  float total = 0.0f;
  for (const q3::WorldLight& l : lights) {
    EXPECT_TRUE(l.estimated);
    EXPECT_LT(glm::length(l.position - light), 24.0f) << l.source;
    total += l.quakeIntensity;
  }
  EXPECT_NEAR(total, 350.0f, 350.0f * 0.15f);
  EXPECT_GE(stats.admittedFromLightmaps, 1u);
}

TEST(RecoverLights, LightTheBakeShowsEverywhereBecomesTheAmbient) {
  // A stripped room baked from one light plus 12 light values everywhere: the lamp comes back
  // from the lightmaps, the 12 as the ambient every program then lights with.
  q3::WorldScene scene = testing::syntheticLitRoom(glm::vec3(-70.0f, 50.0f, 150.0f), 350.0f, 12.0f);
  const RecoveredLights recovered = recoverLights(scene);
  EXPECT_GE(recovered.lights.size(), 1u);
  EXPECT_NEAR(recovered.ambientValue, 12.0f, 1.5f);
  scene.ambientLight = glm::vec3(20.0f, 5.0f, 5.0f);   // an authored ambient: the larger one stays
  applyRecoveredLights(scene, recovered);
  EXPECT_EQ(scene.ambientLight.r, 20.0f);
  EXPECT_NEAR(scene.ambientLight.g, 12.0f, 1.5f);
  // Nothing unexplained, nothing added; a hostile value is capped at full bright.
  q3::WorldScene dark = testing::syntheticLitRoom(glm::vec3(-70.0f, 50.0f, 150.0f), 350.0f, 0.0f);
  EXPECT_LT(recoverLights(dark).ambientValue, 1.0f);
  RecoveredLights hostile;
  hostile.ambientValue = 1e30f;
  applyRecoveredLights(dark, hostile);
  EXPECT_EQ(dark.ambientLight, glm::vec3(q3::kQ3FullBright));
}

TEST(ShadowRayCalibration, TheSameLightsWithOneAndTwoThreads) {
  // The shadow rays run in parallel; each sample keeps its own random sky rays, so the thread
  // count changes nothing. A stripped map (lightmap candidates) with an open sky (random rays).
  q3::WorldScene scene = testing::syntheticLitRoom(glm::vec3(-70.0f, 50.0f, 150.0f), 350.0f, 6.0f);
  scene.lights.push_back(testing::estimatedLight(glm::vec3(60.0f, -40.0f, 120.0f), 200.0f));
  LightCalibrationOptions options;
  options.skyLightValue = 40.0f;
  std::vector<q3::WorldLight> results[2];
  LightCalibrationStats stats[2];
  for (int threads = 1; threads <= 2; ++threads) {
    tbb::task_arena arena(threads);
    arena.execute([&] {
      results[threads - 1] = calibrateWithShadowRays(scene, scene.lights, {}, options, &stats[threads - 1]);
    });
  }
  ASSERT_GE(results[0].size(), 1u);
  ASSERT_EQ(results[0].size(), results[1].size());
  for (size_t i = 0; i < results[0].size(); ++i) {
    EXPECT_EQ(results[0][i].position, results[1][i].position) << i;
    EXPECT_EQ(results[0][i].quakeIntensity, results[1][i].quakeIntensity) << i;
  }
  EXPECT_EQ(stats[0].shadowRays, stats[1].shadowRays);
  EXPECT_EQ(stats[0].lightmapCandidates, stats[1].lightmapCandidates);
  EXPECT_EQ(stats[0].unexplained, stats[1].unexplained);
}

/// The lit room map built as every program builds a map (q3::buildWorldScene), no textures.
q3::WorldScene builtLitRoom(const std::vector<testing::BakedLight>& lights) {
  const q3::BspFile bsp = q3::parseBsp(testing::litRoomMap(lights).build(), "maps/lit_room.bsp");
  const q3::ShaderLibrary shaders;
  q3::WorldBuildOptions options;
  options.loadTextures = false;
  return q3::buildWorldScene(bsp, shaders, [](std::string_view) { return std::nullopt; }, options);
}

TEST(RecoverLights, FindsTheLightAStrippedMapWasBakedFrom) {
  const testing::BakedLight baked{{40.0f, -30.0f, 150.0f}, 300.0f};
  const q3::WorldScene scene = builtLitRoom({baked});
  ASSERT_TRUE(scene.lights.empty());   // the builder adds no estimate
  const RecoveredLights recovered = recoverLights(scene);
  ASSERT_FALSE(recovered.lights.empty());
  EXPECT_EQ(recovered.stats.authored, 0u);
  EXPECT_GE(recovered.stats.estimated, 1u);
  float total = 0.0f;
  for (const q3::WorldLight& l : recovered.lights) {
    EXPECT_TRUE(l.estimated);
    EXPECT_LT(glm::length(l.position - baked.position), 24.0f) << l.source;
    EXPECT_NEAR(l.intensity, q3::pointLightIntensity(l.quakeIntensity), 1e-3f * l.intensity);
    total += l.quakeIntensity;
  }
  EXPECT_NEAR(total, baked.value, baked.value * 0.1f);
}

TEST(RecoverLights, IsTheSameOnItsOwnResultAndKeepsAuthoredLightsFirst) {
  q3::WorldScene scene = builtLitRoom({{{-60.0f, 80.0f, 170.0f}, 250.0f}});
  q3::WorldLight sun;
  sun.type = q3::WorldLightType::Sun;
  sun.intensity = 0.5f;
  sun.source = "test sun";
  scene.lights.push_back(sun);
  const RecoveredLights first = recoverLights(scene);
  ASSERT_GE(first.lights.size(), 2u);
  EXPECT_EQ(first.lights[0].source, "test sun");
  scene.lights = first.lights;
  const RecoveredLights second = recoverLights(scene);
  ASSERT_EQ(second.lights.size(), first.lights.size());
  for (size_t i = 0; i < first.lights.size(); ++i) {
    EXPECT_EQ(second.lights[i].position, first.lights[i].position);
    EXPECT_EQ(second.lights[i].quakeIntensity, first.lights[i].quakeIntensity);
  }
}

TEST(RecoverLights, WithoutCalibrationGivesTheGridEstimate) {
  const q3::WorldScene scene = builtLitRoom({{{0.0f, 0.0f, 128.0f}, 300.0f}});
  RecoveryOptions options;
  options.calibrate = false;
  const RecoveredLights grid = recoverLights(scene, options);
  EXPECT_GE(grid.stats.estimated, 1u);
  EXPECT_EQ(grid.lights.size(), grid.stats.estimated);
  EXPECT_EQ(grid.stats.calibration.samples, 0u);
}

}  // namespace
}  // namespace pa::recovery
