// Known answers of the denoiser's lane helpers (weight_lanes.h) against their scalar forms, and of
// the row filters that take kCount pixels at a time: widths that are not a multiple of the lane
// count, the last block of a row, borders, constant images and ramps.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "renderer/scene/denoise/denoiser.h"
#include "renderer/scene/denoise/weight_lanes.h"

namespace pa::denoise {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

/// Every lane of f(lanes) must equal the scalar g(value) bit for bit, for values taken kCount at a time.
template <typename Lanes, typename Scalar>
void expectSameBits(const std::vector<float>& values, Lanes&& f, Scalar&& g) {
  for (size_t i = 0; i < values.size(); i += lanes::kCount) {
    lanes::F v;
    for (int k = 0; k < lanes::kCount; ++k) v[k] = values[std::min(values.size() - 1, i + k)];
    const lanes::F r = f(v);
    for (int k = 0; k < lanes::kCount; ++k)
      ASSERT_EQ(std::bit_cast<uint32_t>(r[k]), std::bit_cast<uint32_t>(g(v[k]))) << "x = " << v[k];
  }
}

std::vector<float> sweep() {
  std::vector<float> values = {0.0f, -0.0f, kNaN, -kInf, kInf, -80.0f, -80.00001f, -79.99999f, 1e-30f, -1e-30f, 3.0f};
  for (float x = -120.0f; x <= 2.0f; x += 0.0137f) values.push_back(x);
  return values;
}

TEST(WeightLanes, NegativeExpLanesAreTheScalarBits) {
  expectSameBits(sweep(), [](lanes::F v) { return negativeExp(v); }, [](float v) { return negativeExp(v); });
}

TEST(WeightLanes, NegativeExpKnownAnswers) {
  EXPECT_EQ(negativeExp(0.0f), 1.0f);
  EXPECT_EQ(negativeExp(5.0f), 1.0f);   // positive exponents count as 0
  for (float x : {-0.5f, -1.0f, -2.0f, -10.0f, -40.0f, -79.0f})
    EXPECT_NEAR(negativeExp(x) / std::exp(x), 1.0f, 1e-5f) << x;
  EXPECT_EQ(negativeExp(kMinExponent), kMinExponentWeight);
  EXPECT_NEAR(kMinExponentWeight / std::exp(kMinExponent), 1.0f, 1e-3f);
  EXPECT_EQ(negativeExp(-1000.0f), negativeExp(kMinExponent));
  EXPECT_EQ(negativeExp(kNaN), negativeExp(kMinExponent));
  EXPECT_EQ(negativeExp(-kInf), negativeExp(kMinExponent));
  EXPECT_GT(negativeExp(kMinExponent), 0.0f);
  EXPECT_LT(negativeExp(kMinExponent), 1e-34f);
}

TEST(WeightLanes, AbsoluteMaxAndLuminanceAreTheScalarBits) {
  const std::vector<float> values = sweep();
  expectSameBits(values, [](lanes::F v) { return absolute(v); }, [](float v) { return std::abs(v); });
  expectSameBits(values, [](lanes::F v) { return maxOf(v, lanes::splat(0.0f)); },
                 [](float v) { return std::max(v, 0.0f); });
  expectSameBits(values, [](lanes::F v) { return maxOf(lanes::splat(0.5f), v); },
                 [](float v) { return std::max(0.5f, v); });
  expectSameBits(values, [](lanes::F v) { return luminance(v, v * 0.5f, lanes::splat(2.0f) - v); },
                 [](float v) { return luminance(v, v * 0.5f, 2.0f - v); });
}

/// A frame of a plane facing the camera, depth growing along x (a ramp), radiance from `value`.
struct Frame {
  uint32_t width, height;
  std::vector<glm::vec3> radiance, albedo, normal;
  std::vector<float> depth, variance;
  Frame(uint32_t w, uint32_t h, float (*value)(uint32_t x, uint32_t y))
      : width(w), height(h), radiance(size_t{w} * h), albedo(size_t{w} * h), normal(size_t{w} * h, glm::vec3(0, 0, 1)),
        depth(size_t{w} * h), variance(size_t{w} * h, 0.0f) {
    for (uint32_t y = 0; y < h; ++y) {
      for (uint32_t x = 0; x < w; ++x) {
        const size_t i = size_t{y} * w + x;
        radiance[i] = glm::vec3(value(x, y), 0.5f * value(x, y), 0.25f);
        albedo[i] = glm::vec3(0.5f, 0.6f, 0.7f);
        depth[i] = 4.0f + 0.01f * static_cast<float>(x);
        if (x * 3 > w * 2) normal[i] = glm::vec3(0.6f, 0, 0.8f);   // an edge: another plane at the right
      }
    }
  }
  std::vector<glm::vec3> denoised(uint32_t iterations) const {
    std::vector<glm::vec3> out = radiance;
    Config config;
    config.iterations = iterations;
    Denoiser(config).apply(Guides{width, height, albedo, normal, depth, variance, 1, {}, {}}, out);
    return out;
  }
};

float noisy(uint32_t x, uint32_t y) {
  const uint32_t h = (x * 73856093u) ^ (y * 19349663u);
  return 0.3f + 0.2f * static_cast<float>(h % 1000u) / 1000.0f;
}
float constant(uint32_t, uint32_t) { return 0.375f; }
float ramp(uint32_t x, uint32_t) { return 0.1f + 0.01f * static_cast<float>(x); }

TEST(DenoiserRows, SkyBeyondTheBordersChangesNoBit) {
  // The planes' zero border is what sky pixels give: a frame extended by sky columns and rows
  // must filter its own pixels to the same bits, whatever the width's remainder by kCount.
  for (uint32_t width = 1; width <= 21; ++width) {
    for (uint32_t iterations : {1u, 3u, 5u}) {
      const Frame small(width, 6, noisy);
      Frame wide(width + 5, 9, noisy);
      for (uint32_t y = 0; y < wide.height; ++y) {
        for (uint32_t x = 0; x < wide.width; ++x) {
          const size_t i = size_t{y} * wide.width + x;
          if (x >= width || y >= small.height) wide.depth[i] = kInf;
          else wide.depth[i] = small.depth[size_t{y} * width + x], wide.normal[i] = small.normal[size_t{y} * width + x];
        }
      }
      const std::vector<glm::vec3> a = small.denoised(iterations), b = wide.denoised(iterations);
      for (uint32_t y = 0; y < small.height; ++y)
        for (uint32_t x = 0; x < width; ++x)
          for (int c = 0; c < 3; ++c)
            ASSERT_EQ(std::bit_cast<uint32_t>(a[size_t{y} * width + x][c]),
                      std::bit_cast<uint32_t>(b[size_t{y} * wide.width + x][c]))
                << "width " << width << " iterations " << iterations << " pixel " << x << "," << y;
    }
  }
}

TEST(DenoiserRows, ConstantImageStaysConstantAtEveryWidth) {
  for (uint32_t width = 1; width <= 20; ++width) {
    const Frame f(width, 5, constant);
    const std::vector<glm::vec3> out = f.denoised(5);
    for (size_t i = 0; i < out.size(); ++i) {
      EXPECT_NEAR(out[i].r, f.radiance[i].r, 1e-6f) << width << " " << i;
      EXPECT_NEAR(out[i].g, f.radiance[i].g, 1e-6f) << width << " " << i;
      EXPECT_NEAR(out[i].b, f.radiance[i].b, 1e-6f) << width << " " << i;
    }
  }
}

TEST(DenoiserRows, RampKeepsItsSlopeAwayFromBordersAndEdges) {
  // A linear ramp on a plane: symmetric weights average x - d and x + d to x, so pixels whose
  // whole reach (3 pixels for 2 passes) lies on the same plane keep their value.
  for (uint32_t width : {13u, 17u, 23u, 40u}) {
    const Frame f(width, 9, ramp);
    const std::vector<glm::vec3> out = f.denoised(2);
    for (uint32_t y = 3; y + 3 < f.height; ++y) {
      for (uint32_t x = 3; x + 3 < width && (x + 3) * 3 <= width * 2; ++x) {
        const size_t i = size_t{y} * width + x;
        EXPECT_NEAR(out[i].r, f.radiance[i].r, 2e-6f) << width << " " << x;
        EXPECT_NEAR(out[i].g, f.radiance[i].g, 2e-6f) << width << " " << x;
      }
    }
  }
}

TEST(DenoiserRows, MirroredFrameGivesTheMirroredImage) {
  // The kernel is symmetric: a frame mirrored left to right filters to the mirrored result (up
  // to the order of the sums), so the last block of a row is handled as the first.
  for (uint32_t width = 9; width <= 19; ++width) {
    const Frame f(width, 7, noisy);
    Frame m = f;
    for (uint32_t y = 0; y < f.height; ++y) {
      for (uint32_t x = 0; x < width; ++x) {
        const size_t i = size_t{y} * width + x, j = size_t{y} * width + (width - 1 - x);
        m.radiance[j] = f.radiance[i];
        m.normal[j] = f.normal[i];
        m.depth[j] = f.depth[i];
      }
    }
    const std::vector<glm::vec3> a = f.denoised(3), b = m.denoised(3);
    for (uint32_t y = 0; y < f.height; ++y) {
      for (uint32_t x = 0; x < width; ++x) {
        const glm::vec3 p = a[size_t{y} * width + x], q = b[size_t{y} * width + (width - 1 - x)];
        EXPECT_NEAR(p.r, q.r, 1e-5f * std::abs(p.r) + 1e-7f) << width << " " << x << "," << y;
        EXPECT_NEAR(p.g, q.g, 1e-5f * std::abs(p.g) + 1e-7f) << width << " " << x << "," << y;
      }
    }
  }
}

}  // namespace
}  // namespace pa::denoise
