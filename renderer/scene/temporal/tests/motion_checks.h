// Checks shared by the motion-vector tests: what a frame's motion AOV holds on one instance and
// on everything else.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>

#include "scene_builders.h"

namespace pa::test {

/// Pixels per world unit of a film `size` pixels wide, seeing a plane 10 units away with a 40
/// degree field (the top-down camera of these tests).
inline float pixelsPerUnitAt10(uint32_t size) {
  return 0.5f * static_cast<float>(size) / (10.0f * std::tan(20.0f * 3.14159265f / 180.0f));
}

/// Expects every pixel of `moving` to carry a motion of length `expectedPixels` (within 2%) and
/// every other pixel none, with at least `minMoving` and `minStill` pixels of each.
inline void expectMotionOnlyOn(const FrameView& f, InstanceId moving, float expectedPixels,
                               size_t minMoving, size_t minStill) {
  size_t onMoving = 0, onStill = 0;
  for (size_t i = 0; i < f.motion.size(); ++i) {
    const glm::vec2 m = f.motion[i];
    ASSERT_TRUE(std::isfinite(m.x)) << i;
    if (f.instance[i] == moving) {
      ++onMoving;
      EXPECT_NEAR(glm::length(m), expectedPixels, 0.02f * expectedPixels) << i;
    } else {
      ++onStill;
      EXPECT_LT(glm::length(m), 1e-3f) << i;
    }
  }
  EXPECT_GT(onMoving, minMoving);
  EXPECT_GT(onStill, minStill);
}

}  // namespace pa::test
