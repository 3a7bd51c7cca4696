// Known-answer tests of the dynamic-resolution controller against a simulated frame cost.
#include <gtest/gtest.h>

#include <cmath>

#include "port/engine_glue/dynamic_resolution.h"

namespace glue {
namespace {

/// A frame: fixed cost plus a part proportional to the traced pixels.
double frameMs(float scale) { return 10.0 + 90.0 * double(scale) * double(scale); }

TEST(DynamicResolution, SettlesWhereTheFrameTimeMeetsTheTarget) {
  // 20 fps = 50 ms: 10 + 90 s^2 = 50 -> s = 2/3.
  ResolutionController c;
  float scale = 1.0f;
  int changesLate = 0;
  for (int f = 0; f < 200; ++f) {
    const float next = c.update(frameMs(scale), 20.0f, 0.25f);
    if (f >= 150 && next != scale) ++changesLate;
    scale = next;
  }
  EXPECT_NEAR(scale, 2.0f / 3.0f, 0.05f);
  EXPECT_NEAR(frameMs(scale), 50.0, 50.0 * ResolutionController::kDeadBand + 1.0);
  EXPECT_EQ(changesLate, 0);   // settled: no oscillation
}

TEST(DynamicResolution, StaysWithinMinimumAndOne) {
  ResolutionController slow;
  float scale = 1.0f;
  for (int f = 0; f < 200; ++f) scale = slow.update(frameMs(scale), 200.0f, 0.4f);   // unreachable 5 ms
  EXPECT_FLOAT_EQ(scale, 0.4f);
  ResolutionController fast;
  scale = 0.4f;
  for (int f = 0; f < 200; ++f) scale = fast.update(frameMs(scale) * 0.1, 20.0f, 0.4f);   // always quick
  EXPECT_FLOAT_EQ(scale, 1.0f);
}

TEST(DynamicResolution, FollowsALoadChangeAndTurnsOff) {
  ResolutionController c;
  float scale = 1.0f;
  for (int f = 0; f < 150; ++f) scale = c.update(frameMs(scale), 20.0f, 0.2f);
  const float before = scale;
  for (int f = 0; f < 150; ++f) scale = c.update(2.0 * frameMs(scale), 20.0f, 0.2f);   // twice as costly
  EXPECT_LT(scale, before - 0.1f);
  EXPECT_NEAR(2.0 * frameMs(scale), 50.0, 50.0 * ResolutionController::kDeadBand + 2.0);
  EXPECT_FLOAT_EQ(c.update(40.0, 0.0f, 0.2f), 1.0f);   // r_pt_fps 0: off (the glue uses r_pt_scale)
}

}  // namespace
}  // namespace glue
