// EmitterIndex: the emitters it finds near a point are every one that can light it, in order,
// and the sums over them equal the sums over all emitters bit for bit.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include <glm/geometric.hpp>

#include "port/light_recovery/calibration_model.h"
#include "port/light_recovery/emitter_index.h"

namespace pa::recovery {
namespace {

using namespace model;

const SegmentBlocked kNothingBlocks = [](const glm::vec3&, const glm::vec3&) { return false; };

/// `count` triangles of 1 to 128 units, radiance 0.01 to 100, scattered over a 4096-unit cube.
std::vector<CalibrationEmitter> scatteredEmitters(size_t count, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> position(-2048.0f, 2048.0f), unit(-1.0f, 1.0f), logSize(0.0f, 7.0f),
      logRadiance(-2.0f, 2.0f);
  std::vector<CalibrationEmitter> emitters;
  for (size_t i = 0; i < count; ++i) {
    const glm::vec3 a(position(rng), position(rng), position(rng));
    const float size = std::exp2(logSize(rng));
    const glm::vec3 b = a + size * glm::vec3(unit(rng), unit(rng), unit(rng));
    const glm::vec3 c = a + size * glm::vec3(unit(rng), unit(rng), unit(rng));
    emitters.push_back({a, b, c, std::pow(10.0f, logRadiance(rng)), i % 3 == 0, int32_t(i % 5)});
  }
  return emitters;
}

TEST(EmitterIndex, FindsEveryEmitterThatLightsAPointInOrder) {
  const std::vector<CalibrationEmitter> emitters = scatteredEmitters(3000, 7);
  LightCalibrationOptions o;
  const EmitterIndex index(emitters, o.minTracedValue);
  ASSERT_EQ(index.emitters().size(), emitters.size());
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> position(-2100.0f, 2100.0f), unit(-1.0f, 1.0f);
  std::vector<uint32_t> near;
  size_t listed = 0, lighting = 0;
  for (int p = 0; p < 2000; ++p) {
    const Sample s{{position(rng), position(rng), position(rng)},
                   glm::normalize(glm::vec3(unit(rng), unit(rng), unit(rng)) + glm::vec3(0.0f, 0.0f, 1e-3f)), 0.0f};
    index.near(s.position, o.minTracedValue, near);
    ASSERT_TRUE(std::is_sorted(near.begin(), near.end()));
    ASSERT_TRUE(std::adjacent_find(near.begin(), near.end()) == near.end());
    float sumNear = 0.0f, sumAll = 0.0f;
    size_t rays = 0;
    for (const uint32_t i : near) sumNear += emitterLight(s, index.emitters()[i], s.position, kNothingBlocks, o, rays);
    for (uint32_t i = 0; i < index.emitters().size(); ++i) {
      const float value = emitterLight(s, index.emitters()[i], s.position, kNothingBlocks, o, rays);
      sumAll += value;
      if (value > 0.0f) {
        ++lighting;
        EXPECT_TRUE(std::binary_search(near.begin(), near.end(), i)) << "emitter " << i << " lights point " << p;
      }
    }
    EXPECT_EQ(sumNear, sumAll);   // the same additions in the same order
    listed += near.size();
  }
  EXPECT_GT(lighting, 100u);                    // the test sees lit points
  EXPECT_LT(listed, 2000u * 3000u / 50u);       // and the tree skips most emitters (1.4%)
}

TEST(EmitterIndex, LeavesOutEmittersThatGiveNoLight) {
  const glm::vec3 a(0.0f), b(16.0f, 0.0f, 0.0f), c(0.0f, 16.0f, 0.0f);
  const float nan = std::nanf("");
  const EmitterIndex index({{a, b, c, 1.0f, false, 0},          // kept
                            {a, b, b, 1.0f, false, 0},          // no area
                            {a, b, c, 0.0f, false, 0},          // dark
                            {a, b, c, nan, false, 0},           // NaN radiance
                            {glm::vec3(nan), b, c, 1.0f, false, 0},
                            {a, b, c, 2.0f, true, 3}},          // kept
                           0.5f);
  ASSERT_EQ(index.emitters().size(), 2u);
  EXPECT_EQ(index.emitters()[1].group, 3);
  EXPECT_TRUE(index.emitters()[1].twoSided);
  EXPECT_FLOAT_EQ(index.emitters()[0].area, 128.0f);
  EXPECT_EQ(index.emitters()[0].unitNormal, glm::vec3(0.0f, 0.0f, 1.0f));
}

TEST(EmitterIndex, AnotherThresholdOrANonFinitePointIsHandled) {
  const std::vector<CalibrationEmitter> emitters = scatteredEmitters(50, 3);
  const EmitterIndex index(emitters, 0.5f);
  std::vector<uint32_t> near;
  index.near(glm::vec3(1e6f), 0.5f, near);   // far outside: none
  EXPECT_TRUE(near.empty());
  index.near(glm::vec3(1e6f), 0.25f, near);   // not the index's threshold: all, in order
  ASSERT_EQ(near.size(), 50u);
  EXPECT_TRUE(std::is_sorted(near.begin(), near.end()));
  index.near(glm::vec3(std::nanf("")), 0.5f, near);
  EXPECT_TRUE(near.empty());
  const EmitterIndex unbounded(emitters, 0.0f);   // no threshold: every emitter counts everywhere
  unbounded.near(glm::vec3(1e6f), 0.0f, near);
  EXPECT_EQ(near.size(), 50u);
  const EmitterIndex empty;
  empty.near(glm::vec3(0.0f), 0.5f, near);
  EXPECT_TRUE(near.empty());
}

}  // namespace
}  // namespace pa::recovery
