// Sobol / Owen scrambling, alias table and warps.
#include <gtest/gtest.h>

#include <array>
#include <bit>
#include <set>

#include "renderer/scene/sampling/alias_table.h"
#include "renderer/scene/sampling/sobol_sampler.h"
#include "renderer/scene/sampling/warp.h"

namespace pa::sampling {
namespace {

TEST(Sobol, FirstPointsMatchTheKnownSequence) {
  // Dimension 0 is van der Corput, dimension 1 the Pascal-matrix dimension (natural, not Gray-code, order).
  const std::array<float, 8> d0{0.0f, 0.5f, 0.25f, 0.75f, 0.125f, 0.625f, 0.375f, 0.875f};
  const std::array<float, 8> d1{0.0f, 0.5f, 0.75f, 0.25f, 0.625f, 0.125f, 0.375f, 0.875f};
  for (uint32_t i = 0; i < 8; ++i) {
    EXPECT_EQ(toUnitFloat(sobol(i, 0)), d0[i]) << i;
    EXPECT_EQ(toUnitFloat(sobol(i, 1)), d1[i]) << i;
  }
}

TEST(Sobol, EveryDimensionPairIsStratifiedBeforeAndAfterScrambling) {
  // Each dimension: the first 2^k points fall in distinct intervals of width 2^-k, scrambled or not.
  constexpr uint32_t kLog = 8, kCount = 1u << kLog;
  for (uint32_t dim = 0; dim < kSobolDimensions; ++dim) {
    std::set<uint32_t> plain, scrambled;
    for (uint32_t i = 0; i < kCount; ++i) {
      plain.insert(sobol(i, dim) >> (32 - kLog));
      scrambled.insert(nestedUniformScramble(sobol(i, dim), 0x1234567u + dim) >> (32 - kLog));
    }
    EXPECT_EQ(plain.size(), kCount) << dim;
    EXPECT_EQ(scrambled.size(), kCount) << dim;
  }
  // 2D (0,1): the first 16 points occupy all 4x4 cells.
  std::set<uint32_t> cells;
  for (uint32_t i = 0; i < 16; ++i) cells.insert((sobol(i, 0) >> 30) * 4 + (sobol(i, 1) >> 30));
  EXPECT_EQ(cells.size(), 16u);
}

TEST(Sobol, PixelSamplerIsStratifiedAndDeterministic) {
  const PixelSampler a(42, 3), b(42, 3), c(43, 3);
  EXPECT_EQ(a.get4(5), b.get4(5));
  EXPECT_NE(a.get4(5), c.get4(5));
  // Shuffled index over a full power-of-two block is still a stratified set.
  std::set<uint32_t> strata;
  for (uint32_t i = 0; i < 64; ++i) strata.insert(static_cast<uint32_t>(PixelSampler(7, i).get4(2).x * 64.0f));
  EXPECT_EQ(strata.size(), 64u);
  // Mean of many samples of one dimension is 1/2.
  double sum = 0.0;
  for (uint32_t i = 0; i < 4096; ++i) sum += PixelSampler(99, i).get4(9).w;
  EXPECT_NEAR(sum / 4096.0, 0.5, 1e-3);
}

TEST(Sobol, ReversedByteTableIsTheSobolPointOfTheReversedIndexReversed) {
  for (uint32_t dim = 0; dim < kSobolDimensions; ++dim)
    for (uint32_t y : {0u, 1u, 0x80000000u, 0xffffffffu, 0x12345678u, 0xdeadbeefu, 0x00ff00ffu})
      EXPECT_EQ(reversedSobolOfReversed(y, dim), reverseBits(sobol(reverseBits(y), dim))) << dim << " " << y;
}

TEST(Sobol, Get4GivesTheBitsOfItsDefinition) {
  // get4 reverses bits once per dimension and runs the dimensions in SIMD lanes where it can;
  // every float must be get4Reference's, the scrambled Sobol point as defined.
  uint32_t state = 1;
  const auto next = [&] { return state = hashCombine(state, 0x51ed27u); };
  const std::array<uint32_t, 6> edges{0u, 1u, 2u, 0x7fffffffu, 0x80000000u, 0xffffffffu};
  const auto same = [](glm::vec4 a, glm::vec4 b) {
    for (int d = 0; d < 4; ++d)
      if (std::bit_cast<uint32_t>(a[d]) != std::bit_cast<uint32_t>(b[d])) return false;
    return true;
  };
  for (uint32_t seed : edges)
    for (uint32_t index : edges)
      for (uint32_t group : edges) {
        const PixelSampler s(seed, index);
        EXPECT_TRUE(same(s.get4(group), s.get4Reference(group))) << seed << " " << index << " " << group;
      }
  for (int i = 0; i < 100000; ++i) {
    const PixelSampler s(next(), next() >> (next() & 31u));
    const uint32_t group = next() & 0xffffu;
    ASSERT_TRUE(same(s.get4(group), s.get4Reference(group))) << i;
  }
}

TEST(AliasTable, SamplesInProportionToWeights) {
  const std::array<double, 5> w{1.0, 0.0, 3.0, 4.0, 2.0};
  const AliasTable t(w);
  ASSERT_FALSE(t.empty());
  EXPECT_FLOAT_EQ(t.pdf(0), 0.1f);
  EXPECT_FLOAT_EQ(t.pdf(1), 0.0f);
  EXPECT_FLOAT_EQ(t.pdf(3), 0.4f);
  std::array<int, 5> counts{};
  constexpr int kN = 100000;
  for (int i = 0; i < kN; ++i) counts[t.sample((static_cast<float>(i) + 0.5f) / kN)]++;
  EXPECT_EQ(counts[1], 0);
  for (int i = 0; i < 5; ++i) EXPECT_NEAR(counts[static_cast<size_t>(i)] / double{kN}, w[static_cast<size_t>(i)] / 10.0, 1e-3);
}

TEST(AliasTable, AllZeroOrInvalidWeightsGiveAnEmptyTable) {
  const std::array<double, 3> w{0.0, -1.0, std::nan("")};
  EXPECT_TRUE(AliasTable(w).empty());
  EXPECT_TRUE(AliasTable(std::span<const double>{}).empty());
}

TEST(Warp, CosineHemisphereAndFrameStayNormalised) {
  const glm::vec3 n = glm::normalize(glm::vec3(0.3f, -0.5f, 0.8f));
  const Frame f(n);
  EXPECT_NEAR(glm::dot(f.t, f.b), 0.0f, 1e-6f);
  EXPECT_NEAR(glm::dot(f.t, f.n), 0.0f, 1e-6f);
  double meanCos = 0.0;
  for (uint32_t i = 0; i < 1024; ++i) {
    const glm::vec4 u = PixelSampler(1, i).get4(0);
    const glm::vec3 d = f.toWorld(cosineHemisphere({u.x, u.y}));
    EXPECT_NEAR(glm::length(d), 1.0f, 1e-5f);
    EXPECT_GE(glm::dot(d, n), -1e-6f);
    meanCos += glm::dot(d, n);
  }
  EXPECT_NEAR(meanCos / 1024.0, 2.0 / 3.0, 2e-3);   // E[cos] under cos/pi = 2/3
}

TEST(Warp, PowerHeuristic) {
  EXPECT_FLOAT_EQ(powerHeuristic(1.0f, 1.0f), 0.5f);
  EXPECT_FLOAT_EQ(powerHeuristic(3.0f, 1.0f), 0.9f);
  EXPECT_FLOAT_EQ(powerHeuristic(0.0f, 0.0f), 0.0f);
}

}  // namespace
}  // namespace pa::sampling
