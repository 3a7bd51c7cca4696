// Light grid sampling.
#include <gtest/gtest.h>

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

  // Outside the grid: clamped to the edge.
  EXPECT_EQ(sampleLightGrid(bsp.lightGrid, {128, -500, -900}).ambient, glm::vec3(100, 50, 0));

  // An all-black neighbour (inside a wall) is left out and the weights renormalised.
  std::fill(point(0, 0), point(0, 0) + 8, 0);
  const BspFile solid = parseBsp(w.build(), "grid.bsp");
  EXPECT_EQ(sampleLightGrid(solid.lightGrid, {32, 0, 0}).ambient, glm::vec3(100, 50, 0));
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
