// Firefly spreading (denoise/fireflies.h): known answers on small synthetic frames.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include <tbb/task_arena.h>

#include "renderer/scene/denoise/fireflies.h"

namespace pa::denoise {
namespace {

/// A w x h frame of one plane facing the camera at depth 10, lit radiance `lit` everywhere.
struct Frame {
  uint32_t w, h;
  std::vector<glm::vec3> radiance, emission, normal;
  std::vector<float> depth;
  Frame(uint32_t width, uint32_t height, float lit)
      : w(width), h(height), radiance(size_t(width) * height, glm::vec3(lit)),
        emission(size_t(width) * height, glm::vec3(0.0f)), normal(size_t(width) * height, glm::vec3(0, 0, 1)),
        depth(size_t(width) * height, 10.0f) {}
  size_t at(uint32_t x, uint32_t y) const { return size_t(y) * w + x; }
  FireflyInputs inputs() const { return {w, h, emission, normal, depth}; }
  glm::vec3 sum() const {
    glm::vec3 s(0.0f);
    for (const glm::vec3& r : radiance) s += r;
    return s;
  }
};

TEST(Fireflies, ASpeckIsCutToItsNeighbourhoodAndItsExcessShared) {
  Frame f(16, 16, 0.1f);
  f.radiance[f.at(8, 8)] = glm::vec3(10.1f, 5.1f, 0.1f);
  const glm::vec3 before = f.sum();
  EXPECT_EQ(spreadFireflies(f.inputs(), f.radiance), 1u);
  // Cut to 4 x 0.1 in luminance, hue kept; the excess goes to the 25 pixels of its 5 x 5 window.
  const glm::vec3 speck(10.1f, 5.1f, 0.1f);
  const float lum = 0.2126f * speck.r + 0.7152f * speck.g + 0.0722f * speck.b;
  const glm::vec3 excess = speck * (1.0f - 0.4f / lum);
  EXPECT_NEAR(f.radiance[f.at(8, 8)].r, speck.r - excess.r + excess.r / 25.0f, 1e-4f);
  EXPECT_NEAR(f.radiance[f.at(10, 6)].g, 0.1f + excess.g / 25.0f, 1e-5f);
  EXPECT_EQ(f.radiance[f.at(11, 8)], glm::vec3(0.1f));   // outside the window
  const glm::vec3 after = f.sum();
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(after[c], before[c], 1e-4f * before[c]);   // no darkening
}

TEST(Fireflies, EmissionSkyOtherSurfacesAndDimNoiseAreLeftAlone) {
  Frame f(16, 16, 0.1f);
  // A lamp seen by the camera: bright emission, ordinary lit part: nothing to cut.
  f.emission[f.at(3, 3)] = glm::vec3(50.0f);
  f.radiance[f.at(3, 3)] = glm::vec3(50.1f);
  // Sky on the right half; a wall at another angle on the bottom rows.
  for (uint32_t y = 0; y < 16; ++y)
    for (uint32_t x = 10; x < 16; ++x) {
      f.depth[f.at(x, y)] = std::numeric_limits<float>::infinity();
      f.radiance[f.at(x, y)] = glm::vec3(0.3f);
    }
  for (uint32_t y = 12; y < 16; ++y)
    for (uint32_t x = 0; x < 10; ++x) f.normal[f.at(x, y)] = glm::vec3(1, 0, 0);
  // A speck on the plane next to the sky and the other wall.
  f.radiance[f.at(9, 11)] = glm::vec3(8.0f);
  // Dim noise under the floor luminance (0.05) is never a firefly, however dark around it.
  Frame dim(8, 8, 0.0f);
  dim.radiance[dim.at(4, 4)] = glm::vec3(0.04f);
  EXPECT_EQ(spreadFireflies(dim.inputs(), dim.radiance), 0u);
  EXPECT_EQ(dim.radiance[dim.at(4, 4)], glm::vec3(0.04f));

  const glm::vec3 before = f.sum();
  EXPECT_EQ(spreadFireflies(f.inputs(), f.radiance), 1u);
  EXPECT_EQ(f.radiance[f.at(3, 3)], glm::vec3(50.1f));
  for (uint32_t y = 0; y < 16; ++y) {
    EXPECT_EQ(f.radiance[f.at(10, y)], glm::vec3(0.3f)) << y;   // sky receives nothing
    for (uint32_t x = 0; x < 10; ++x) {
      if (y >= 12) {
        EXPECT_EQ(f.radiance[f.at(x, y)], glm::vec3(0.1f)) << x << "," << y;   // nor the other wall
      }
    }
  }
  // The receivers are the plane's pixels of the window: columns 7-9, rows 9-11 (9 of them).
  EXPECT_NEAR(f.radiance[f.at(7, 9)].r, 0.1f + (8.0f - 0.4f) / 9.0f, 1e-5f);
  const glm::vec3 after = f.sum();
  EXPECT_NEAR(after.r, before.r, 1e-4f * before.r);
}

TEST(Fireflies, TheResultDoesNotDependOnTheThreadCount) {
  Frame a(64, 40, 0.0f);
  for (size_t i = 0; i < a.radiance.size(); ++i) {
    const uint32_t hash = uint32_t(i) * 2654435761u;
    a.radiance[i] = glm::vec3(float(hash % 97) * 0.01f) * ((hash >> 8) % 29 == 0 ? 40.0f : 1.0f);
  }
  Frame b = a;
  tbb::task_arena one(1);
  uint32_t cutOne = 0;
  one.execute([&] { cutOne = spreadFireflies(a.inputs(), a.radiance); });
  EXPECT_GT(cutOne, 0u);
  EXPECT_EQ(spreadFireflies(b.inputs(), b.radiance), cutOne);
  EXPECT_EQ(a.radiance, b.radiance);
}

TEST(Fireflies, MismatchedBuffersAreRefused) {
  Frame f(4, 4, 0.1f);
  std::vector<glm::vec3> shortRadiance(15);
  EXPECT_THROW(spreadFireflies(f.inputs(), shortRadiance), std::invalid_argument);
}

}  // namespace
}  // namespace pa::denoise
