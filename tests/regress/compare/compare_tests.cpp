// Known-answer tests of pa-regress's comparisons: LDR-FLIP and the noise-aware Z-test.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "tests/regress/compare/flip.h"
#include "tests/regress/compare/heat_map.h"
#include "tests/regress/compare/noise_test.h"

namespace pa::regress {
namespace {

std::vector<std::uint8_t> uniform(int w, int h, std::uint8_t r, std::uint8_t g, std::uint8_t b) {
  std::vector<std::uint8_t> out;
  for (int i = 0; i < w * h; ++i) out.insert(out.end(), {r, g, b});
  return out;
}

TEST(Flip, IdenticalImagesHaveZeroError) {
  std::vector<std::uint8_t> img(24 * 16 * 3);
  for (size_t i = 0; i < img.size(); ++i) img[i] = static_cast<std::uint8_t>((i * 37) % 256);
  for (float e : flipErrorMap(img, img, 24, 16)) EXPECT_EQ(e, 0.0f);
}

// The paper normalises colour errors by the Hunt-adjusted distance of pure green to pure blue:
// two flat fields of those colours (no features) have error exactly 1.
TEST(Flip, GreenAgainstBlueIsTheMaximum) {
  for (float e : flipErrorMap(uniform(20, 12, 0, 255, 0), uniform(20, 12, 0, 0, 255), 20, 12)) EXPECT_NEAR(e, 1.0f, 1e-5f);
}

TEST(Flip, SymmetricAndGrowsWithTheDifference) {
  const auto grey = uniform(16, 16, 128, 128, 128);
  const float small = flipErrorMap(grey, uniform(16, 16, 133, 128, 128), 16, 16)[100];
  const float large = flipErrorMap(grey, uniform(16, 16, 200, 128, 128), 16, 16)[100];
  EXPECT_GT(small, 0.0f);
  EXPECT_LT(small, large);
  EXPECT_FLOAT_EQ(large, flipErrorMap(uniform(16, 16, 200, 128, 128), grey, 16, 16)[100]);
}

TEST(Flip, AnEdgeMovedByOnePixelIsSeenAtTheEdgeOnly) {
  const int w = 40, h = 8;
  auto a = uniform(w, h, 20, 20, 20), b = a;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c) {
        if (x >= 20) a[3 * (y * w + x) + c] = 230;
        if (x >= 21) b[3 * (y * w + x) + c] = 230;
      }
  const auto e = flipErrorMap(a, b, w, h);
  EXPECT_GT(e[4 * w + 20], 0.5f);
  EXPECT_LT(e[4 * w + 2], 0.01f);
  EXPECT_LT(e[4 * w + 38], 0.01f);
}

TEST(Flip, RejectsMismatchedBuffers) {
  EXPECT_THROW(flipErrorMap(uniform(4, 4, 0, 0, 0), uniform(4, 5, 0, 0, 0), 4, 4), std::invalid_argument);
}

TEST(NoiseTest, CriticalValuesOfTheNormal) {
  EXPECT_NEAR(twoSidedCriticalZ(0.05), 1.959964, 1e-5);
  EXPECT_NEAR(twoSidedCriticalZ(0.01), 2.575829, 1e-5);
  EXPECT_NEAR(twoSidedCriticalZ(1e-6), 4.891638, 1e-5);
}

// Two renders of one image: per pixel mean mu_i plus Gaussian noise of known variance.
HdrImage noisy(int w, int h, std::mt19937_64& rng, double bias) {
  HdrImage img{w, h, std::vector<float>(static_cast<size_t>(w) * h * 3), std::vector<float>(static_cast<size_t>(w) * h)};
  std::normal_distribution<double> normal;
  for (int i = 0; i < w * h; ++i) {
    const double mu = 0.2 + 0.001 * (i % 97), sigma = 0.01 + 0.0001 * (i % 13);
    const double y = mu + bias + sigma * normal(rng);
    for (int c = 0; c < 3; ++c) img.rgb[3 * i + c] = static_cast<float>(y);  // grey: luminance = y
    img.varianceY[i] = static_cast<float>(sigma * sigma);
  }
  return img;
}

// The Sidak threshold holds the family-wise false-alarm rate at alpha: with the pixel scale alone
// and "every pixel must pass", 400 unchanged pairs of 1000 pixels fail about 4 times at
// alpha = 0.01 (binomial: 0..12 holds with probability > 0.999). The default test (99.75 % of the
// pixels, plus 8x8 tiles and the whole image at alpha / 3 each) fails at most 2/3 alpha: about 2.7.
TEST(NoiseTest, FalseAlarmRateIsAlpha) {
  std::mt19937_64 rng(12345);
  int anyPixel = 0, defaults = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const HdrImage a = noisy(40, 25, rng, 0), b = noisy(40, 25, rng, 0);
    if (!noiseTest(a, b, {0.01, 1.0, {}}).pass) ++anyPixel;
    if (!noiseTest(a, b, {}).pass) ++defaults;
  }
  std::printf("false alarms in 400 unchanged pairs: any pixel %d, default test %d\n", anyPixel, defaults);
  EXPECT_LE(anyPixel, 12);
  EXPECT_LE(defaults, 10);
}

// A bias of a third of a standard deviation everywhere: no pixel can tell, the whole image can.
TEST(NoiseTest, ASmallBiasEverywhereFailsAtTheWholeImageScale) {
  std::mt19937_64 rng(99);
  const HdrImage a = noisy(40, 25, rng, 0), b = noisy(40, 25, rng, 0.005);
  const auto pixelsOnly = noiseTest(b, a, {0.01, 0.9975, {}});
  EXPECT_TRUE(pixelsOnly.pass);
  const auto r = noiseTest(b, a, {});
  EXPECT_FALSE(r.pass);
  ASSERT_EQ(r.scales.size(), 2u);
  EXPECT_EQ(r.scales[1].tiles, 1u);
  EXPECT_EQ(r.scales[1].failedTiles, 1u);
}

TEST(NoiseTest, ABiasOfFiveStandardDeviationsFails) {
  std::mt19937_64 rng(7);
  const HdrImage a = noisy(40, 25, rng, 0), b = noisy(40, 25, rng, 0.07);  // sqrt(2) * 0.0112 * 5 ~ 0.08
  const auto r = noiseTest(b, a, {});
  EXPECT_FALSE(r.pass);
  EXPECT_GT(r.failedPixels, 100u);
}

TEST(NoiseTest, ANoiselessPixelThatChangesFails) {
  HdrImage a{2, 1, {0.5f, 0.5f, 0.5f, 0.1f, 0.1f, 0.1f}, {0.0f, 0.0f}}, b = a;
  EXPECT_TRUE(noiseTest(a, b, {0.01, 1.0}).pass);
  b.rgb[3] = 0.2f;
  const auto r = noiseTest(b, a, {0.01, 1.0});
  EXPECT_FALSE(r.pass);
  EXPECT_TRUE(std::isinf(r.z[1]));
}

TEST(HeatMap, EndsAreBlackAndPaleYellow) {
  const auto img = heatMap({0.0f, 2.0f, INFINITY}, 3, 1, 1.0f);
  EXPECT_EQ(img.pixels[0], 0);
  EXPECT_EQ(img.pixels[2], 4);
  EXPECT_EQ(img.pixels[3], 252);
  EXPECT_EQ(img.pixels[8], 164);
}

}  // namespace
}  // namespace pa::regress
