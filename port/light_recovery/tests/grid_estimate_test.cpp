// Known-answer tests of the light-grid estimator: a grid baked from known point lights the way
// q3map2's TraceGrid does (without occlusion) must give those lights back.
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "port/q3formats/bsp/light_grid.h"
#include "port/light_recovery/grid_estimate.h"
#include "port/q3formats/world/world_lights.h"

namespace pa::recovery {
namespace {

using namespace q3;

struct TestLight {
  glm::vec3 position;
  float value;
  glm::vec3 color{1.0f};
};

/// Longitude/latitude bytes of a unit direction (inverse of lightGridDirection).
std::array<uint8_t, 2> encodeDirection(const glm::vec3& d) {
  constexpr float kStep = 2.0f * std::numbers::pi_v<float> / 256.0f;
  const float polar = std::acos(std::clamp(d.z, -1.0f, 1.0f));
  float azimuth = std::atan2(d.y, d.x);
  if (azimuth < 0.0f) azimuth += 2.0f * std::numbers::pi_v<float>;
  return {uint8_t(int(std::lround(polar / kStep)) & 255), uint8_t(int(std::lround(azimuth / kStep)) & 255)};
}

/// Bytes of a light-value colour, scaled down as a whole past 255 (q3map2's ColorToBytes).
std::array<uint8_t, 3> toBytes(glm::vec3 c) {
  const float peak = std::max({c.r, c.g, c.b});
  if (peak > 255.0f) c *= 255.0f / peak;
  return {uint8_t(std::lround(c.r)), uint8_t(std::lround(c.g)), uint8_t(std::lround(c.b))};
}

/// A grid over [0, size] baked from `lights` plus suns (towards, value) like q3map2's TraceGrid.
WorldLightGrid bakeGrid(glm::vec3 size, const std::vector<TestLight>& lights,
                        const std::vector<std::pair<glm::vec3, float>>& suns = {}) {
  WorldLightGrid grid;
  grid.origin = glm::vec3(0.0f);
  grid.cellSize = {64.0f, 64.0f, 128.0f};
  for (int k = 0; k < 3; ++k) grid.counts[size_t(k)] = int(size[k] / grid.cellSize[k]) + 1;
  for (int z = 0; z < grid.counts[2]; ++z)
    for (int y = 0; y < grid.counts[1]; ++y)
      for (int x = 0; x < grid.counts[0]; ++x) {
        const glm::vec3 p = glm::vec3(x, y, z) * grid.cellSize;
        std::vector<std::pair<glm::vec3, glm::vec3>> contributions;   // direction, colour
        for (const TestLight& l : lights) {
          const float d = std::max(16.0f, glm::length(l.position - p));
          contributions.emplace_back(glm::normalize(l.position - p + glm::vec3(1e-4f)),
                                     l.color * l.value * kQ3mapPointScale / (d * d));
        }
        for (const auto& [towards, value] : suns) contributions.emplace_back(towards, glm::vec3(value));
        glm::vec3 sum(0.0f);
        for (const auto& [dir, color] : contributions) sum += glm::length(color) * dir;
        const glm::vec3 main = glm::normalize(sum);
        glm::vec3 directed(0.0f), ambient(0.0f);
        for (const auto& [dir, color] : contributions) {
          const float d = std::max(0.0f, glm::dot(dir, main));
          directed += d * color;
          ambient += 0.25f * (1.0f - d) * color;
        }
        const auto a = toBytes(ambient), di = toBytes(directed);
        const auto angles = encodeDirection(main);
        grid.samples.push_back({a[0], a[1], a[2], di[0], di[1], di[2], angles[0], angles[1]});
      }
  return grid;
}

const WorldLight* nearest(const std::vector<WorldLight>& lights, const glm::vec3& p) {
  const WorldLight* best = nullptr;
  float bestDistance = std::numeric_limits<float>::max();
  for (const WorldLight& l : lights)
    if (float d = glm::length(l.position - p); d < bestDistance) {
      bestDistance = d;
      best = &l;
    }
  return best;
}

TEST(LightEstimate, DirectionBytesRoundTrip) {
  const glm::vec3 d = glm::normalize(glm::vec3(0.3f, -0.5f, 0.8f));
  const auto bytes = encodeDirection(d);
  EXPECT_GT(glm::dot(lightGridDirection(bytes[0], bytes[1]), d), 0.999f);
}

TEST(LightEstimate, RecoversKnownPointLights) {
  const std::vector<TestLight> truth = {
      {{200.0f, 300.0f, 150.0f}, 300.0f},
      {{1500.0f, 700.0f, 330.0f}, 600.0f, {1.0f, 0.5f, 0.25f}},
      {{700.0f, 1300.0f, 420.0f}, 200.0f, {0.5f, 0.75f, 1.0f}},
  };
  const WorldLightGrid grid = bakeGrid({2048.0f, 1536.0f, 640.0f}, truth);
  LightEstimateStats stats;
  const std::vector<WorldLight> found = estimateLightsFromGrid(grid, {}, {}, &stats);
  EXPECT_GT(stats.votingLines, 100u);
  ASSERT_EQ(found.size(), truth.size());
  for (const TestLight& t : truth) {
    const WorldLight* l = nearest(found, t.position);
    ASSERT_NE(l, nullptr);
    EXPECT_LT(glm::length(l->position - t.position), 12.0f) << t.position.x;
    EXPECT_GT(l->quakeIntensity, t.value / 1.3f) << t.position.x;
    EXPECT_LT(l->quakeIntensity, t.value * 1.3f) << t.position.x;
    EXPECT_FLOAT_EQ(l->intensity, pointLightIntensity(l->quakeIntensity));
    EXPECT_LT(glm::length(l->color - t.color), 0.15f) << t.position.x;
    EXPECT_EQ(l->type, WorldLightType::Point);
    EXPECT_FALSE(l->linearFalloff);
  }
}

TEST(LightEstimate, LightsTheSceneAlreadyHasAreNotAddedAgain) {
  const std::vector<TestLight> truth = {{{300.0f, 300.0f, 200.0f}, 400.0f}, {{1200.0f, 900.0f, 300.0f}, 400.0f}};
  const WorldLightGrid grid = bakeGrid({1536.0f, 1280.0f, 512.0f}, truth);
  KnownLighting known;
  known.pointLights.emplace_back(truth[0].position + glm::vec3(4.0f), truth[0].value);
  std::vector<WorldLight> found = estimateLightsFromGrid(grid, known);
  ASSERT_EQ(found.size(), 1u);
  EXPECT_LT(glm::length(found[0].position - truth[1].position), 12.0f);

  KnownLighting emitterThere;
  emitterThere.emitters.emplace_back(truth[1].position + glm::vec3(0.0f, 0.0f, 40.0f), 16.0f);
  found = estimateLightsFromGrid(grid, emitterThere);
  ASSERT_EQ(found.size(), 1u);
  EXPECT_LT(glm::length(found[0].position - truth[0].position), 12.0f);
}

TEST(LightEstimate, SunlitGridGivesNoPointLights) {
  const glm::vec3 towardSun = glm::normalize(glm::vec3(0.4f, 0.2f, 1.0f));
  const WorldLightGrid grid = bakeGrid({1024.0f, 1024.0f, 512.0f}, {}, {{towardSun, 100.0f}});
  KnownLighting known;
  known.towardSuns.push_back(towardSun);
  EXPECT_TRUE(estimateLightsFromGrid(grid, known).empty());
  // Even when the sun is not declared, parallel lines meet nowhere.
  EXPECT_TRUE(estimateLightsFromGrid(grid, {}).empty());
}

TEST(LightEstimate, HostileGridsGiveNothing) {
  WorldLightGrid grid = bakeGrid({512.0f, 512.0f, 256.0f}, {{{200.0f, 200.0f, 100.0f}, 300.0f}});
  ASSERT_FALSE(estimateLightsFromGrid(grid, {}).empty());
  WorldLightGrid shortSamples = grid;
  shortSamples.samples.pop_back();
  EXPECT_TRUE(estimateLightsFromGrid(shortSamples, {}).empty());
  WorldLightGrid nanCell = grid;
  nanCell.cellSize.y = std::numeric_limits<float>::quiet_NaN();
  EXPECT_TRUE(estimateLightsFromGrid(nanCell, {}).empty());
  WorldLightGrid negative = grid;
  negative.counts[1] = -3;
  EXPECT_TRUE(estimateLightsFromGrid(negative, {}).empty());
  WorldLightGrid huge = grid;
  huge.cellSize = glm::vec3(1.0e30f);   // accumulator voxels grow to fit the budget
  EXPECT_NO_THROW(estimateLightsFromGrid(huge, {}));
  EXPECT_TRUE(estimateLightsFromGrid(WorldLightGrid{}, {}).empty());
}

}  // namespace
}  // namespace pa::recovery
