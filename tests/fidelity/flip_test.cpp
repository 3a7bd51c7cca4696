// Known-answer tests for LDR-FLIP (tests/fidelity/flip.h).
#include "tests/fidelity/flip.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <stdexcept>

namespace pa::fidelity {
namespace {

RgbImage filled(int width, int height, std::uint8_t r, std::uint8_t g, std::uint8_t b) {
  RgbImage image{width, height, std::vector<std::uint8_t>(static_cast<size_t>(width) * height * 3)};
  for (size_t i = 0; i < image.pixels.size(); i += 3) {
    image.pixels[i] = r;
    image.pixels[i + 1] = g;
    image.pixels[i + 2] = b;
  }
  return image;
}

RgbImage grey(int width, int height, std::uint8_t v) { return filled(width, height, v, v, v); }

RgbImage noisy(int width, int height, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> byte(0, 255);
  RgbImage image = grey(width, height, 0);
  for (auto& p : image.pixels) p = static_cast<std::uint8_t>(byte(rng));
  return image;
}

// Flat grey plus uniform noise of +-amplitude on every channel, clamped to 0..255.
RgbImage greyWithNoise(int width, int height, int base, int amplitude, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> offset(-amplitude, amplitude);
  RgbImage image = grey(width, height, 0);
  for (auto& p : image.pixels) p = static_cast<std::uint8_t>(std::clamp(base + offset(rng), 0, 255));
  return image;
}

// The paper's colour pipeline by hand on two flat colours given as CIELAB (D65) values: on flat
// images the CSF filters change nothing and the feature term vanishes, so FLIP is the mapped,
// compressed HyAB distance of the Hunt-adjusted colours. c_max from the published CIELAB of the
// sRGB green (87.7347, -86.1827, 83.1793) and blue (32.2970, 79.1875, -107.8602) primaries.
double handFlip(double l1, double a1, double b1, double l2, double a2, double b2) {
  auto hyabHunt = [](double la, double aa, double ba, double lb, double ab, double bb) {
    return std::abs(la - lb) + std::hypot(0.01 * la * aa - 0.01 * lb * ab, 0.01 * la * ba - 0.01 * lb * bb);
  };
  const double cmax = std::pow(hyabHunt(87.7347, -86.1827, 83.1793, 32.2970, 79.1875, -107.8602), 0.7);
  const double e = std::pow(hyabHunt(l1, a1, b1, l2, a2, b2), 0.7);
  return e < 0.4 * cmax ? 0.95 / (0.4 * cmax) * e : 0.95 + (e - 0.4 * cmax) / (0.6 * cmax) * 0.05;
}

void expectUniform(const FlipMap& map, double value, double tolerance) {
  EXPECT_NEAR(map.mean, value, tolerance);
  for (float e : map.error) ASSERT_NEAR(e, value, tolerance);
}

TEST(Flip, DefaultViewingIs67PixelsPerDegree) {
  EXPECT_NEAR(flipDefaultPixelsPerDegree(), 3840 * 3.14159265358979 / 180, 1e-9);
  EXPECT_NEAR(flipDefaultPixelsPerDegree(), 67.0206, 1e-4);
  EXPECT_NEAR(pixelsPerDegree(1.4, 0.7, 3840), 2 * flipDefaultPixelsPerDegree(), 1e-9);
}

TEST(Flip, IdenticalImagesScoreZero) {
  const RgbImage image = noisy(64, 48, 7);
  const FlipMap map = flip(image, image, flipDefaultPixelsPerDegree());
  ASSERT_EQ(map.error.size(), 64u * 48u);
  expectUniform(map, 0.0, 0.0);
}

TEST(Flip, FlatGreyPairsMatchThePapersFormulas) {
  const double ppd = flipDefaultPixelsPerDegree();
  // Grey v has a* = b* = 0 and L* = 116 cbrt(Y) - 16 with Y the sRGB-decoded v: L*(0) = 0,
  // L*(255) = 100, L*(128) = 53.5850, L*(118) = 49.6370. HyAB reduces to |dL*|.
  const double blackWhite = handFlip(0, 0, 0, 100, 0, 0);
  EXPECT_NEAR(blackWhite, 0.96738, 1e-5);  // upper segment of the mapping
  expectUniform(flip(grey(40, 30, 0), grey(40, 30, 255), ppd), blackWhite, 1e-4);
  expectUniform(flip(grey(40, 30, 0), grey(40, 30, 128), ppd), handFlip(0, 0, 0, 53.5850, 0, 0), 1e-4);
  const double close = handFlip(53.5850, 0, 0, 49.6370, 0, 0);
  EXPECT_NEAR(close, 0.15046, 1e-4);  // lower, linear segment
  expectUniform(flip(grey(40, 30, 128), grey(40, 30, 118), ppd), close, 1e-4);
}

TEST(Flip, FlatColourPairsMatchThePapersFormulas) {
  const double ppd = flipDefaultPixelsPerDegree();
  // Published CIELAB (D65) of sRGB red (53.2408, 80.0925, 67.2032) and green (above).
  expectUniform(flip(filled(33, 21, 255, 0, 0), filled(33, 21, 0, 255, 0), ppd),
                handFlip(53.2408, 80.0925, 67.2032, 87.7347, -86.1827, 83.1793), 1e-4);
  // Green against blue is c_max itself: the largest error, exactly 1.
  expectUniform(flip(filled(33, 21, 0, 255, 0), filled(33, 21, 0, 0, 255), ppd), 1.0, 1e-4);
}

TEST(Flip, IsSymmetricAndWithinZeroOne) {
  const RgbImage a = noisy(50, 40, 1), b = noisy(50, 40, 2);
  const double ppd = flipDefaultPixelsPerDegree();
  const FlipMap ab = flip(a, b, ppd), ba = flip(b, a, ppd);
  EXPECT_NEAR(ab.mean, ba.mean, 1e-12);
  for (size_t i = 0; i < ab.error.size(); ++i) {
    ASSERT_NEAR(ab.error[i], ba.error[i], 1e-6);
    ASSERT_GE(ab.error[i], 0.0f);
    ASSERT_LE(ab.error[i], 1.0f);
  }
  EXPECT_GT(ab.mean, 0.3);
}

TEST(Flip, OnePixelChangeScoresBelowAPatchChange) {
  const double ppd = flipDefaultPixelsPerDegree();
  const RgbImage base = grey(64, 64, 100);
  RgbImage pixel = base, patch = base;
  for (int c = 0; c < 3; ++c) pixel.pixels[(32 * 64 + 32) * 3 + c] = 200;
  for (int y = 24; y < 40; ++y)
    for (int x = 24; x < 40; ++x)
      for (int c = 0; c < 3; ++c) patch.pixels[(static_cast<size_t>(y) * 64 + x) * 3 + c] = 200;
  const FlipMap one = flip(base, pixel, ppd), many = flip(base, patch, ppd);
  EXPECT_GT(one.mean, 0.0);
  EXPECT_LT(one.mean, 0.01);
  EXPECT_GT(many.mean, 5 * one.mean);
  // The feature term raises the error at the changed pixel above the CSF-blurred colour error
  // alone: a lone bright pixel is a strong point.
  EXPECT_GT(one.error[32 * 64 + 32], one.error[32 * 64 + 36]);
}

TEST(Flip, LargerNoiseScoresHigher) {
  const double ppd = flipDefaultPixelsPerDegree();
  const RgbImage base = grey(64, 48, 120);
  const double small = flip(base, greyWithNoise(64, 48, 120, 8, 3), ppd).mean;
  const double medium = flip(base, greyWithNoise(64, 48, 120, 24, 3), ppd).mean;
  const double large = flip(base, greyWithNoise(64, 48, 120, 64, 3), ppd).mean;
  EXPECT_GT(small, 0.0);
  EXPECT_LT(small, medium);
  EXPECT_LT(medium, large);
}

TEST(Flip, FewerPixelsPerDegreeSeeMoreOfFineNoise) {
  // Seen from closer (lower ppd), the CSF blurs a pixel's noise less.
  const RgbImage base = grey(64, 48, 120), test = greyWithNoise(64, 48, 120, 24, 5);
  EXPECT_GT(flip(base, test, 20).mean, flip(base, test, 67).mean);
}

TEST(Flip, ErrorImageAndBadInput) {
  const FlipMap map = flip(grey(8, 8, 0), grey(8, 8, 255), flipDefaultPixelsPerDegree());
  const RgbImage image = flipErrorImage(map);
  ASSERT_EQ(image.width, 8);
  EXPECT_EQ(image.pixels[0], static_cast<std::uint8_t>(std::lround(map.error[0] * 255)));
  EXPECT_THROW(flip(grey(8, 8, 0), grey(8, 9, 0), 67), std::invalid_argument);
  EXPECT_THROW(flip(grey(8, 8, 0), grey(8, 8, 0), 0), std::invalid_argument);
}

}  // namespace
}  // namespace pa::fidelity
