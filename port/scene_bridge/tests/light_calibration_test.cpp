// Known-answer tests of the lightmap calibration through the bridge's BVH shadow rays: a room
// whose lightmaps were synthesised from a known light gives its value back.
#include <gtest/gtest.h>

#include "port/q3formats/world/tests/synthetic_lit_room.h"
#include "port/scene_bridge/light_calibration.h"

namespace pa::bridge {
namespace {

TEST(BridgeLightCalibration, RecoversTheLightThroughTheBvh) {
  const glm::vec3 light(20.0f, 40.0f, 140.0f);
  q3::WorldScene scene = q3::testing::syntheticLitRoom(light, 400.0f, 6.0f);
  scene.lights.push_back(q3::testing::estimatedLight(light, 1500.0f));
  ASSERT_TRUE(hasEstimatedLights(scene));
  q3::LightCalibrationStats stats;
  const std::vector<q3::WorldLight> lights = calibratedLights(scene, {}, &stats);
  ASSERT_EQ(lights.size(), 1u);
  EXPECT_NEAR(lights[0].quakeIntensity, 400.0f, 400.0f * 0.05f);
  EXPECT_GT(stats.shadowRays, stats.samples / 2);
}

TEST(BridgeLightCalibration, DropsLightsInsideSolid) {
  const glm::vec3 light(0.0f, 0.0f, 128.0f);
  q3::WorldScene scene = q3::testing::syntheticLitRoom(light, 300.0f, 0.0f);
  scene.lights.push_back(q3::testing::estimatedLight(light, 300.0f));
  q3::testing::addSolidCube(scene, glm::vec3(150.0f, 150.0f, 60.0f), 40.0f);
  scene.lightCandidates.push_back(q3::testing::estimatedLight(glm::vec3(150.0f, 150.0f, 60.0f), 300.0f));  // inside it
  q3::LightCalibrationStats stats;
  const std::vector<q3::WorldLight> lights = calibratedLights(scene, {}, &stats);
  ASSERT_EQ(lights.size(), 1u);
  EXPECT_EQ(lights[0].position, light);
  EXPECT_EQ(stats.inSolid, 1u);
  EXPECT_EQ(stats.admitted, 0u);
}

TEST(BridgeLightCalibration, MapsWithoutEstimatesKeepTheirLights) {
  // The authored light explains the bake: no lightmap candidate either.
  q3::WorldScene scene = q3::testing::syntheticLitRoom(glm::vec3(0.0f, 0.0f, 128.0f), 300.0f, 0.0f);
  q3::WorldLight authored = q3::testing::estimatedLight(glm::vec3(0.0f, 0.0f, 128.0f), 300.0f);
  authored.estimated = false;
  scene.lights.push_back(authored);
  EXPECT_FALSE(hasEstimatedLights(scene));
  q3::LightCalibrationStats stats;
  const std::vector<q3::WorldLight> lights = calibratedLights(scene, {}, &stats);
  ASSERT_EQ(lights.size(), 1u);
  EXPECT_EQ(lights[0].quakeIntensity, 300.0f);
  EXPECT_EQ(stats.lightmapCandidates, 0u);
}

TEST(BridgeLightCalibration, FindsTheLightOfAStrippedMapInItsLightmaps) {
  // No light entity, no grid: the lightmaps alone give the light back.
  const glm::vec3 light(-70.0f, 50.0f, 150.0f);
  q3::WorldScene scene = q3::testing::syntheticLitRoom(light, 350.0f, 0.0f);
  q3::LightCalibrationStats stats;
  const std::vector<q3::WorldLight> lights = calibratedLights(scene, {}, &stats);
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

}  // namespace
}  // namespace pa::bridge
