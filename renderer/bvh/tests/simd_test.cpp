// The baseline lanes' reductions (simd.h) against their definition spelled out lane by lane.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>

#include <gtest/gtest.h>

#include "renderer/bvh/simd.h"

namespace pa::simd {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

/// minOverLanes / maxOverLanes as defined: the extreme of the lanes in mask that hold a number.
float extremeByLane(const float (&lanes)[8], unsigned mask, bool largest) {
  float best = largest ? -kInf : kInf;
  for (int i = 0; i < 8; ++i) {
    if ((mask >> i & 1) == 0 || std::isnan(lanes[i])) continue;
    best = largest ? std::max(best, lanes[i]) : std::min(best, lanes[i]);
  }
  return best;
}

TEST(Simd, ReductionsOverLanesTakeTheLanesInTheMaskAndPassOverNaN) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> value(-1e3f, 1e3f);
  const float specials[] = {kInf, -kInf, std::numeric_limits<float>::quiet_NaN(), 0.0f, -0.0f,
                            std::numeric_limits<float>::max(), std::numeric_limits<float>::denorm_min()};
  for (int trial = 0; trial < 20000; ++trial) {
    alignas(32) float lanes[8];
    for (float& x : lanes) x = rng() % 5 == 0 ? specials[rng() % std::size(specials)] : value(rng);
    const unsigned mask = rng() % 256;
    const vfloat8 v = vfloat8::load(lanes);
    const float lo = minOverLanes(v, mask), hi = maxOverLanes(v, mask);
    const float wantLo = extremeByLane(lanes, mask, false), wantHi = extremeByLane(lanes, mask, true);
    // Zeros of either sign are one value to the kernels (they only compare these bounds).
    ASSERT_EQ(lo, wantLo) << "trial " << trial << " mask " << mask;
    ASSERT_EQ(hi, wantHi) << "trial " << trial << " mask " << mask;
    ASSERT_FALSE(std::isnan(lo) || std::isnan(hi));
  }
  const vfloat8 any(3.0f);
  EXPECT_EQ(minOverLanes(any, 0), kInf);   // no lane: the identity of each
  EXPECT_EQ(maxOverLanes(any, 0), -kInf);
}

#if defined(__AVX2__)
TEST(Simd, TransposeEightMakesRowsColumns) {
  float rows[8][9];   // rows one float apart from an aligned start: any alignment is read
  for (int i = 0; i < 8; ++i)
    for (int k = 0; k < 9; ++k) rows[i][k] = static_cast<float>(100 * i + k);
  const float* starts[8];
  for (int i = 0; i < 8; ++i) starts[i] = &rows[7 - i][1];   // reversed, so order matters
  __m256 columns[8];
  transposeEight(starts, columns);
  for (int k = 0; k < 8; ++k) {
    alignas(32) float lane[8];
    _mm256_store_ps(lane, columns[k]);
    for (int i = 0; i < 8; ++i) EXPECT_EQ(lane[i], rows[7 - i][1 + k]) << "column " << k << " lane " << i;
  }
}
#endif

}  // namespace
}  // namespace pa::simd
