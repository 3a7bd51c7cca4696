// Known-answer tests of the lightmap calibration: a room whose lightmaps were synthesised from
// a known point light must give that light's value back, whatever the grid's guess.
#include <gtest/gtest.h>

#include "port/light_recovery/tests/synthetic_lit_room.h"
#include "port/light_recovery/calibration.h"

namespace pa::recovery {
namespace {

using namespace q3;

const SegmentBlocked kNothingBlocks = [](const glm::vec3&, const glm::vec3&) { return false; };

TEST(LightCalibration, RecoversTheValueOfTheLightThatBakedTheLightmaps) {
  const glm::vec3 light(40.0f, -30.0f, 150.0f);
  WorldScene scene = testing::syntheticLitRoom(light, 300.0f, 0.0f);
  scene.lights.push_back(testing::estimatedLight(light, 900.0f));   // the grid overestimated it 3x
  LightCalibrationStats stats;
  const std::vector<WorldLight> lights = calibrateEstimatedLights(scene, scene.lights, {}, kNothingBlocks, {}, &stats);
  ASSERT_EQ(lights.size(), 1u);
  EXPECT_NEAR(lights[0].quakeIntensity, 300.0f, 300.0f * 0.05f);
  EXPECT_NEAR(lights[0].intensity, pointLightIntensity(lights[0].quakeIntensity), 1e-3f);
  EXPECT_EQ(stats.refitted, 1u);
  EXPECT_GT(stats.samples, 10000u);
  EXPECT_NEAR(stats.meanAfter, stats.meanTexel, stats.meanTexel * 0.05f);
}

TEST(LightCalibration, BouncedLightGoesToTheConstantNotToTheLight) {
  const glm::vec3 light(-60.0f, 80.0f, 180.0f);
  WorldScene scene = testing::syntheticLitRoom(light, 250.0f, 12.0f);
  scene.lights.push_back(testing::estimatedLight(light, 100.0f));   // underestimated
  LightCalibrationStats stats;
  const std::vector<WorldLight> lights = calibrateEstimatedLights(scene, scene.lights, {}, kNothingBlocks, {}, &stats);
  ASSERT_EQ(lights.size(), 1u);
  EXPECT_NEAR(lights[0].quakeIntensity, 250.0f, 250.0f * 0.05f);
  EXPECT_NEAR(stats.unexplained, 3.0f * 12.0f, 3.0f);   // summed over RGB
}

TEST(LightCalibration, AdmitsAConfirmedCandidateAndLeavesASpuriousOneOut) {
  const glm::vec3 light(0.0f, 0.0f, 128.0f);
  WorldScene scene = testing::syntheticLitRoom(light, 200.0f, 0.0f);
  WorldLight real = testing::estimatedLight(light, 80.0f);
  WorldLight spurious = testing::estimatedLight(glm::vec3(180.0f, 180.0f, 40.0f), 150.0f);
  const std::vector<WorldLight> candidates = {real, spurious};
  LightCalibrationStats stats;
  const std::vector<WorldLight> lights = calibrateEstimatedLights(scene, scene.lights, candidates, kNothingBlocks, {}, &stats);
  ASSERT_EQ(lights.size(), 1u);
  EXPECT_EQ(stats.admitted, 1u);
  EXPECT_EQ(lights[0].position, light);
  EXPECT_NEAR(lights[0].quakeIntensity, 200.0f, 200.0f * 0.05f);
}

TEST(LightCalibration, AFittedValueStaysBelowItsCap) {
  const glm::vec3 light(10.0f, 20.0f, 120.0f);
  WorldScene scene = testing::syntheticLitRoom(light, 300.0f, 0.0f);
  WorldLight candidate = testing::estimatedLight(light, 50.0f);
  candidate.maxQuakeIntensity = 120.0f;   // what its peak allows
  const std::vector<WorldLight> lights = calibrateEstimatedLights(scene, scene.lights, {}, kNothingBlocks, {}, nullptr, {}, {}, {candidate});
  ASSERT_EQ(lights.size(), 1u);
  EXPECT_FLOAT_EQ(lights[0].quakeIntensity, 120.0f);
}

TEST(LightCalibration, AuthoredLightsStayAndTheirLightIsNotFittedTwice) {
  const glm::vec3 light(30.0f, 30.0f, 120.0f);
  WorldScene scene = testing::syntheticLitRoom(light, 300.0f, 0.0f);
  WorldLight authored = testing::estimatedLight(light, 300.0f);
  authored.estimated = false;
  scene.lights.push_back(authored);
  const std::vector<WorldLight> candidates = {testing::estimatedLight(light + glm::vec3(8.0f, 0.0f, 0.0f), 300.0f)};
  const std::vector<WorldLight> lights = calibrateEstimatedLights(scene, scene.lights, candidates, kNothingBlocks);
  ASSERT_EQ(lights.size(), 1u);
  EXPECT_FALSE(lights[0].estimated);
  EXPECT_EQ(lights[0].quakeIntensity, 300.0f);
}

TEST(LightCalibration, NothingToFitLeavesTheLightsAlone) {
  WorldScene scene;   // no surfaces, no lightmaps
  scene.lights.push_back(testing::estimatedLight(glm::vec3(0.0f), 300.0f));
  LightCalibrationStats stats;
  const std::vector<WorldLight> lights = calibrateEstimatedLights(scene, scene.lights, {}, kNothingBlocks, {}, &stats);
  ASSERT_EQ(lights.size(), 1u);
  EXPECT_EQ(lights[0].quakeIntensity, 300.0f);
  EXPECT_EQ(stats.samples, 0u);
}

TEST(LightCalibration, HostileLightmapsAreSkippedNotRead) {
  WorldScene scene = testing::syntheticLitRoom(glm::vec3(0.0f, 0.0f, 128.0f), 200.0f, 0.0f);
  for (WorldImage& image : scene.lightmaps) image.rgba8.resize(7);   // truncated
  scene.models[0].meshes[0].indices = {0, 1, 99};                     // out of range
  scene.lights.push_back(testing::estimatedLight(glm::vec3(0.0f, 0.0f, 128.0f), 300.0f));
  LightCalibrationStats stats;
  const std::vector<WorldLight> lights = calibrateEstimatedLights(scene, scene.lights, {}, kNothingBlocks, {}, &stats);
  ASSERT_EQ(lights.size(), 1u);
  EXPECT_EQ(lights[0].quakeIntensity, 300.0f);
  EXPECT_EQ(stats.samples, 0u);
}

}  // namespace
}  // namespace pa::recovery
