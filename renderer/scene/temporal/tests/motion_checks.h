// Checks shared by the motion-vector and temporal tests: what a frame's motion AOV holds on one
// instance and on everything else; a frame's planes as bytes.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <vector>

#include "scene_builders.h"

namespace pa::test {

/// Bytes of a span, for comparing frames bit for bit.
template <typename T>
std::vector<uint8_t> bytesOf(std::span<const T> v) {
  std::vector<uint8_t> out(v.size_bytes());
  if (!v.empty()) std::memcpy(out.data(), v.data(), out.size());
  return out;
}

/// A grey floor (x in [-8, 8], y in [-4, 4], z = 0) lit by two lamps of linear falloff over 3.5
/// units, 1.5 above it at x = -4 and x = 4, and a black sky; not committed. Returns the left lamp,
/// whose description it writes to `leftDesc`.
inline LightId addFloorWithTwoLamps(Renderer& r, LightDesc& leftDesc) {
  const MaterialId grey = r.addMaterial(diffuse(0.6f));
  addMesh(r, quad({-8, -4, 0}, {16, 0, 0}, {0, 8, 0}), grey);
  leftDesc = LightDesc{};
  leftDesc.position = {-4, 0, 1.5f};
  leftDesc.intensity = 8.0f;
  leftDesc.falloff = Falloff::Linear;
  leftDesc.range = 3.5f;
  const LightId left = r.addLight(leftDesc);
  LightDesc right = leftDesc;
  right.position = {4, 0, 1.5f};
  r.addLight(right);
  r.setSky(SkyDesc{});
  return left;
}

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
