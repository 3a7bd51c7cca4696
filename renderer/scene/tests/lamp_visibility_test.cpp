// LampVisibility (lights/lamp_visibility.h) and how the light sampler uses it: a synthetic reach
// test (a wall along x = 0 that no shadow ray crosses) stands in for a level; lamps behind the
// wall count as hidden on the other side, are chosen kHiddenWeight as often there, and the
// estimator stays exact whatever the map says (unbiased), even when the map is wrong.
#include <gtest/gtest.h>

#include <vector>

#include <glm/geometric.hpp>

#include "renderer/scene/lights/lamp_visibility.h"
#include "renderer/scene/lights/light_sampler.h"
#include "scene_builders.h"

namespace pa {
namespace {

/// Upward-facing points 0.25 apart on a 64 x 64 floor at z = 0 (x, y = -31.875 ... 31.875):
/// about 16 in each bin of a 64-cell grid.
std::vector<SurfacePoint> floorPoints() {
  std::vector<SurfacePoint> points;
  for (int y = 0; y < 256; ++y)
    for (int x = 0; x < 256; ++x)
      points.push_back({glm::vec3(0.25f * float(x) - 31.875f, 0.25f * float(y) - 31.875f, 0.0f), glm::vec3(0, 0, 1)});
  return points;
}

/// A wall along x = 0: a ray reaches its end only on the same side.
bool wallAtZero(const glm::vec3& from, const glm::vec3& to) { return (from.x > 0.0f) == (to.x > 0.0f); }

LightDesc lampAt(const glm::vec3& position, float intensity = 100.0f) {
  LightDesc l;
  l.position = position;
  l.intensity = intensity;
  return l;
}

/// Two lamps either side of the wall, a third out of every floor point's range.
std::vector<LightDesc> westEastAndFar() {
  LightDesc far = lampAt({0.0f, 0.0f, 500.0f});
  far.falloff = Falloff::Linear;
  far.range = 100.0f;
  return {lampAt({-10.0f, 0.0f, 8.0f}), lampAt({10.0f, 0.0f, 8.0f}, 400.0f), far};
}

/// E[radiance / pdf] over the lamp choice at p, n: every lamp's contribution times the
/// probability with which sample() picks it, summed over a fine stratification of u.w.
glm::vec3 estimatorMean(const LightSampler& sampler, const glm::vec3& p, const glm::vec3& n) {
  constexpr int kStrata = 1 << 14;
  glm::dvec3 sum(0.0);
  for (int i = 0; i < kStrata; ++i) {
    LightSample ls;
    if (!sampler.sample(p, n, glm::vec4(0.5f, 0.5f, 0.5f, (float(i) + 0.5f) / float(kStrata)), ls)) continue;
    sum += glm::dvec3(ls.radiance / ls.pdf);
  }
  return glm::vec3(sum / double(kStrata));
}

glm::vec3 exactSum(const std::vector<LightDesc>& lights, const glm::vec3& p) {
  glm::vec3 sum(0.0f);
  for (const LightDesc& l : lights) sum += l.color * l.intensity * distanceFalloff(l, glm::length(p - l.position));
  return sum;
}

TEST(LampVisibility, HidesTheLampsNoRayReachedPerSide) {
  const std::vector<LightDesc> lamps = westEastAndFar();
  const LampVisibility map(floorPoints(), lamps, wallAtZero);
  const glm::vec3 up(0, 0, 1);
  const int64_t west = map.row({-20.5f, 3.5f, 0.0f}, up), east = map.row({20.5f, 3.5f, 0.0f}, up);
  ASSERT_GE(west, 0);
  ASSERT_GE(east, 0);
  EXPECT_EQ(map.hidden(west, 0), 0b010) << "west of the wall only the east lamp is hidden";
  EXPECT_EQ(map.hidden(east, 0), 0b001) << "east of the wall only the west lamp is hidden";
  EXPECT_EQ(map.lamps().size(), 3u);
  EXPECT_GT(map.rayCount(), 0u);
  // The far lamp is out of range of every point: never traced, never hidden. Other facings and
  // points outside the grid have no row.
  EXPECT_EQ(map.row({-20.5f, 3.5f, 0.0f}, glm::vec3(1, 0, 0)), -1);
  EXPECT_EQ(map.row({-500.0f, 3.0f, 0.0f}, up), -1);
  // Every ray arrives: nothing hidden anywhere.
  const LampVisibility open(floorPoints(), lamps, [](const glm::vec3&, const glm::vec3&) { return true; });
  EXPECT_EQ(open.rowCount(), 0u);
  EXPECT_EQ(open.row({-20.5f, 3.5f, 0.0f}, up), -1);
}

TEST(LampVisibility, TooFewRaysHideNothing) {
  // Three points in one bin: fewer than kLeastRays rays toward the lamp behind the wall.
  std::vector<SurfacePoint> points;
  for (int i = 0; i < 3; ++i) points.push_back({glm::vec3(-10.0f + 0.1f * float(i), 0.0f, 0.0f), glm::vec3(0, 0, 1)});
  points.push_back({glm::vec3(30.0f, 20.0f, 10.0f), glm::vec3(0, 0, 1)});   // spans the grid
  static_assert(LampVisibility::kLeastRays > 3);
  const LampVisibility map(points, std::vector<LightDesc>{lampAt({10.0f, 0.0f, 8.0f})}, wallAtZero);
  EXPECT_EQ(map.row({-10.0f, 0.0f, 0.0f}, glm::vec3(0, 0, 1)), -1);
}

TEST(LampVisibility, TooManyLampsGiveNoMap) {
  // 4096 bins with points x 8200 lamps passes kMostPairs: nothing is traced, no lamp hidden.
  std::vector<LightDesc> lamps;
  for (int i = 0; i < 8200; ++i) lamps.push_back(lampAt({10.0f + 0.001f * float(i), 0.0f, 8.0f}));
  const LampVisibility map(floorPoints(), lamps, wallAtZero);
  static_assert(4096ull * 8200 > LampVisibility::kMostPairs);
  EXPECT_EQ(map.rayCount(), 0u);
  EXPECT_EQ(map.rowCount(), 0u);
  EXPECT_EQ(map.row({-20.5f, 3.5f, 0.0f}, glm::vec3(0, 0, 1)), -1);
  // A hundred lamps on the same floor are judged.
  lamps.resize(100);
  EXPECT_GT(LampVisibility(floorPoints(), lamps, wallAtZero).rowCount(), 0u);
}

TEST(LampVisibility, SamplerChoosesHiddenLampsLessAndStaysExact) {
  const std::vector<LightDesc> lamps = westEastAndFar();
  LightSampler sampler(lamps, {}, Sky{}, Bounds{});
  const glm::vec3 p(-20.5f, 3.5f, 0.0f), n(0, 0, 1);
  uint32_t index = 0;
  float plain = 0.0f;
  ASSERT_TRUE(sampler.pickLamp(p, n, 0.999f, true, index, plain));
  ASSERT_EQ(index, 1u) << "the brighter east lamp sits at the top of the choice";
  const glm::vec3 plainMean = estimatorMean(sampler, p, n);

  sampler.setLampVisibility(std::make_shared<const LampVisibility>(floorPoints(), lamps, wallAtZero));
  float hidden = 0.0f;
  ASSERT_TRUE(sampler.pickLamp(p, n, 0.999f, true, index, hidden));
  ASSERT_EQ(index, 1u);
  const double west = localLightWeight(lamps[0], p) * lampCosineFactor(lamps[0], p, n),
               east = localLightWeight(lamps[1], p) * lampCosineFactor(lamps[1], p, n);
  EXPECT_NEAR(plain, east / (west + east), 1e-5);
  const double k = LampVisibility::kHiddenWeight;
  EXPECT_NEAR(hidden, k * east / (west + k * east), 1e-5);
  // Stored and recomputed weights choose alike with the map.
  for (float u = 0.01f; u < 1.0f; u += 0.049f) {
    uint32_t a = 0, b = 0;
    float pa = 0.0f, pb = 0.0f;
    ASSERT_EQ(sampler.pickLamp(p, n, u, true, a, pa), sampler.pickLamp(p, n, u, false, b, pb));
    EXPECT_EQ(a, b);
    EXPECT_EQ(pa, pb);
  }
  // Unshadowed, the estimator's mean is the exact sum with or without the map.
  const glm::vec3 exact = exactSum(lamps, p);
  const glm::vec3 mapped = estimatorMean(sampler, p, n);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(plainMean[c], exact[c], 1e-3f * exact[c]);
    EXPECT_NEAR(mapped[c], exact[c], 1e-3f * exact[c]);
  }
}

TEST(LampVisibility, AWrongMapCostsNoLight) {
  // A map that says every lamp is hidden everywhere (a reach test that always fails) and one
  // traced from points on the other side: the estimator's mean stays the exact sum.
  const std::vector<LightDesc> lamps = westEastAndFar();
  const auto never = [](const glm::vec3&, const glm::vec3&) { return false; };
  for (const auto& map : {std::make_shared<const LampVisibility>(floorPoints(), lamps, never),
                          std::make_shared<const LampVisibility>(floorPoints(), lamps, wallAtZero)}) {
    LightSampler sampler(lamps, {}, Sky{}, Bounds{});
    sampler.setLampVisibility(map);
    for (const glm::vec3 p : {glm::vec3(-20.5f, 3.5f, 0.0f), glm::vec3(12.5f, -7.5f, 0.0f)}) {
      const glm::vec3 exact = exactSum(lamps, p);
      const glm::vec3 mean = estimatorMean(sampler, p, glm::vec3(0, 0, 1));
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(mean[c], exact[c], 1e-3f * exact[c]);
    }
  }
}

TEST(LampVisibility, OnlyLampsWhereTheMapSawThemUseIt) {
  // The map is applied by index to lamps that stand where they stood when traced: a moved lamp,
  // or lamps in another order, keep their full weight.
  const std::vector<LightDesc> lamps = westEastAndFar();
  const auto map = std::make_shared<const LampVisibility>(floorPoints(), lamps, wallAtZero);
  const glm::vec3 p(-20.5f, 3.5f, 0.0f), n(0, 0, 1);
  const auto eastProbability = [&](const std::vector<LightDesc>& now, uint32_t eastIndex) {
    LightSampler sampler(now, {}, Sky{}, Bounds{});
    sampler.setLampVisibility(map);
    for (float u = 0.0005f; u < 1.0f; u += 0.001f) {
      uint32_t index = 0;
      float probability = 0.0f;
      if (sampler.pickLamp(p, n, u, true, index, probability) && index == eastIndex) return probability;
    }
    return 0.0f;
  };
  const auto weight = [&](const LightDesc& l) { return double(localLightWeight(l, p) * lampCosineFactor(l, p, n)); };
  const double west = weight(lamps[0]), east = weight(lamps[1]);
  EXPECT_NEAR(eastProbability(lamps, 1), LampVisibility::kHiddenWeight * east / (west + LampVisibility::kHiddenWeight * east), 1e-5);
  std::vector<LightDesc> moved = lamps;
  moved[1].position.y += 0.5f;
  const double movedEast = weight(moved[1]);
  EXPECT_NEAR(eastProbability(moved, 1), movedEast / (west + movedEast), 1e-5);
  const std::vector<LightDesc> swapped = {lamps[1], lamps[0], lamps[2]};
  EXPECT_NEAR(eastProbability(swapped, 0), east / (west + east), 1e-5);
  // A dynamic light after the map's lamps: the map still applies to them.
  std::vector<LightDesc> withRocket = lamps;
  withRocket.push_back(lampAt({5.0f, 5.0f, 30.0f}, 10.0f));
  const double rocket = weight(withRocket[3]);
  EXPECT_NEAR(eastProbability(withRocket, 1),
              LampVisibility::kHiddenWeight * east / (west + rocket + LampVisibility::kHiddenWeight * east), 1e-5);
}

TEST(LampVisibility, GroupsPastTheMapsLampsHideNothing) {
  // A game's dynamic lights come after the map's lamps: the sampler asks for groups of eight the
  // map has no byte for, on every row including the last; they read as not hidden.
  const std::vector<LightDesc> lamps = westEastAndFar();
  const LampVisibility map(floorPoints(), lamps, wallAtZero);
  ASSERT_GT(map.rowCount(), 0u);
  const int64_t last = int64_t(map.rowCount()) - 1;
  EXPECT_EQ(map.hidden(last, 1), 0);
  EXPECT_EQ(map.hidden(last, 7), 0);
  const int64_t west = map.row({-20.5f, 3.5f, 0.0f}, glm::vec3(0, 0, 1));
  ASSERT_GE(west, 0);
  EXPECT_EQ(map.hidden(west, 0), 0b010);
  EXPECT_EQ(map.hidden(west, 1), 0);
  // A row's bytes read at once (the sampler's way) are hidden()'s for the map's groups.
  ASSERT_EQ(map.groupCount(), 1u);
  for (int64_t row = 0; row <= last; ++row) EXPECT_EQ(map.rowBits(row)[0], map.hidden(row, 0)) << row;
}

TEST(LampVisibility, CacheRetracesOnlyForAnotherSetOfLamps) {
  LampVisibilityCache cache;
  int traced = 0;
  const auto points = [&traced] {
    ++traced;
    return floorPoints();
  };
  Bounds bounds;
  bounds.extend(glm::vec3(-32.0f));
  bounds.extend(glm::vec3(32.0f));
  std::vector<LightDesc> lamps = westEastAndFar();
  const auto first = cache.get(bounds, lamps, points, wallAtZero);
  ASSERT_NE(first, nullptr);
  EXPECT_EQ(traced, 1);
  // Dynamic lights come and go after the map's lamps: the same map.
  lamps.push_back(lampAt({1.0f, 2.0f, 3.0f}));
  EXPECT_EQ(cache.get(bounds, lamps, points, wallAtZero), first);
  EXPECT_EQ(traced, 1);
  // Another level: its lamps stand elsewhere.
  for (LightDesc& l : lamps) l.position.x += 100.0f;
  const auto second = cache.get(bounds, lamps, points, wallAtZero);
  EXPECT_NE(second, first);
  EXPECT_EQ(traced, 2);
  // The same lamps in a scene whose bounds moved far: retraced.
  Bounds moved = bounds;
  moved.max += glm::vec3(50.0f);
  EXPECT_NE(cache.get(moved, lamps, points, wallAtZero), second);
  EXPECT_EQ(traced, 3);
  // No lamp: no map, nothing traced.
  EXPECT_EQ(cache.get(bounds, {}, points, wallAtZero), nullptr);
  EXPECT_EQ(traced, 3);
}

/// A floor split by a wall along x = 0, a lamp each side (the east one brighter), seen from
/// above on the west side: the renderer's Direct image with RendererConfig::lampVisibility.
FrameView westOfTheWall(Renderer& renderer) {
  test::MeshArrays floor = test::quad({-50, -50, 0}, {100, 0, 0}, {0, 100, 0});
  test::MeshArrays wall = test::quad({0, -50, 0}, {0, 100, 0}, {0, 0, 40});
  const MaterialId grey = renderer.addMaterial(test::diffuse(0.5f));
  floor.setMaterial(grey);
  wall.setMaterial(grey);
  renderer.addInstance({renderer.addMesh(floor.desc())});
  renderer.addInstance({renderer.addMesh(wall.desc())});
  renderer.addLight(lampAt({-10.0f, 0.0f, 8.0f}, 100.0f));
  renderer.addLight(lampAt({10.0f, 0.0f, 8.0f}, 400.0f));
  renderer.commit();
  return renderer.render(test::lookAt({-20, 0, 10}, {-20, 0, 0}, 40.0f), test::settingsFor(Integrator::Direct, 16, 64, 1));
}

TEST(LampVisibility, RendererChoosesLampsBehindAWallLessForTheSameMean) {
  // The map is traced by the renderer from the scene's surfaces with real shadow rays: the same
  // mean (unbiased), and the noise of the samples spent on the lamp behind the wall is gone.
  Renderer plain(RendererConfig{.threads = 2, .lampVisibility = false});
  Renderer mapped(RendererConfig{.threads = 2, .lampVisibility = true});
  const test::FrameStats a = test::greyStats(westOfTheWall(plain));
  const test::FrameStats b = test::greyStats(westOfTheWall(mapped));
  ASSERT_GT(a.mean, 0.0);
  EXPECT_NEAR(b.mean, a.mean, 4.0 * std::hypot(a.standardError, b.standardError));
  EXPECT_LT(b.standardError, 0.5 * a.standardError);
}

}  // namespace
}  // namespace pa
