// Real-map checks of light recovery (OpenArena data, skipped when not installed).
#include <algorithm>
#include <filesystem>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "port/light_recovery/grid_estimate.h"
#include "port/q3formats/world/world_game.h"

namespace pa::recovery {
namespace {

using namespace q3;

const std::filesystem::path kGameDir = "/usr/share/games/openarena/baseoa";

TEST(RealMapGridEstimate, FindsTheHiddenLightsOfAMapThatKeptThem) {
  if (!std::filesystem::exists(kGameDir / "pak1-maps.pk3")) GTEST_SKIP() << "OpenArena data not installed at " << kGameDir;
  const GameWorlds game(kGameDir);
  // q3dm6ish kept its 30 light entities: hide them, estimate from the grid, compare.
  WorldBuildOptions options;
  options.loadTextures = false;
  WorldScene scene = game.load("q3dm6ish", options);
  std::vector<WorldLight> real;
  std::erase_if(scene.lights, [&](const WorldLight& l) {
    if (l.type == WorldLightType::Sun) return false;
    real.push_back(l);
    return true;
  });
  ASSERT_GE(real.size(), 20u);
  const std::vector<WorldLight> estimated = estimateLightsFromGrid(scene.lightGrid, knownLightingOf(scene));
  ASSERT_FALSE(estimated.empty());
  // Most of the light value is found within 64 units, at about the right value.
  double total = 0.0, found = 0.0;
  for (const WorldLight& r : real) {
    total += r.quakeIntensity;
    for (const WorldLight& e : estimated)
      if (glm::length(e.position - r.position) < 64.0f && e.quakeIntensity > r.quakeIntensity / 1.5f &&
          e.quakeIntensity < r.quakeIntensity * 1.5f) {
        found += r.quakeIntensity;
        break;
      }
  }
  EXPECT_GT(found / total, 0.5);   // measured 71% (docs/performance.md)
  size_t near = 0;
  for (const WorldLight& e : estimated)
    near += std::any_of(real.begin(), real.end(),
                        [&](const WorldLight& r) { return glm::length(e.position - r.position) < 64.0f; });
  EXPECT_GT(double(near) / double(estimated.size()), 0.6);   // measured 82%
}

}  // namespace
}  // namespace pa::recovery
