// Known-answer tests of the temporal filter on synthetic frames (G-buffers written by hand).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <span>
#include <vector>

#include <tbb/task_arena.h>

#include "renderer/scene/temporal/temporal.h"

namespace pa::temporal {
namespace {

/// A synthetic frame: one instance and material, a still camera (zero motion), unit albedo.
struct Synthetic {
  uint32_t width, height;
  std::vector<glm::vec3> radiance, emission, albedo, normal;
  std::vector<float> depth;
  GBuffer gbuffer;

  Synthetic(uint32_t w, uint32_t h, float z) : width(w), height(h) {
    const size_t n = size_t{w} * h;
    radiance.assign(n, glm::vec3(1.0f));
    emission.assign(n, glm::vec3(0.0f));
    albedo.assign(n, glm::vec3(1.0f));
    normal.assign(n, glm::vec3(0, 0, 1));
    depth.assign(n, z);
    gbuffer.resize(w, h);
    for (size_t i = 0; i < n; ++i) {
      gbuffer.instance[i] = 0;
      gbuffer.material[i] = 0;
      gbuffer.motion[i] = glm::vec2(0.0f);
      gbuffer.previousDepth[i] = z;   // a still scene: the hit was where it is
      gbuffer.previousNormal[i] = glm::vec3(0, 0, 1);
    }
  }
  /// Puts a surface at depth z over columns [x0, width): a still camera sees it where it was.
  void setDepth(uint32_t x0, float z) {
    for (uint32_t y = 0; y < height; ++y)
      for (uint32_t x = x0; x < width; ++x) {
        depth[size_t{y} * width + x] = z;
        gbuffer.previousDepth[size_t{y} * width + x] = z;
      }
  }
  FrameInputs inputs() const { return {width, height, emission, albedo, normal, depth, &gbuffer, {}}; }
};

/// Deterministic noise in [0, 1) for (pixel, frame).
float noise(uint32_t pixel, uint32_t frame) {
  uint32_t h = pixel * 0x9E3779B1u ^ (frame + 1) * 0x85EBCA77u;
  h ^= h >> 15;
  h *= 0x2C1B3C6Du;
  h ^= h >> 12;
  h *= 0x297A2D39u;
  h ^= h >> 15;
  return static_cast<float>(h >> 8) / 16777216.0f;
}

TEST(TemporalFilter, FirstFrameHasNoHistoryThenLengthsGrow) {
  Synthetic f(16, 8, 10.0f);
  TemporalFilter t;
  for (uint32_t frame = 1; frame <= 3; ++frame) {
    std::vector<glm::vec3> radiance = f.radiance;
    t.accumulate(f.inputs(), radiance);
    for (float length : t.historyLength()) EXPECT_EQ(length, static_cast<float>(frame));
    EXPECT_NEAR(radiance[5].g, 1.0f, 1e-6f);   // a constant signal stays itself
    t.endFrame();
  }
}

TEST(TemporalFilter, DepthStepIsDisocclusion) {
  Synthetic f(32, 16, 10.0f);
  TemporalFilter t;
  for (int frame = 0; frame < 5; ++frame) {
    std::vector<glm::vec3> radiance = f.radiance;
    t.accumulate(f.inputs(), radiance);
    t.endFrame();
  }
  // Something moves in front of the right half (same instance and material: only depth tells).
  f.setDepth(20, 6.0f);
  std::vector<glm::vec3> radiance = f.radiance;
  t.accumulate(f.inputs(), radiance);
  const auto lengths = t.historyLength();
  for (uint32_t y = 0; y < f.height; ++y) {
    for (uint32_t x = 0; x < f.width; ++x) {
      const float length = lengths[size_t{y} * f.width + x];
      if (x < 20) EXPECT_EQ(length, 6.0f) << x << "," << y;   // kept its history
      else EXPECT_EQ(length, 1.0f) << x << "," << y;          // disoccluded: starts again
    }
  }
}

TEST(TemporalFilter, NormalFlipAndOtherMaterialAreDisocclusion) {
  Synthetic f(16, 8, 10.0f);
  TemporalFilter t;
  for (int frame = 0; frame < 3; ++frame) {
    std::vector<glm::vec3> radiance = f.radiance;
    t.accumulate(f.inputs(), radiance);
    t.endFrame();
  }
  f.normal[3] = glm::vec3(1, 0, 0);
  f.gbuffer.previousNormal[3] = glm::vec3(1, 0, 0);
  f.gbuffer.material[7] = 2;
  std::vector<glm::vec3> radiance = f.radiance;
  t.accumulate(f.inputs(), radiance);
  EXPECT_EQ(t.historyLength()[3], 1.0f);
  EXPECT_EQ(t.historyLength()[7], 1.0f);
  EXPECT_EQ(t.historyLength()[5], 4.0f);
}

TEST(TemporalFilter, MotionFetchesHistoryFromThePreviousPosition) {
  // Frame 1: columns hold their index as radiance. Frame 2: the picture moved 3 pixels right
  // (motion -3), this frame's own radiance is 0: with alpha = 1/2 the result is half the history.
  Synthetic f(16, 4, 10.0f);
  TemporalFilter t;
  std::vector<glm::vec3> radiance(f.radiance.size());
  for (uint32_t y = 0; y < f.height; ++y)
    for (uint32_t x = 0; x < f.width; ++x) radiance[size_t{y} * f.width + x] = glm::vec3(static_cast<float>(x));
  t.accumulate(f.inputs(), radiance);
  t.endFrame();
  for (glm::vec2& m : f.gbuffer.motion) m = glm::vec2(-3.0f, 0.0f);
  std::vector<glm::vec3> zero(f.radiance.size(), glm::vec3(0.0f));
  t.accumulate(f.inputs(), zero);
  for (uint32_t x = 0; x < f.width; ++x) {
    const size_t i = size_t{1} * f.width + x;
    if (x < 2) {
      EXPECT_EQ(t.historyLength()[i], 1.0f) << x;   // came from outside the old picture
      EXPECT_EQ(zero[i].g, 0.0f);
    } else if (x == 2) {
      // One pixel outside: no bilinear tap, the 3 x 3 fallback finds the border pixel (value 0).
      EXPECT_EQ(t.historyLength()[i], 2.0f);
      EXPECT_EQ(zero[i].g, 0.0f);
    } else {
      EXPECT_EQ(t.historyLength()[i], 2.0f) << x;
      EXPECT_NEAR(zero[i].g, 0.5f * static_cast<float>(x - 3), 1e-5f) << x;
    }
  }
}

TEST(TemporalFilter, NoisyStillSignalConvergesToItsMean) {
  // Each frame: uniform noise in [0, 1) (mean 0.5, standard deviation 0.289).
  Synthetic f(32, 32, 10.0f);
  TemporalFilter t;
  std::vector<glm::vec3> radiance;
  for (uint32_t frame = 0; frame < 60; ++frame) {
    radiance.resize(f.radiance.size());
    for (size_t i = 0; i < radiance.size(); ++i) radiance[i] = glm::vec3(noise(static_cast<uint32_t>(i), frame));
    t.accumulate(f.inputs(), radiance);
    t.endFrame();
  }
  double sum = 0.0, squaredError = 0.0;
  for (const glm::vec3& c : radiance) {
    sum += c.g;
    squaredError += (c.g - 0.5) * (c.g - 0.5);
  }
  const double n = static_cast<double>(radiance.size());
  EXPECT_NEAR(sum / n, 0.5, 0.02);
  // An exponential average with alpha 0.1 keeps alpha / (2 - alpha) = 5.3% of the variance:
  // rms 0.066 against one frame's 0.289. The rejection test (3 standard errors) drops a
  // history by chance now and then: 145 of these 1024 pixels once in 60 frames (0.24% per
  // pixel and frame, about what 3 sigma lets through).
  EXPECT_LT(std::sqrt(squaredError / n), 0.09);
  size_t dropped = 0;
  for (float length : t.historyLength()) dropped += length < 60.0f ? 1 : 0;
  EXPECT_LE(dropped, radiance.size() / 5);
}

TEST(TemporalFilter, SwitchedOffSignalDropsHistoryAtOnce) {
  Synthetic f(32, 32, 10.0f);
  TemporalFilter t;
  for (uint32_t frame = 0; frame < 30; ++frame) {
    std::vector<glm::vec3> radiance(f.radiance.size());
    for (size_t i = 0; i < radiance.size(); ++i)
      radiance[i] = glm::vec3(1.0f + 0.5f * noise(static_cast<uint32_t>(i), frame));
    t.accumulate(f.inputs(), radiance);
    t.endFrame();
  }
  std::vector<glm::vec3> dark(f.radiance.size(), glm::vec3(0.0f));
  t.accumulate(f.inputs(), dark);
  for (size_t i = 0; i < dark.size(); ++i) {
    EXPECT_EQ(dark[i].g, 0.0f) << i;
    EXPECT_EQ(t.historyLength()[i], 1.0f) << i;
  }
}

TEST(TemporalFilter, EmissionPassesThroughExactly) {
  Synthetic f(8, 8, 10.0f);
  TemporalFilter t;
  for (uint32_t frame = 0; frame < 4; ++frame) {
    for (size_t i = 0; i < f.emission.size(); ++i) f.emission[i] = glm::vec3(static_cast<float>(frame));
    std::vector<glm::vec3> radiance(f.radiance.size());
    for (size_t i = 0; i < radiance.size(); ++i) radiance[i] = glm::vec3(2.0f) + f.emission[i];
    t.accumulate(f.inputs(), radiance);
    for (const glm::vec3& c : radiance) EXPECT_NEAR(c.g, 2.0f + static_cast<float>(frame), 1e-5f);
    t.endFrame();
  }
}

TEST(TemporalFilter, SameResultWithOneAndTwoThreads) {
  const auto run = [](int threads) {
    tbb::task_arena arena(threads);
    std::vector<glm::vec3> out;
    arena.execute([&] {
      Synthetic f(40, 24, 10.0f);
      f.setDepth(25, 7.0f);
      TemporalFilter t;
      for (uint32_t frame = 0; frame < 6; ++frame) {
        for (glm::vec2& m : f.gbuffer.motion) m = glm::vec2(0.37f * static_cast<float>(frame), -0.21f);
        std::vector<glm::vec3> radiance(f.radiance.size());
        for (size_t i = 0; i < radiance.size(); ++i) radiance[i] = glm::vec3(noise(static_cast<uint32_t>(i), frame));
        t.accumulate(f.inputs(), radiance);
        t.endFrame();
        out = radiance;
      }
    });
    return out;
  };
  const auto one = run(1), two = run(2);
  ASSERT_EQ(one.size(), two.size());
  for (size_t i = 0; i < one.size(); ++i) ASSERT_EQ(one[i], two[i]) << i;
}

TEST(TemporalFilter, RejectionRowsAtEveryWidth) {
  // The rejection test sums 5 x 5 neighbourhoods kCount pixels at a time: at every width (not
  // only multiples of the lane count, borders included) a steady image keeps every history, a
  // ramp too, and a light dimmed to a third over the whole frame drops every one.
  for (uint32_t width = 1; width <= 21; ++width) {
    for (const bool ramp : {false, true}) {
      Synthetic f(width, 6, 5.0f);
      for (uint32_t y = 0; y < f.height; ++y)
        for (uint32_t x = 0; x < width; ++x)
          f.radiance[size_t{y} * width + x] = glm::vec3(ramp ? 0.2f + 0.05f * static_cast<float>(x + y) : 0.5f);
      TemporalFilter filter;
      for (int frame = 0; frame < 8; ++frame) {
        std::vector<glm::vec3> r = f.radiance;
        filter.accumulate(f.inputs(), r);
        filter.endFrame();
      }
      std::vector<glm::vec3> steady = f.radiance;
      filter.accumulate(f.inputs(), steady);
      for (size_t i = 0; i < steady.size(); ++i) {
        ASSERT_EQ(filter.historyLength()[i], 9.0f) << "width " << width << " pixel " << i;
        EXPECT_NEAR(steady[i].g, f.radiance[i].g, 1e-6f);
      }
      filter.endFrame();
      std::vector<glm::vec3> dimmed = f.radiance;
      for (glm::vec3& c : dimmed) c /= 3.0f;
      const std::vector<glm::vec3> expected = dimmed;
      filter.accumulate(f.inputs(), dimmed);
      for (size_t i = 0; i < dimmed.size(); ++i) {
        ASSERT_EQ(filter.historyLength()[i], 1.0f) << "width " << width << " pixel " << i;
        EXPECT_EQ(dimmed[i], expected[i]);
      }
    }
  }
}

/// The same filter twice, reprojecting by row lanes and pixel by pixel: each frame must give
/// both the same bits (radiance, variance, history length).
struct LanesAndSingle {
  TemporalFilter lanes;
  TemporalFilter single{[] {
    Config c;
    c.rowLanes = false;
    return c;
  }()};
  /// Accumulates `f` with both and compares; true when they agree.
  ::testing::AssertionResult accumulate(Synthetic& f) {
    std::vector<glm::vec3> a = f.radiance, b = f.radiance;
    lanes.accumulate(f.inputs(), a);
    single.accumulate(f.inputs(), b);
    const auto same = [](const auto& x, const auto& y) {
      return std::memcmp(x.data(), y.data(), x.size() * sizeof(x[0])) == 0;
    };
    if (!same(a, b)) return ::testing::AssertionFailure() << "radiance differs";
    if (!same(lanes.variance(), single.variance())) return ::testing::AssertionFailure() << "variance differs";
    if (!same(lanes.historyLength(), single.historyLength())) return ::testing::AssertionFailure() << "length differs";
    lanes.endFrame();
    single.endFrame();
    return ::testing::AssertionSuccess();
  }
};

TEST(TemporalFilter, RowLanesGiveTheSameBitsAsPixelByPixel) {
  // Reprojection kCount pixels at a time against one by one, on frames with every case: motion
  // that varies per pixel (bilinear taps, taps off the frame, the 3 x 3 fallback at material and
  // depth edges), disocclusion, sky, a NaN pixel, tilted normals; widths around the lane count.
  for (uint32_t width : {1u, 7u, 8u, 9u, 10u, 17u, 21u, 40u}) {
    const uint32_t height = 9;
    Synthetic f(width, height, 5.0f);
    LanesAndSingle filters;
    for (uint32_t frame = 0; frame < 12; ++frame) {
      for (uint32_t y = 0; y < height; ++y) {
        for (uint32_t x = 0; x < width; ++x) {
          const size_t i = size_t{y} * width + x;
          const float u = noise(static_cast<uint32_t>(i), frame);
          f.radiance[i] = glm::vec3(0.3f + u, 0.5f * u + 0.1f, 0.2f);
          f.depth[i] = (y == 0 && x % 3 == 0) ? std::numeric_limits<float>::infinity()
                                               : 4.0f + 0.1f * static_cast<float>(x) + (x > width / 2 ? 3.0f : 0.0f);
          f.normal[i] = x % 4 == 1 ? glm::normalize(glm::vec3(0.3f, 0.1f, 1.0f)) : glm::vec3(0, 0, 1);
          f.gbuffer.material[i] = (x + frame) % 5 == 0 ? 1 : 0;
          f.gbuffer.instance[i] = (y * 7 + x + frame) % 11 == 0 ? 2 : 0;
          f.gbuffer.motion[i] = glm::vec2(0.6f * static_cast<float>(static_cast<int>(y % 5) - 2) + 0.13f * u,
                                          (x % 6 == 5) ? std::numeric_limits<float>::quiet_NaN() : -0.35f * u);
          f.gbuffer.previousDepth[i] = f.depth[i] * (1.0f + 0.2f * (u - 0.5f));
          f.gbuffer.previousNormal[i] = f.normal[i];
        }
      }
      if (frame % 4 == 3) f.radiance[size_t{height / 2} * width + width / 2] = glm::vec3(std::nanf(""));
      ASSERT_TRUE(filters.accumulate(f)) << width << " frame " << frame;
    }
  }
}

TEST(TemporalFilter, RowLanesGiveTheSameBitsAsPixelByPixelUnderAPan) {
  // A camera pan moves every pixel alike, so a row's lanes reproject onto consecutive pixels;
  // one band moves differently, and the pan's sub-pixel part crosses whole pixels over the frames.
  const uint32_t width = 40, height = 12;
  Synthetic f(width, height, 5.0f);
  LanesAndSingle filters;
  for (uint32_t frame = 0; frame < 10; ++frame) {
    const glm::vec2 pan(0.37f * static_cast<float>(frame % 4) - 0.6f, 0.45f - 0.3f * static_cast<float>(frame % 3));
    for (uint32_t y = 0; y < height; ++y) {
      for (uint32_t x = 0; x < width; ++x) {
        const size_t i = size_t{y} * width + x;
        const float u = noise(static_cast<uint32_t>(i), frame);
        f.radiance[i] = glm::vec3(0.3f + u, 0.5f * u + 0.1f, 0.2f);
        f.depth[i] = 4.0f + 0.05f * static_cast<float>(x + y);
        f.normal[i] = glm::vec3(0, 0, 1);
        f.gbuffer.material[i] = x > 30 ? 1 : 0;
        f.gbuffer.instance[i] = 0;
        f.gbuffer.motion[i] = y == 5 ? pan + glm::vec2(0.2f * u, 0.0f) : pan;
        f.gbuffer.previousDepth[i] = f.depth[i] * (1.0f + 0.01f * (u - 0.5f));
        f.gbuffer.previousNormal[i] = f.normal[i];
      }
    }
    ASSERT_TRUE(filters.accumulate(f)) << "frame " << frame;
  }
  const std::span<const float> length = filters.lanes.historyLength();
  EXPECT_GT(*std::max_element(length.begin(), length.end()), 3.0f);
}

}  // namespace
}  // namespace pa::temporal
