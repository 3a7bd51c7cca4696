// Known answers for the flare pass (flares.h): projection, occlusion against the depth at the
// flare's pixel, fading over time, size and intensity as the stock renderer computes them.
#include <cmath>
#include <limits>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "port/engine_glue/flares.h"

namespace glue {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

/// A 640x360 view at the origin looking along +X, 90 x 90 degrees (tan = 1 both ways).
FlareView view(int timeMs) {
  FlareView v;
  v.width = 640;
  v.height = 360;
  v.timeMs = timeMs;
  return v;
}

FlareDepthQuery constantDepth(float depth) {
  return [depth](float, float) { return depth; };
}

TEST(FlareMath, SizeAndIntensityAsStock) {
  // size = width (r_flareSize / 640 + 8 / distance): 640 (40/640 + 8/320) = 56.
  EXPECT_FLOAT_EQ(flareHalfSize(640.0f, 320.0f, 40.0f), 56.0f);
  // Distances under 1 count as 1.
  EXPECT_FLOAT_EQ(flareHalfSize(640.0f, 0.25f, 40.0f), 640.0f * (40.0f / 640.0f + 8.0f));
  // intensity = 150 56^2 / (320 + 56 sqrt 150)^2.
  const float expected = 150.0f * 56.0f * 56.0f / std::pow(320.0f + 56.0f * std::sqrt(150.0f), 2.0f);
  EXPECT_NEAR(flareIntensity(56.0f, 320.0f, 150.0f), expected, 1e-6f);
  EXPECT_NEAR(flareIntensity(56.0f, 320.0f, 150.0f), 0.4649f, 1e-3f);
  // Never above 1; 1 in the limit of distance 0 (here 1).
  EXPECT_LE(flareIntensity(1e6f, 1.0f, 150.0f), 1.0f);
}

TEST(FlareTracker, ProjectsToTheStockPixel) {
  FlareTracker tracker;
  std::vector<FlareQuad> quads;
  // Straight ahead: the centre of the view; 100 units left of the axis at distance 320 is
  // ndc x = -100/320 -> pixel 0.5 (1 - 0.3125) 640 = 220; 50 up -> 180 + 50/320 180 = 208.125
  // from the bottom, 360 - 208 = 152 from the top.
  const std::vector<Flare> flares{{{320, 0, 0}, {1, 1, 1}, {0, 0, 0}}, {{320, 100, 50}, {1, 1, 1}, {0, 0, 0}}};
  FlareView v = view(1000);
  v.x = 10;
  v.y = 20;
  tracker.update(v, flares, {}, constantDepth(kInf), quads);
  ASSERT_EQ(quads.size(), 2u);
  EXPECT_FLOAT_EQ(quads[0].centerX, 10 + 320.0f);
  EXPECT_FLOAT_EQ(quads[0].centerY, 20 + 180.0f);
  EXPECT_FLOAT_EQ(quads[1].centerX, 10 + 220.0f);
  EXPECT_FLOAT_EQ(quads[1].centerY, 20 + 360.0f - 208.0f);
  EXPECT_FLOAT_EQ(quads[0].halfSize, 56.0f);
}

TEST(FlareTracker, OffScreenBehindAndBackFacingFlaresAreSkipped) {
  FlareTracker tracker;
  std::vector<FlareQuad> quads;
  const std::vector<Flare> flares{
      {{-320, 0, 0}, {1, 1, 1}, {0, 0, 0}},     // behind the camera
      {{2, 0, 0}, {1, 1, 1}, {0, 0, 0}},        // nearer than the near plane (4)
      {{100, 150, 0}, {1, 1, 1}, {0, 0, 0}},    // outside the 90-degree view (ndc x = -1.5)
      {{320, 0, 0}, {1, 1, 1}, {1, 0, 0}},      // facing away from the camera
  };
  tracker.update(view(1000), flares, {}, constantDepth(kInf), quads);
  EXPECT_TRUE(quads.empty());
}

TEST(FlareTracker, FadesInOverTimeAtTheFadeRate) {
  FlareTracker tracker;
  std::vector<FlareQuad> quads;
  const std::vector<Flare> flares{{{320, 0, 0}, {1, 1, 1}, {0, 0, 0}}};
  const FlareParams params;   // fade 7 per second
  const float full = flareIntensity(56.0f, 320.0f, 150.0f);
  // First view in sight: (time - (time - 1)) / 1000 x 7.
  tracker.update(view(1000), flares, params, constantDepth(kInf), quads);
  ASSERT_EQ(quads.size(), 1u);
  EXPECT_NEAR(quads[0].color.x, full * 0.007f, 1e-6f);
  // 50 ms later: 51 ms x 7 / 1000 = 0.357 of full.
  tracker.update(view(1050), flares, params, constantDepth(kInf), quads);
  ASSERT_EQ(quads.size(), 1u);
  EXPECT_NEAR(quads[0].color.x, full * 0.357f, 1e-5f);
  // After 1/7 s it is at full intensity and stays there.
  tracker.update(view(1200), flares, params, constantDepth(kInf), quads);
  ASSERT_EQ(quads.size(), 1u);
  EXPECT_NEAR(quads[0].color.x, full, 1e-6f);
}

TEST(FlareTracker, OccludedFlareFadesOutThenIsForgotten) {
  FlareTracker tracker;
  std::vector<FlareQuad> quads;
  const std::vector<Flare> flares{{{320, 0, 0}, {1, 0.5f, 0.25f}, {0, 0, 0}}};
  const FlareParams params;
  const float full = flareIntensity(56.0f, 320.0f, 150.0f);
  tracker.update(view(1000), flares, params, constantDepth(kInf), quads);
  tracker.update(view(1500), flares, params, constantDepth(kInf), quads);
  ASSERT_EQ(quads.size(), 1u);
  EXPECT_NEAR(quads[0].color.y, 0.5f * full, 1e-6f);
  // A wall 100 units in front of the flare: hidden; fades from 1: 1 - 51 x 7 / 1000.
  tracker.update(view(1550), flares, params, constantDepth(220.0f), quads);
  tracker.update(view(1600), flares, params, constantDepth(220.0f), quads);
  ASSERT_EQ(quads.size(), 1u);
  EXPECT_NEAR(quads[0].color.x, full * (1.0f - 0.051f * 7.0f), 1e-5f);
  // Gone after 1/7 s; seen again it starts from zero.
  tracker.update(view(1800), flares, params, constantDepth(220.0f), quads);
  EXPECT_TRUE(quads.empty());
  tracker.update(view(1850), flares, params, constantDepth(kInf), quads);
  ASSERT_EQ(quads.size(), 1u);
  EXPECT_NEAR(quads[0].color.x, full * 0.007f, 1e-6f);
}

TEST(FlareTracker, SurfacesWithin24UnitsInFrontDoNotHide) {
  FlareTracker tracker;
  std::vector<FlareQuad> quads;
  const std::vector<Flare> flares{{{320, 0, 0}, {1, 1, 1}, {0, 0, 0}}};
  tracker.update(view(1000), flares, {}, constantDepth(300.0f), quads);   // the lamp's own fitting
  EXPECT_EQ(quads.size(), 1u);
  FlareTracker hidden;
  hidden.update(view(1000), flares, {}, constantDepth(295.0f), quads);    // 25 units in front
  EXPECT_TRUE(quads.empty());
}

TEST(FlareTracker, LeavingTheViewResetsTheFade) {
  FlareTracker tracker;
  std::vector<FlareQuad> quads;
  const std::vector<Flare> flares{{{320, 0, 0}, {1, 1, 1}, {0, 0, 0}}};
  const float full = flareIntensity(56.0f, 320.0f, 150.0f);
  tracker.update(view(1000), flares, {}, constantDepth(kInf), quads);
  tracker.update(view(1500), flares, {}, constantDepth(kInf), quads);
  EXPECT_NEAR(quads.at(0).color.x, full, 1e-6f);
  FlareView away = view(1550);
  away.forward = {-1, 0, 0};
  away.left = {0, -1, 0};
  tracker.update(away, flares, {}, constantDepth(kInf), quads);
  EXPECT_TRUE(quads.empty());
  tracker.update(view(1600), flares, {}, constantDepth(kInf), quads);   // back: fades in again
  EXPECT_NEAR(quads.at(0).color.x, full * 0.007f, 1e-6f);
}

TEST(FlareTracker, FacingDimsByTheCosine) {
  FlareTracker tracker;
  std::vector<FlareQuad> quads;
  const glm::vec3 normal = glm::normalize(glm::vec3(-1, 1, 0));   // 45 degrees off the camera
  const std::vector<Flare> flares{{{320, 0, 0}, {1, 1, 1}, normal}};
  tracker.update(view(1000), flares, {}, constantDepth(kInf), quads);
  tracker.update(view(2000), flares, {}, constantDepth(kInf), quads);
  EXPECT_NEAR(quads.at(0).color.x, flareIntensity(56.0f, 320.0f, 150.0f) * std::sqrt(0.5f), 1e-6f);
}

}  // namespace
}  // namespace glue
