// Light grid sampling.
#include <gtest/gtest.h>

#include <cmath>

#include <glm/geometric.hpp>

#include "port/q3formats/bsp/light_grid.h"
#include "port/q3formats/bsp/tests/bsp_writer.h"

namespace q3 {
namespace {

TEST(LightGrid, DirectionBytes) {
  auto near = [](glm::vec3 a, glm::vec3 b) { return glm::distance(a, b) < 1e-5f; };
  EXPECT_TRUE(near(lightGridDirection(0, 0), {0, 0, 1}));
  EXPECT_TRUE(near(lightGridDirection(64, 0), {1, 0, 0}));   // longitude 90 degrees, latitude 0
  EXPECT_TRUE(near(lightGridDirection(64, 64), {0, 1, 0}));  // latitude 90 degrees
  EXPECT_TRUE(near(lightGridDirection(128, 0), {0, 0, -1}));
}

TEST(LightGrid, TrilinearSampleSkipsSolidPoints) {
  auto w = testing::sampleMap();  // 3 x 3 x 1 points, 128 apart, origin (0, 0, 0)
  auto point = [&](int x, int y) { return w.lightGrid.begin() + (y * 3 + x) * 8; };
  const uint8_t bright[8] = {100, 50, 0, 200, 200, 200, 64, 0};
  const uint8_t dark[8] = {0, 10, 20, 0, 0, 0, 0, 0};
  std::copy(bright, bright + 8, point(1, 0));
  std::copy(dark, dark + 8, point(0, 0));
  const BspFile bsp = parseBsp(w.build(), "grid.bsp");

  const auto atPoint = sampleLightGrid(bsp.lightGrid, {128, 0, 0});
  ASSERT_TRUE(atPoint.valid);
  EXPECT_EQ(atPoint.ambient, glm::vec3(100, 50, 0));
  EXPECT_EQ(atPoint.directed, glm::vec3(200));
  EXPECT_LT(glm::distance(atPoint.direction, glm::vec3(1, 0, 0)), 1e-5f);

  const auto between = sampleLightGrid(bsp.lightGrid, {32, 0, 0});  // 3/4 dark, 1/4 bright
  EXPECT_NEAR(between.ambient.x, 25.0f, 1e-4f);
  EXPECT_NEAR(between.ambient.y, 0.75f * 10 + 0.25f * 50, 1e-4f);
  EXPECT_NEAR(between.directed.x, 50.0f, 1e-4f);

  // Outside the grid the engine clamps the cell but keeps the fraction: y = -500 is cell -4 +
  // 0.094 -> cell 0 with 9.4 % of row 1 (10, 20, 30); z has one point, so only the lower corner
  // counts (weight 0.031) and the remaining weights are renormalised.
  const auto outside = sampleLightGrid(bsp.lightGrid, {128, -500, -900});
  const float fy = -500.0f / 128.0f - std::floor(-500.0f / 128.0f);
  EXPECT_NEAR(outside.ambient.x, (1 - fy) * 100 + fy * 10, 1e-3f);
  EXPECT_NEAR(outside.ambient.y, (1 - fy) * 50 + fy * 20, 1e-3f);
  EXPECT_NEAR(outside.ambient.z, fy * 30, 1e-3f);

  // An all-black neighbour (inside a wall) is left out and the weights renormalised.
  std::fill(point(0, 0), point(0, 0) + 8, 0);
  const BspFile solid = parseBsp(w.build(), "grid.bsp");
  EXPECT_EQ(sampleLightGrid(solid.lightGrid, {32, 0, 0}).ambient, glm::vec3(100, 50, 0));
}

TEST(LightGrid, ColorShiftBrightensAndKeepsHue) {
  auto w = testing::sampleMap();
  const uint8_t point[8] = {10, 20, 30, 100, 50, 25, 7, 9};
  std::copy(point, point + 8, w.lightGrid.begin());
  const BspFile bsp = parseBsp(w.build(), "grid.bsp");
  const BspLightGrid shifted = shiftLightGridColors(bsp.lightGrid, 2);
  // x4: (40, 80, 120) fits; (400, 200, 100) is scaled by 255/400 with integer division.
  EXPECT_EQ(std::vector<uint8_t>(shifted.raw.begin(), shifted.raw.begin() + 8),
            (std::vector<uint8_t>{40, 80, 120, 255, 127, 63, 7, 9}));
  EXPECT_EQ(shiftLightGridColors(bsp.lightGrid, 0).raw, bsp.lightGrid.raw);
}

TEST(LightGrid, NoGridGivesInvalidSample) {
  auto w = testing::sampleMap();
  w.lightGrid.clear();
  const BspFile bsp = parseBsp(w.build(), "nogrid.bsp");
  EXPECT_FALSE(bsp.lightGrid.valid);
  EXPECT_FALSE(sampleLightGrid(bsp.lightGrid, {0, 0, 0}).valid);
}

}  // namespace
}  // namespace q3
