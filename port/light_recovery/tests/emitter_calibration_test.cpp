// Known-answer tests of the emitter fit: a room whose lightmaps were baked with a ceiling lamp
// at a known share of its shader's value must give that share back.
#include <gtest/gtest.h>

#include <cmath>

#include "port/light_recovery/emitter_calibration.h"
#include "port/light_recovery/recover_lights.h"
#include "port/light_recovery/tests/synthetic_lit_room.h"
#include "port/q3formats/world/world_lights.h"

namespace pa::recovery {
namespace {

using namespace q3;

const SegmentBlocked kNothingBlocks = [](const glm::vec3&, const glm::vec3&) { return false; };

/// A 32 x 32 lamp facing down, 8 units under the ceiling's centre, in two triangles.
std::vector<CalibrationEmitter> ceilingLamp(float radianceSum, int32_t group) {
  const float z = testing::kRoomHeight - 8.0f;
  const glm::vec3 a(-16, -16, z), b(16, -16, z), c(16, 16, z), d(-16, 16, z);
  // Counter-clockwise seen from below (the front faces down).
  return {{a, c, b, radianceSum, false, group}, {a, d, c, radianceSum, false, group}};
}

/// Adds `share` of the lamps' light to every lightmap texel of the room (the model's form:
/// L * A * cos * cos' / max(d^2, A) in light-value units, from each triangle's centre), as if
/// the compiler had lit the room with the lamp at that share of its value.
void bakeLamp(WorldScene& scene, const std::vector<CalibrationEmitter>& lamp, float share) {
  const auto walls = testing::roomWalls();
  for (size_t w = 0; w < walls.size(); ++w) {
    WorldImage& image = scene.lightmaps[w];
    for (uint32_t y = 0; y < image.height; ++y)
      for (uint32_t x = 0; x < image.width; ++x) {
        const glm::vec3 p = walls[w].origin + walls[w].u * ((float(x) + 0.5f) / float(image.width)) +
                            walls[w].v * ((float(y) + 0.5f) / float(image.height));
        float value = 0.0f;   // summed over RGB
        for (const CalibrationEmitter& e : lamp) {
          const glm::vec3 centre = (e.a + e.b + e.c) / 3.0f, cross = glm::cross(e.b - e.a, e.c - e.a);
          const float area = 0.5f * glm::length(cross);
          const glm::vec3 to = centre - p;
          const float d2 = glm::dot(to, to), d = std::sqrt(d2);
          const float cosR = glm::dot(walls[w].normal, to) / d, cosE = -glm::dot(cross / (2.0f * area), to / d);
          if (cosR > 0.0f && cosE > 0.0f)
            value += kQ3FullBright / 3.14159265f * e.radiance * area * cosR * cosE / std::max(d2, area);
        }
        uint8_t* texel = &image.rgba8[(size_t(y) * image.width + x) * 4];
        const long byte = std::lround(float(texel[0]) + share * value / 3.0f);
        texel[0] = texel[1] = texel[2] = uint8_t(std::clamp(byte, 0l, 255l));
      }
  }
}

float fittedShare(float bakedShare, float radianceSum) {
  const std::vector<CalibrationEmitter> lamp = ceilingLamp(radianceSum, 0);
  WorldScene scene = testing::syntheticLitRoom({}, 6.0f);
  bakeLamp(scene, lamp, bakedShare);
  EmitterFitStats stats;
  const std::vector<float> scales = fitEmitterScales(scene, {}, {}, {}, lamp, 1, kNothingBlocks, {}, &stats);
  EXPECT_EQ(scales.size(), 1u);
  EXPECT_EQ(stats.groups, 1u);
  return scales.empty() ? -1.0f : scales[0];
}

TEST(EmitterCalibration, ALampTheBakeShowsAtAQuarterIsScaledToAQuarter) {
  EXPECT_NEAR(fittedShare(0.25f, 30.0f), 0.25f, 0.03f);
}

TEST(EmitterCalibration, ALampTheBakeShowsInFullKeepsItsValue) {
  EXPECT_NEAR(fittedShare(1.0f, 30.0f), 1.0f, 0.03f);
}

TEST(EmitterCalibration, ALampTheBakeNeverSawIsTurnedOff) {
  EXPECT_LT(fittedShare(0.0f, 30.0f), 0.03f);
}

TEST(EmitterCalibration, UngroupedEmittersAndUnlitGroupsKeepTheirValue) {
  WorldScene scene = testing::syntheticLitRoom({}, 6.0f);
  std::vector<CalibrationEmitter> lamps = ceilingLamp(30.0f, -1);   // known light, not fitted
  const std::vector<CalibrationEmitter> hidden = ceilingLamp(0.0f, 1); // group 1 lights nothing
  lamps.insert(lamps.end(), hidden.begin(), hidden.end());
  EmitterFitStats stats;
  const std::vector<float> scales = fitEmitterScales(scene, {}, {}, {}, lamps, 3, kNothingBlocks, {}, &stats);
  EXPECT_EQ(scales, std::vector<float>(3, 1.0f));
  EXPECT_EQ(stats.groups, 0u);
}

TEST(EmitterCalibration, HostileGroupsAndNoVisibilityLeaveEveryScaleAtOne) {
  WorldScene scene = testing::syntheticLitRoom({}, 6.0f);
  const std::vector<CalibrationEmitter> lamp = ceilingLamp(30.0f, 7);   // group past the count
  EXPECT_EQ(fitEmitterScales(scene, {}, {}, {}, lamp, 2, kNothingBlocks), std::vector<float>(2, 1.0f));
  EXPECT_EQ(fitEmitterScales(scene, {}, {}, {}, ceilingLamp(30.0f, 0), 1, SegmentBlocked{}), std::vector<float>(1, 1.0f));
}

TEST(EmitterCalibration, ApplyingARecoveryScalesEachSurfaceLightByItsShareOnly) {
  WorldScene scene;
  scene.materials.resize(4);
  for (WorldMaterial& m : scene.materials) m.surfaceLight = 1000.0f;
  RecoveredLights recovered;
  recovered.lights.push_back(testing::estimatedLight(glm::vec3(1.0f), 50.0f));
  recovered.surfaceLightScales = {0.25f, 2.0f, std::nanf("")};   // never raised; NaN ignored; 4th: none
  applyRecoveredLights(scene, recovered);
  ASSERT_EQ(scene.lights.size(), 1u);
  EXPECT_FLOAT_EQ(scene.materials[0].surfaceLight, 250.0f);
  EXPECT_FLOAT_EQ(scene.materials[1].surfaceLight, 1000.0f);
  EXPECT_FLOAT_EQ(scene.materials[2].surfaceLight, 1000.0f);
  EXPECT_FLOAT_EQ(scene.materials[3].surfaceLight, 1000.0f);
}

}  // namespace
}  // namespace pa::recovery
