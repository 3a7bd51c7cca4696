// Lights and cameras from entities: q3map2 light semantics, spot cones, spawn cameras.
#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "port/q3formats/world/world_lights.h"
#include "port/q3formats/world/world_source.h"

namespace q3 {
namespace {

TEST(WorldLights, FullBrightLightValueGivesIrradiancePi) {
  // A 300 light at distance d gives q3map2 light value 300 * 7500 / d^2; find d where it is 64.
  const float d = std::sqrt(300.0f * kQ3mapPointScale / kQ3FullBright);
  EXPECT_NEAR(pointLightIntensity(300.0f) / (d * d), std::numbers::pi_v<float>, 1e-4f);
  EXPECT_NEAR(sunIrradiance(64.0f), std::numbers::pi_v<float>, 1e-6f);
  EXPECT_NEAR(linearLightRange(300.0f), 281.25f, 1e-3f);
}

TEST(WorldEntities, PointLightWithDefaultsAndColour) {
  std::vector<SourceEntity> entities = {
      {{"classname", "worldspawn"}},
      {{"classname", "light"}, {"origin", "10 20 30"}, {"_color", "1 0.5 0"}},
      {{"classname", "light"}, {"origin", "0 0 0"}, {"light", "200"}, {"spawnflags", "1"}},
  };
  WorldScene scene;
  addEntityLightsAndCameras(entities, scene);
  ASSERT_EQ(scene.lights.size(), 2u);
  EXPECT_EQ(scene.lights[0].type, WorldLightType::Point);
  EXPECT_EQ(scene.lights[0].position, glm::vec3(10, 20, 30));
  EXPECT_FLOAT_EQ(scene.lights[0].quakeIntensity, 300.0f);
  EXPECT_FLOAT_EQ(scene.lights[0].intensity, pointLightIntensity(300.0f));
  EXPECT_EQ(scene.lights[0].color, glm::vec3(1.0f, 0.5f, 0.0f));
  EXPECT_TRUE(scene.lights[1].linearFalloff);
  EXPECT_FLOAT_EQ(scene.lights[1].range, linearLightRange(200.0f));
  EXPECT_EQ(scene.lights[1].source, "entity 2 (light)");
}

TEST(WorldEntities, WorldspawnAmbientAndMinlightTimesRawColour) {
  // q3map2 LightWorld: `_color` as written (not normalised), `_ambient` else `ambient`, `_minlight`.
  std::vector<SourceEntity> entities = {
      {{"classname", "worldspawn"}, {"_color", "1 0.61 0.5"}, {"ambient", "46"}, {"_minlight", "32"}},
      {{"classname", "worldspawn"}, {"_ambient", "99"}},   // only the first worldspawn counts
  };
  WorldScene scene;
  addEntityLightsAndCameras(entities, scene);
  EXPECT_FLOAT_EQ(scene.ambientLight.r, 46.0f);
  EXPECT_FLOAT_EQ(scene.ambientLight.g, 46.0f * 0.61f);
  EXPECT_FLOAT_EQ(scene.ambientLight.b, 23.0f);
  EXPECT_FLOAT_EQ(scene.minimumLight.g, 32.0f * 0.61f);
  EXPECT_TRUE(scene.warnings.empty());

  entities = {{{"classname", "worldspawn"}, {"_ambient", "10"}, {"ambient", "50"}, {"minlight", "40"}}};
  scene = {};
  addEntityLightsAndCameras(entities, scene);
  EXPECT_EQ(scene.ambientLight, glm::vec3(10.0f));   // `_ambient` wins; white without `_color`
  EXPECT_EQ(scene.minimumLight, glm::vec3(0.0f));    // q3map2 reads only `_minlight`
}

TEST(WorldEntities, MalformedWorldspawnLightIsIgnoredWithAWarning) {
  std::vector<SourceEntity> entities = {
      {{"classname", "worldspawn"}, {"_ambient", "-5"}, {"_minlight", "bright"}, {"_color", "0 0 0"}}};
  WorldScene scene;
  addEntityLightsAndCameras(entities, scene);
  EXPECT_EQ(scene.ambientLight, glm::vec3(0.0f));
  EXPECT_EQ(scene.minimumLight, glm::vec3(0.0f));
  EXPECT_EQ(scene.warnings.size(), 2u);
}

TEST(WorldEntities, TargetedLightIsASpotWithQ3map2Cone) {
  std::vector<SourceEntity> entities = {
      {{"classname", "light"}, {"origin", "0 0 256"}, {"target", "t1"}, {"radius", "48"}},
      {{"classname", "info_null"}, {"origin", "0 0 0"}, {"targetname", "t1"}},
  };
  WorldScene scene;
  addEntityLightsAndCameras(entities, scene);
  ASSERT_EQ(scene.lights.size(), 1u);
  const WorldLight& spot = scene.lights[0];
  EXPECT_EQ(spot.type, WorldLightType::Spot);
  EXPECT_NEAR(spot.direction.z, -1.0f, 1e-6f);
  // Cone radius at the target: 48 + 16 = 64 at distance 256.
  EXPECT_NEAR(spot.cosOuterAngle, std::cos(std::atan(64.0f / 256.0f)), 1e-6f);
  EXPECT_NEAR(spot.cosInnerAngle, std::cos(std::atan(32.0f / 256.0f)), 1e-6f);
}

TEST(WorldEntities, HostileValuesBecomeWarningsNotLights) {
  std::vector<SourceEntity> entities = {
      {{"classname", "light"}},                                     // no origin
      {{"classname", "light"}, {"origin", "nan 0 0"}},              // non-finite
      {{"classname", "light"}, {"origin", "0 0 0"}, {"light", "-50"}},
      {{"classname", "light"}, {"origin", "1 2"}},                  // too few numbers
      {{"classname", "light"}, {"origin", "0 0 0"}, {"target", "nowhere"}},
  };
  WorldScene scene;
  addEntityLightsAndCameras(entities, scene);
  ASSERT_EQ(scene.lights.size(), 1u);   // the last one, as a point light
  EXPECT_EQ(scene.lights[0].type, WorldLightType::Point);
  EXPECT_EQ(scene.warnings.size(), 5u);
}

TEST(WorldEntities, SpawnPointsBecomeEyeLevelCameras) {
  std::vector<SourceEntity> entities = {
      {{"classname", "info_player_deathmatch"}, {"origin", "100 0 24"}, {"angle", "90"}},
      {{"classname", "info_player_intermission"}, {"origin", "0 0 100"}, {"angles", "45 180 0"}},
  };
  WorldScene scene;
  addEntityLightsAndCameras(entities, scene);
  ASSERT_EQ(scene.cameras.size(), 2u);
  const WorldCamera& spawn = scene.cameras[0];
  EXPECT_EQ(spawn.eye, glm::vec3(100, 0, 24 + 35));
  EXPECT_NEAR(spawn.forward.x, 0.0f, 1e-6f);
  EXPECT_NEAR(spawn.forward.y, 1.0f, 1e-6f);
  EXPECT_NEAR(spawn.left.x, -1.0f, 1e-6f);   // yaw 90: left is -X
  EXPECT_NEAR(spawn.up.z, 1.0f, 1e-6f);
  const WorldCamera& inter = scene.cameras[1];
  EXPECT_EQ(inter.eye, glm::vec3(0, 0, 100));
  // Pitch 45 looks down: forward = (-cos45, 0, -sin45).
  EXPECT_NEAR(inter.forward.x, -std::sqrt(0.5f), 1e-6f);
  EXPECT_NEAR(inter.forward.z, -std::sqrt(0.5f), 1e-6f);
  EXPECT_NEAR(glm::dot(inter.forward, inter.up), 0.0f, 1e-6f);
}

}  // namespace
}  // namespace q3
