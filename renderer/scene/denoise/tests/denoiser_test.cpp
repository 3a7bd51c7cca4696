// Known answers of the à-trous denoiser on synthetic guide images: constants stay constant,
// noise on a plane shrinks, edges of normal / depth / albedo / sky hold, non-finite values
// stay put, and the result does not depend on the thread count.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <vector>

#include <tbb/task_arena.h>

#include "renderer/scene/denoise/denoiser.h"

namespace pa::denoise {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

/// A synthetic frame: radiance plus the film's guide images.
struct Frame {
  uint32_t width = 0, height = 0;
  std::vector<glm::vec3> radiance, albedo, normal, emission;
  std::vector<float> depth, variance;
  uint64_t samplesPerPixel = 1;

  Frame(uint32_t w, uint32_t h)
      : width(w), height(h), radiance(size_t{w} * h, glm::vec3(0.5f)), albedo(size_t{w} * h, glm::vec3(0.5f)),
        normal(size_t{w} * h, glm::vec3(0, 0, 1)), emission(size_t{w} * h, glm::vec3(0.0f)), depth(size_t{w} * h, 5.0f),
        variance(size_t{w} * h, 0.0f) {}
  size_t at(uint32_t x, uint32_t y) const { return size_t{y} * width + x; }
  Guides guides() const { return Guides{width, height, albedo, normal, depth, variance, samplesPerPixel, emission, {}}; }
  std::vector<glm::vec3> denoised(const Config& config = {}) const {
    std::vector<glm::vec3> out = radiance;
    Denoiser denoiser(config);
    denoiser.apply(guides(), out);
    return out;
  }
};

/// Deterministic uniform noise in [-1, 1) (a 32-bit LCG; no library distribution).
class Noise {
 public:
  float next() {
    state_ = state_ * 1664525u + 1013904223u;
    return static_cast<float>(state_ >> 8) / static_cast<float>(1u << 23) - 1.0f;
  }

 private:
  uint32_t state_ = 12345u;
};

/// Multiplies every pixel's radiance by (1 + amount * u), u uniform in [-1, 1): 1-spp-like noise.
void addNoise(Frame& f, float amount) {
  Noise noise;
  for (glm::vec3& r : f.radiance) r *= 1.0f + amount * noise.next();
}

/// Mean and variance of the green channel over columns [x0, x1) and rows [y0, y1).
struct Stats {
  double mean = 0.0, variance = 0.0;
};
Stats statsOf(const Frame& f, const std::vector<glm::vec3>& img, uint32_t x0, uint32_t x1, uint32_t y0, uint32_t y1) {
  double sum = 0.0, sumSquares = 0.0;
  const double n = static_cast<double>(x1 - x0) * (y1 - y0);
  for (uint32_t y = y0; y < y1; ++y) {
    for (uint32_t x = x0; x < x1; ++x) {
      const double v = img[f.at(x, y)].g;
      sum += v;
      sumSquares += v * v;
    }
  }
  const double mean = sum / n;
  return {mean, sumSquares / n - mean * mean};
}

TEST(Denoiser, ConstantImageStaysConstant) {
  Frame f(64, 48);
  for (size_t i = 0; i < f.radiance.size(); ++i) f.radiance[i] = glm::vec3(0.3f, 0.2f, 0.1f);
  const std::vector<glm::vec3> out = f.denoised();
  for (const glm::vec3& r : out) {
    EXPECT_NEAR(r.r, 0.3f, 1e-6f);
    EXPECT_NEAR(r.g, 0.2f, 1e-6f);
    EXPECT_NEAR(r.b, 0.1f, 1e-6f);
  }
}

TEST(Denoiser, EmissionIsLeftOutOfTheFilterAndAddedBack) {
  // A bright emitter pixel (emission 50 on top of the noisy reflected light) must keep exactly
  // its emission plus the filtered reflected light, and lend none of it to its neighbours: the
  // result equals the emitter-free frame's everywhere but there, where it is 50 more.
  Frame plain(48, 32);
  addNoise(plain, 0.9f);
  Frame lit = plain;
  const size_t lamp = lit.at(20, 15);
  lit.emission[lamp] = glm::vec3(50.0f);
  lit.radiance[lamp] += lit.emission[lamp];
  const std::vector<glm::vec3> expected = plain.denoised();
  const std::vector<glm::vec3> out = lit.denoised();
  for (size_t i = 0; i < out.size(); ++i) {
    const float added = i == lamp ? 50.0f : 0.0f;
    EXPECT_NEAR(out[i].g, expected[i].g + added, 1e-4f * (1.0f + added)) << i;
  }
  // Without the emission guide the lamp is filtered as if it were noise: it loses most of its
  // radiance (a 1-spp emitter would read far darker than the converged one).
  lit.emission.clear();
  EXPECT_LT(lit.denoised()[lamp].g, 25.0f);
}

TEST(Denoiser, ZeroIterationsIsIdentity) {
  Frame f(16, 16);
  addNoise(f, 0.9f);
  Config config;
  config.iterations = 0;
  const std::vector<glm::vec3> out = f.denoised(config);
  EXPECT_EQ(0, std::memcmp(out.data(), f.radiance.data(), out.size() * sizeof(glm::vec3)));
}

TEST(Denoiser, NoisyPlaneLosesMostOfItsVariance) {
  Frame f(96, 64);
  addNoise(f, 0.9f);   // 1-spp-like: standard deviation 52% of the mean
  const std::vector<glm::vec3> out = f.denoised();
  const Stats before = statsOf(f, f.radiance, 16, 80, 16, 48);
  const Stats after = statsOf(f, out, 16, 80, 16, 48);
  EXPECT_NEAR(after.mean, 0.5, 0.02);
  EXPECT_LT(after.variance * 20.0, before.variance) << "before " << before.variance << " after " << after.variance;
}

TEST(Denoiser, ConvergedPixelVarianceLeavesTheImageAlone) {
  // With enough samples the film's per-pixel variance is trusted: zero noise, nothing to blur
  // (a lighting gradient and a stripe pattern stay).
  Frame f(32, 32);
  f.samplesPerPixel = 1024;
  for (uint32_t y = 0; y < f.height; ++y)
    for (uint32_t x = 0; x < f.width; ++x) f.radiance[f.at(x, y)] = glm::vec3(0.01f * x + ((y / 2) % 2) * 0.2f);
  const std::vector<glm::vec3> out = f.denoised();
  for (size_t i = 0; i < out.size(); ++i) EXPECT_NEAR(out[i].g, f.radiance[i].g, 1e-3f) << i;
}

TEST(Denoiser, PixelsWithHistoryKeepItsVarianceAndTheOthersGetAnEstimate) {
  // Temporal history: pixels of 4 or more frames take the film's variance (0 here: converged, the
  // noise is the picture), the others an estimate from their neighbourhood. The split at column
  // 61 leaves lane blocks wholly on either side and one across it; a few pixels next to it have a
  // short history, and sky pixels (none of either) sit in the history side.
  Frame f(96, 64);
  addNoise(f, 0.9f);
  constexpr uint32_t kSplit = 61;
  std::vector<float> history(f.radiance.size(), 0.0f);
  for (uint32_t y = 0; y < f.height; ++y)
    for (uint32_t x = 0; x < kSplit; ++x) history[f.at(x, y)] = 8.0f;
  for (uint32_t y = 8; y < f.height; y += 16) history[f.at(kSplit - 4, y)] = 2.0f;
  for (uint32_t x = 0; x < 20; ++x) f.depth[f.at(x, 0)] = kInf;   // sky along the top row's left
  Guides guides = f.guides();
  guides.historyLength = history;
  std::vector<glm::vec3> out = f.radiance;
  Denoiser().apply(guides, out);
  // The history side keeps nearly all of its "noise" (its variance says it is the picture); the
  // other side loses most of it.
  const Stats keptBefore = statsOf(f, f.radiance, 2, 24, 2, 62), keptAfter = statsOf(f, out, 2, 24, 2, 62);
  EXPECT_NEAR(keptAfter.mean, keptBefore.mean, 0.01);
  EXPECT_GT(keptAfter.variance, 0.8 * keptBefore.variance) << keptBefore.variance << " " << keptAfter.variance;
  const Stats before = statsOf(f, f.radiance, kSplit + 6, 90, 8, 56), after = statsOf(f, out, kSplit + 6, 90, 8, 56);
  EXPECT_NEAR(after.mean, 0.5, 0.03);
  EXPECT_LT(after.variance * 10.0, before.variance) << "before " << before.variance << " after " << after.variance;
  // A short history among long ones still gets its estimate: it is pulled toward its neighbours.
  for (uint32_t y = 8; y < f.height; y += 16) {
    const size_t i = f.at(kSplit - 4, y);
    EXPECT_NE(out[i].g, f.radiance[i].g) << y;
  }
  EXPECT_EQ(out[f.at(3, 0)], f.radiance[f.at(3, 0)]);   // sky passes through
}

/// Splits the frame at column `edge`: `left` / `right` edit one pixel of each side. Then checks
/// that the two columns touching the edge keep their side's true radiance.
template <typename Edit>
void expectEdgeHolds(Frame f, uint32_t edge, Edit&& edit, float trueLeft, float trueRight) {
  for (uint32_t y = 0; y < f.height; ++y)
    for (uint32_t x = 0; x < f.width; ++x) edit(f, f.at(x, y), x < edge);
  addNoise(f, 0.5f);
  const std::vector<glm::vec3> out = f.denoised();
  const Stats left = statsOf(f, out, edge - 1, edge, 4, f.height - 4);
  const Stats right = statsOf(f, out, edge, edge + 1, 4, f.height - 4);
  EXPECT_NEAR(left.mean, trueLeft, 0.05 * trueLeft);
  EXPECT_NEAR(right.mean, trueRight, 0.05 * trueRight);
}

TEST(Denoiser, NormalEdgeHolds) {
  const auto edit = [](Frame& f, size_t i, bool left) {
    f.normal[i] = left ? glm::vec3(0, 0, 1) : glm::vec3(1, 0, 0);
    f.radiance[i] = glm::vec3(left ? 0.1f : 0.4f);
  };
  expectEdgeHolds(Frame(64, 48), 29, edit, 0.1f, 0.4f);
}

TEST(Denoiser, DepthEdgeHolds) {
  const auto edit = [](Frame& f, size_t i, bool left) {
    f.depth[i] = left ? 4.0f : 9.0f;
    f.radiance[i] = glm::vec3(left ? 0.4f : 0.1f);
  };
  expectEdgeHolds(Frame(64, 48), 33, edit, 0.4f, 0.1f);
}

TEST(Denoiser, AlbedoEdgeHolds) {
  // Same light on both sides, different albedo: demodulation filters the light across the
  // edge and remodulation gives each side its own colour back.
  const auto edit = [](Frame& f, size_t i, bool left) {
    f.albedo[i] = glm::vec3(left ? 0.1f : 0.8f);
    f.radiance[i] = f.albedo[i] * 0.5f;
  };
  expectEdgeHolds(Frame(64, 48), 30, edit, 0.05f, 0.4f);
}

TEST(Denoiser, SkyAndBlackAlbedoPassThrough) {
  Frame f(48, 32);
  addNoise(f, 0.9f);
  for (uint32_t y = 0; y < f.height; ++y) {
    for (uint32_t x = 0; x < 12; ++x) {   // sky: no hit, no normal, radiance 5 (would pull its neighbours up)
      const size_t i = f.at(x, y);
      f.depth[i] = kInf;
      f.normal[i] = glm::vec3(0.0f);
      f.albedo[i] = glm::vec3(1.0f);
      f.radiance[i] = glm::vec3(5.0f + 0.01f * static_cast<float>(y));
    }
    const size_t emitter = f.at(30, y);   // black-albedo emitter column
    f.albedo[emitter] = glm::vec3(0.0f);
    f.radiance[emitter] = glm::vec3(8.0f);
  }
  const std::vector<glm::vec3> out = f.denoised();
  for (uint32_t y = 0; y < f.height; ++y) {
    for (uint32_t x = 0; x < 12; ++x) EXPECT_EQ(out[f.at(x, y)], f.radiance[f.at(x, y)]);
    EXPECT_EQ(out[f.at(30, y)], glm::vec3(8.0f));
  }
  EXPECT_NEAR(statsOf(f, out, 12, 13, 4, 28).mean, 0.5, 0.05);   // the plane beside the sky
  EXPECT_NEAR(statsOf(f, out, 29, 30, 4, 28).mean, 0.5, 0.05);   // and beside the emitter
}

TEST(Denoiser, NonFiniteRadianceDoesNotSpread) {
  Frame f(48, 32);
  addNoise(f, 0.5f);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  f.radiance[f.at(20, 16)] = glm::vec3(nan);
  f.radiance[f.at(21, 16)] = glm::vec3(kInf, 0.5f, 0.5f);
  f.radiance[f.at(10, 10)] = glm::vec3(-kInf);
  f.depth[f.at(40, 20)] = kInf;   // a sky pixel with a NaN: becomes black
  f.normal[f.at(40, 20)] = glm::vec3(0.0f);
  f.radiance[f.at(40, 20)] = glm::vec3(nan);
  const std::vector<glm::vec3> out = f.denoised();
  for (const glm::vec3& r : out) ASSERT_TRUE(std::isfinite(r.r) && std::isfinite(r.g) && std::isfinite(r.b));
  EXPECT_NEAR(out[f.at(20, 16)].g, 0.5f, 0.1f);   // holes take their neighbours' estimate
  EXPECT_NEAR(out[f.at(21, 16)].r, 0.5f, 0.1f);
  EXPECT_NEAR(out[f.at(10, 10)].b, 0.5f, 0.1f);
  EXPECT_EQ(out[f.at(40, 20)], glm::vec3(0.0f));
  EXPECT_NEAR(statsOf(f, out, 16, 26, 12, 20).mean, 0.5, 0.03);
}

TEST(Denoiser, NonFiniteGuidesPassThrough) {
  Frame f(24, 24);
  addNoise(f, 0.5f);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  f.normal[f.at(5, 5)] = glm::vec3(nan);
  f.albedo[f.at(6, 5)] = glm::vec3(nan);
  f.depth[f.at(7, 5)] = nan;
  const std::vector<glm::vec3> out = f.denoised();
  for (uint32_t x = 5; x <= 7; ++x) EXPECT_EQ(out[f.at(x, 5)], f.radiance[f.at(x, 5)]);
  for (const glm::vec3& r : out) ASSERT_TRUE(std::isfinite(r.g));
}

TEST(Denoiser, SameResultWithOneAndTwoThreads) {
  Frame f(83, 61);   // odd sizes: partial row blocks
  addNoise(f, 0.9f);
  for (uint32_t y = 0; y < f.height; ++y)
    for (uint32_t x = 40; x < f.width; ++x) f.depth[f.at(x, y)] = 3.0f + 0.05f * static_cast<float>(y);
  std::vector<glm::vec3> one, two;
  tbb::task_arena(1).execute([&] { one = f.denoised(); });
  tbb::task_arena(2).execute([&] { two = f.denoised(); });
  ASSERT_EQ(one.size(), two.size());
  EXPECT_EQ(0, std::memcmp(one.data(), two.data(), one.size() * sizeof(glm::vec3)));
}

TEST(Denoiser, RejectsMismatchedSizes) {
  Frame f(8, 8);
  f.depth.pop_back();
  std::vector<glm::vec3> out = f.radiance;
  Denoiser denoiser;
  EXPECT_THROW(denoiser.apply(f.guides(), out), std::invalid_argument);
}

TEST(Denoiser, EmptyFrameIsFine) {
  Frame f(0, 0);
  EXPECT_TRUE(f.denoised().empty());
}

}  // namespace
}  // namespace pa::denoise
