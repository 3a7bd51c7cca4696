// EnvironmentVisibility (lights/environment_visibility.h) and how the light sampler uses it: a
// synthetic escape test (rays escape only from x > 0) stands in for a level whose west half is
// closed; the sampler keeps its choice where sun and sky are reachable and gives the local
// emitters the environment's share where they are not, with pdfs that match the sampling.
#include <gtest/gtest.h>

#include <memory>
#include <numbers>
#include <vector>

#include <glm/geometric.hpp>

#include "renderer/scene/lights/environment_visibility.h"
#include "renderer/scene/lights/light_sampler.h"

namespace pa {
namespace {

constexpr float kPi = std::numbers::pi_v<float>;

/// Upward-facing points 1 apart on a 40 x 40 floor at z = 0 (x, y = -19.5 ... 19.5).
std::vector<SurfacePoint> floorPoints() {
  std::vector<SurfacePoint> points;
  for (int y = 0; y < 40; ++y)
    for (int x = 0; x < 40; ++x) points.push_back({glm::vec3(x - 19.5f, y - 19.5f, 0.0f), glm::vec3(0, 0, 1)});
  return points;
}

bool eastEscapes(const glm::vec3& origin, const glm::vec3&) { return origin.x > 0.0f; }

TEST(EnvironmentVisibility, SharesFollowTheEscapedFractionPerFacing) {
  const std::vector<glm::vec3> suns = {glm::normalize(glm::vec3(0.3f, 0.0f, -1.0f))};
  const EnvironmentVisibility map(floorPoints(), suns, true, eastEscapes);
  ASSERT_GT(map.binCount(), 0u);
  const glm::vec3 up(0, 0, 1);
  EXPECT_EQ(map.share({-9.5f, 2.5f, 0.1f}, up), EnvironmentVisibility::kHiddenShare);
  EXPECT_EQ(map.share({9.5f, 2.5f, -0.1f}, up), 1.0f);
  EXPECT_GT(map.closedCount(), 0u);
  // Other facings in the same cell have no points: unchanged. Outside the grid: unchanged.
  EXPECT_EQ(map.share({-9.5f, 2.5f, 0.0f}, glm::vec3(1, 0, 0)), 1.0f);
  EXPECT_EQ(map.share({-500.0f, 3.0f, 0.0f}, up), 1.0f);
  EXPECT_EQ(EnvironmentVisibility::normalBin({0.2f, -0.9f, 0.1f}), 3u);
  // Neither sun nor sky, or no points: an empty map, every share 1.
  EXPECT_EQ(EnvironmentVisibility(floorPoints(), {}, false, eastEscapes).binCount(), 0u);
  EXPECT_EQ(EnvironmentVisibility({}, suns, true, eastEscapes).share({-10.0f, 0.0f, 0.0f}, up), 1.0f);
}

TEST(EnvironmentVisibility, CacheRebuildsOnlyWhenItsInputsChange) {
  EnvironmentVisibilityCache cache;
  int traced = 0;
  const auto points = [&traced] {
    ++traced;
    return floorPoints();
  };
  Bounds bounds;
  bounds.extend(glm::vec3(-20.0f));
  bounds.extend(glm::vec3(20.0f));
  const std::vector<glm::vec3> suns = {glm::vec3(0, 0, -1)};
  const auto first = cache.get(bounds, suns, true, {}, points, eastEscapes);
  EXPECT_EQ(cache.get(bounds, suns, true, {}, points, eastEscapes), first);
  EXPECT_EQ(traced, 1);
  EXPECT_NE(cache.get(bounds, suns, false, {}, points, eastEscapes), first);
  EXPECT_EQ(traced, 2);
}

TEST(LightSampler, ClosedBinsHandTheEnvironmentShareToLocalLights) {
  // A point light, a sun and a constant sky; the sun and sky take ~80% of the choice.
  LightDesc lamp;
  lamp.position = {0.0f, 0.0f, 5.0f};
  lamp.intensity = 1000.0f;
  LightDesc sun;
  sun.type = LightType::Directional;
  sun.direction = glm::vec3(0, 0, -1);
  sun.intensity = 10.0f;
  SkyDesc skyDesc;
  skyDesc.color = glm::vec3(1.0f);
  const Sky sky(skyDesc, {});
  Bounds bounds;
  bounds.extend(glm::vec3(-20.0f));
  bounds.extend(glm::vec3(20.0f));
  LightSampler sampler(std::vector<LightDesc>{lamp, sun}, {}, sky, bounds);
  ASSERT_TRUE(sampler.mixesEnvironmentAndLocal());
  const glm::vec3 n(0, 0, 1), west(-9.5f, 0.5f, 0.0f), east(9.5f, 0.5f, 0.0f);
  const float skyWest = sampler.skyPdf(west, n, n), skyEast = sampler.skyPdf(east, n, n);
  EXPECT_EQ(skyWest, skyEast);   // no map yet: the same everywhere
  sampler.setEnvironmentVisibility(
      std::make_shared<const EnvironmentVisibility>(floorPoints(), sampler.sunDirections(), true, eastEscapes));
  EXPECT_EQ(sampler.skyPdf(east, n, n), skyEast);   // open: unchanged
  // Closed: the sky keeps kHiddenShare of its probability, renormalised against the lamp's.
  const double skyShare = skyWest * kPi;   // constant sky: cosine lobe pdf 1 / pi along n
  const int draws = 20000;
  int environment = 0;
  for (int i = 0; i < draws; ++i) {
    LightSample s;
    const glm::vec4 u((i + 0.5f) / draws, 0.37f, 0.61f, 0.23f);
    if (sampler.sample(west, n, u, s) && s.environment) ++environment;
  }
  const double picked = double(environment) / draws;
  EXPECT_LT(picked, 0.05);
  EXPECT_GT(picked, 0.0);   // never 0: unbiased where a bin is judged wrongly
  // The sky's pdf at the closed point is its probability there (the sun's and the sky's summed
  // share, cut to kHiddenShare and renormalised) times the lobe: consistent with the draws.
  const double skyWestNow = double(sampler.skyPdf(west, n, n)) * kPi;
  EXPECT_GT(skyShare, 0.1);
  EXPECT_LT(skyWestNow, skyShare * 0.05);
  EXPECT_GT(skyWestNow, 0.0);
  EXPECT_LE(skyWestNow, picked + 1e-3);
}

}  // namespace
}  // namespace pa
