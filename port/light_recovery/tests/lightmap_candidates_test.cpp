// Known-answer tests of the lightmap candidates: rooms whose lightmaps were baked by formula from
// known point lights, with no light grid at all, must give those lights back (positions from
// the candidates, values from the calibration); hostile lightmaps and meshes must not crash.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "port/light_recovery/tests/synthetic_lit_room.h"
#include "port/light_recovery/lightmap_candidates.h"

namespace pa::recovery {
namespace {

using namespace q3;

const SegmentBlocked kNothingBlocks = [](const glm::vec3&, const glm::vec3&) { return false; };
const KnownLightAt kNothingKnown = [](const glm::vec3&, const glm::vec3&) { return 0.0f; };

/// Candidates from the lightmaps, then the calibration's values: the admitted lights.
std::vector<WorldLight> lightsRecoveredFrom(const WorldScene& scene, LightCalibrationStats* stats = nullptr) {
  const std::vector<WorldLight> candidates = lightsFromLightmaps(scene, kNothingKnown, {}, kNothingBlocks, {});
  return calibrateEstimatedLights(scene, scene.lights, {}, kNothingBlocks, {}, stats, {}, {}, candidates);
}

/// Sum of the values of the lights within `radius` of `at`.
float valueNear(const std::vector<WorldLight>& lights, const glm::vec3& at, float radius) {
  float sum = 0.0f;
  for (const WorldLight& l : lights)
    if (glm::length(l.position - at) < radius) sum += l.quakeIntensity * (l.color.r + l.color.g + l.color.b) / 3.0f;
  return sum;
}

TEST(LightmapLights, TexelsArePlacedOnTheirWalls) {
  const WorldScene scene = testing::syntheticLitRoom(glm::vec3(0.0f, 0.0f, 128.0f), 300.0f, 0.0f);
  const LightmapTexels placed = placeLightmapTexels(scene);
  ASSERT_EQ(placed.pages.size(), 6u);
  EXPECT_EQ(placed.texels.size(), 6u * 64u * 64u);
  // Floor page: pixel (x, y) lies at (-256 + 8x + 4, -256 + 8y + 4, 0), facing up.
  const LightmapTexels::Page& floor = placed.pages[0];
  const int32_t index = floor.texel[size_t(10) * 64 + 20];
  ASSERT_GE(index, 0);
  const LightmapTexel& t = placed.texels[size_t(index)];
  EXPECT_NEAR(t.position.x, -256.0f + 8.0f * 20.0f + 4.0f, 1e-3f);
  EXPECT_NEAR(t.position.y, -256.0f + 8.0f * 10.0f + 4.0f, 1e-3f);
  EXPECT_NEAR(t.position.z, 0.0f, 1e-3f);
  EXPECT_NEAR(t.normal.z, 1.0f, 1e-5f);
}

TEST(LightmapLights, RecoversOneLightWithoutAGrid) {
  const glm::vec3 light(60.0f, -40.0f, 140.0f);
  const WorldScene scene = testing::syntheticLitRoom(light, 300.0f, 0.0f);
  LightmapLightStats lightmapStats;
  const std::vector<WorldLight> candidates =
      lightsFromLightmaps(scene, kNothingKnown, {}, kNothingBlocks, {}, {}, &lightmapStats);
  ASSERT_FALSE(candidates.empty());
  EXPECT_GE(lightmapStats.peaks, 1u);
  // The strongest candidate sits on the light.
  EXPECT_LT(glm::length(candidates[0].position - light), 8.0f) << candidates[0].source;
  for (const WorldLight& c : candidates) {
    EXPECT_TRUE(c.estimated);
    EXPECT_TRUE(std::isfinite(c.quakeIntensity) && c.quakeIntensity > 0.0f);
  }
  LightCalibrationStats stats;
  const std::vector<WorldLight> lights = lightsRecoveredFrom(scene, &stats);
  ASSERT_GE(lights.size(), 1u);
  EXPECT_EQ(stats.admittedFromLightmaps, lights.size());
  for (const WorldLight& l : lights) EXPECT_LT(glm::length(l.position - light), 16.0f) << l.source;
  EXPECT_NEAR(valueNear(lights, light, 16.0f), 300.0f, 300.0f * 0.1f);
}

TEST(LightmapLights, RecoversTwoLightsAndTheirValues) {
  // Each light's floor peak is pulled aside by the other light's slope: the candidates proposed
  // there land 30-50 units off and take 10-15% of the value; the strongest light found near each
  // true light is on it.
  const glm::vec3 first(-150.0f, -120.0f, 180.0f), second(140.0f, 130.0f, 90.0f);
  const WorldScene scene = testing::syntheticLitRoom({{first, 250.0f}, {second, 400.0f}}, 4.0f);
  const std::vector<WorldLight> lights = lightsRecoveredFrom(scene);
  ASSERT_GE(lights.size(), 2u);
  std::string list;
  float elsewhere = 0.0f;
  for (const WorldLight& l : lights) {
    list += l.source + " (" + std::to_string(l.position.x) + " " + std::to_string(l.position.y) + " " +
            std::to_string(l.position.z) + ") value " + std::to_string(l.quakeIntensity) + "\n";
    if (glm::length(l.position - first) >= 64.0f && glm::length(l.position - second) >= 64.0f) elsewhere += l.quakeIntensity;
  }
  for (const auto& [truth, value] : {std::pair{first, 250.0f}, std::pair{second, 400.0f}}) {
    const WorldLight* strongest = nullptr;
    for (const WorldLight& l : lights)
      if (glm::length(l.position - truth) < 64.0f && (!strongest || l.quakeIntensity > strongest->quakeIntensity)) strongest = &l;
    ASSERT_NE(strongest, nullptr) << list;
    EXPECT_LT(glm::length(strongest->position - truth), 8.0f) << list;
    EXPECT_NEAR(strongest->quakeIntensity, value, value * 0.2f) << list;
    EXPECT_NEAR(valueNear(lights, truth, 64.0f), value, value * 0.1f) << list;
  }
  EXPECT_LT(elsewhere, 0.05f * 650.0f) << list;
}

TEST(LightmapLights, KnownLightLeavesNothingToPropose) {
  const glm::vec3 light(0.0f, 30.0f, 120.0f);
  const WorldScene scene = testing::syntheticLitRoom(light, 300.0f, 0.0f);
  const KnownLightAt exact = [&](const glm::vec3& p, const glm::vec3& n) {
    const glm::vec3 toLight = light - p;
    const float d = glm::length(toLight);
    const float clamped = std::max(d, 16.0f);
    return 3.0f * 300.0f * kQ3mapPointScale * std::max(0.0f, glm::dot(n, toLight) / d) / (clamped * clamped);
  };
  LightmapLightStats stats;
  EXPECT_TRUE(lightsFromLightmaps(scene, exact, {}, kNothingBlocks, {}, {}, &stats).empty());
  EXPECT_GE(stats.peaks, 1u);
  EXPECT_EQ(stats.unexplained, 0u);
}

TEST(LightmapLights, NoCandidateInsideSolidOrNearAKnownLight) {
  const glm::vec3 light(-30.0f, 20.0f, 130.0f);
  const WorldScene scene = testing::syntheticLitRoom(light, 300.0f, 0.0f);
  const PointInSolid everywhere = [](const glm::vec3&) { return true; };
  LightmapLightStats stats;
  EXPECT_TRUE(lightsFromLightmaps(scene, kNothingKnown, {}, kNothingBlocks, everywhere, {}, &stats).empty());
  EXPECT_GT(stats.rejected, 0u);
  for (const WorldLight& c : lightsFromLightmaps(scene, kNothingKnown, {light}, kNothingBlocks, {}))
    EXPECT_GE(glm::length(c.position - light), LightmapLightOptions{}.mergeDistance);
}

TEST(LightmapLights, DarkAndSaturatedLightmapsGiveNoLightsAndNoNaN) {
  WorldScene dark = testing::syntheticLitRoom(glm::vec3(0.0f, 0.0f, 128.0f), 300.0f, 0.0f);
  for (WorldImage& image : dark.lightmaps) std::fill(image.rgba8.begin(), image.rgba8.end(), uint8_t(0));
  EXPECT_TRUE(lightsFromLightmaps(dark, kNothingKnown, {}, kNothingBlocks, {}).empty());
  WorldScene saturated = dark;
  for (WorldImage& image : saturated.lightmaps) std::fill(image.rgba8.begin(), image.rgba8.end(), uint8_t(255));
  for (const WorldLight& l : lightsFromLightmaps(saturated, kNothingKnown, {}, kNothingBlocks, {})) {
    EXPECT_TRUE(std::isfinite(l.position.x) && std::isfinite(l.position.y) && std::isfinite(l.position.z));
    EXPECT_TRUE(std::isfinite(l.quakeIntensity));
  }
}

TEST(LightmapLights, HostileMeshesAndLightmapsAreSkipped) {
  EXPECT_TRUE(lightsFromLightmaps(WorldScene{}, kNothingKnown, {}, kNothingBlocks, {}).empty());
  WorldScene scene = testing::syntheticLitRoom(glm::vec3(0.0f, 0.0f, 128.0f), 300.0f, 0.0f);
  const float nan = std::numeric_limits<float>::quiet_NaN(), huge = 1.0e30f;
  scene.lightmaps[0].rgba8.resize(7);                              // truncated
  scene.lightmaps[1].width = 0;                                    // empty
  scene.models[0].meshes[2].indices = {0, 1, 99};                  // out of range
  scene.models[0].meshes[3].lightmapUvs[1] = glm::vec2(nan, 0.5f);  // NaN UV
  scene.models[0].meshes[4].lightmapUvs = {{-huge, -huge}, {huge, -huge}, {huge, huge}, {-huge, huge}};
  scene.models[0].meshes[5].positions[0] = glm::vec3(nan);         // NaN corner
  scene.models[0].meshes[5].lightmap = 1000;                       // no such lightmap
  const LightmapTexels placed = placeLightmapTexels(scene, size_t(1) << 16);
  EXPECT_LE(placed.texels.size(), size_t(1) << 16);
  for (const LightmapTexel& t : placed.texels)
    EXPECT_TRUE(std::isfinite(t.position.x) && std::isfinite(t.normal.z) && std::isfinite(t.value));
  for (const WorldLight& l : lightsFromLightmaps(scene, kNothingKnown, {}, kNothingBlocks, {})) {
    EXPECT_TRUE(std::isfinite(l.position.x) && std::isfinite(l.position.y) && std::isfinite(l.position.z));
    EXPECT_TRUE(std::isfinite(l.quakeIntensity) && l.quakeIntensity > 0.0f);
  }
}

TEST(LightmapLights, PixelTestsAreBounded) {
  const WorldScene scene = testing::syntheticLitRoom(glm::vec3(0.0f, 0.0f, 128.0f), 300.0f, 0.0f);
  EXPECT_LE(placeLightmapTexels(scene, 1000).texels.size(), 1000u);
  EXPECT_TRUE(placeLightmapTexels(scene, size_t(1) << 24, 100).pages.empty());   // 64x64 pages do not fit
}

}  // namespace
}  // namespace pa::recovery
