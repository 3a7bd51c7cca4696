// Known-answer tests for PSNR and SSIM.
#include "tests/fidelity/image_metrics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

namespace pa::fidelity {
namespace {

RgbImage filled(int width, int height, std::uint8_t value) {
  return RgbImage{width, height, std::vector<std::uint8_t>(static_cast<size_t>(width) * height * 3, value)};
}

RgbImage checkerboard(int width, int height, std::uint8_t low, std::uint8_t high) {
  RgbImage image = filled(width, height, low);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      if ((x + y) % 2)
        for (int c = 0; c < 3; ++c) image.pixels[(static_cast<size_t>(y) * width + x) * 3 + c] = high;
  return image;
}

TEST(ImageMetrics, CropKeepsTheRectangle) {
  RgbImage image = filled(4, 3, 0);
  for (size_t i = 0; i < image.pixels.size(); ++i) image.pixels[i] = static_cast<std::uint8_t>(i);
  const RgbImage part = crop(image, 1, 1, 2, 2);
  ASSERT_EQ(part.width, 2);
  ASSERT_EQ(part.height, 2);
  // Pixel (1, 1) starts at byte (1 * 4 + 1) * 3 = 15; (1, 2) at (2 * 4 + 1) * 3 = 27.
  EXPECT_EQ(part.pixels[0], 15);
  EXPECT_EQ(part.pixels[5], 20);
  EXPECT_EQ(part.pixels[6], 27);
  EXPECT_THROW(crop(image, 3, 0, 2, 1), std::invalid_argument);
  EXPECT_THROW(crop(image, 0, 0, 0, 1), std::invalid_argument);
}

TEST(ImageMetrics, MeanLinearLuminanceKnownAnswers) {
  EXPECT_DOUBLE_EQ(meanLinearLuminance(filled(4, 4, 0)), 0.0);
  EXPECT_NEAR(meanLinearLuminance(filled(4, 4, 255)), 1.0, 1e-12);
  // sRGB 188 is linear 0.50289 (IEC 61966-2-1); a checkerboard of 0 and 255 has mean 0.5.
  EXPECT_NEAR(meanLinearLuminance(filled(4, 4, 188)), 0.50289, 1e-5);
  EXPECT_NEAR(meanLinearLuminance(checkerboard(8, 8, 0, 255)), 0.5, 1e-12);
  RgbImage green = filled(2, 2, 0);
  for (int i = 0; i < 4; ++i) green.pixels[3 * i + 1] = 255;
  EXPECT_NEAR(meanLinearLuminance(green), 0.7152, 1e-12);
}

TEST(ImageMetrics, WorstTileFindsTheTileThatDiffers) {
  const RgbImage a = filled(100, 70, 50);
  RgbImage b = a;
  // One pixel of the edge tile (96, 32) differs by 30 in one channel, one of tile (0, 0) by 3.
  b.pixels[(static_cast<size_t>(40) * 100 + 98) * 3 + 1] = 80;
  b.pixels[0] = 53;
  const WorstTile worst = worstTile(a, b, 32);
  EXPECT_EQ(worst.x, 96);
  EXPECT_EQ(worst.y, 32);
  EXPECT_EQ(worst.size, 32);
  // The tile is cut to the image: 4 x 32 pixels, 3 samples each.
  EXPECT_DOUBLE_EQ(worst.mse, 900.0 / (4 * 32 * 3));
  EXPECT_NEAR(worst.psnr, 10 * std::log10(255.0 * 255.0 / worst.mse), 1e-9);
  const WorstTile same = worstTile(a, a, 32);
  EXPECT_EQ(same.x, 0);
  EXPECT_EQ(same.y, 0);
  EXPECT_TRUE(std::isinf(same.psnr));
  EXPECT_THROW(worstTile(a, filled(10, 10, 0), 32), std::invalid_argument);
  EXPECT_THROW(worstTile(a, b, 0), std::invalid_argument);
}

TEST(ImageMetrics, IdenticalImagesHaveInfinitePsnrAndUnitSsim) {
  const auto image = checkerboard(32, 24, 10, 200);
  const auto result = compare(image, image);
  EXPECT_EQ(result.mse, 0);
  EXPECT_TRUE(std::isinf(result.psnr));
  EXPECT_DOUBLE_EQ(result.ssim, 1.0);
  EXPECT_EQ(result.maxAbsDiff, 0);
}

TEST(ImageMetrics, ConstantOffsetGivesKnownPsnr) {
  // Every sample differs by 10: MSE 100, PSNR = 20 log10(255 / 10) = 28.1308 dB.
  const auto result = compare(filled(16, 16, 100), filled(16, 16, 110));
  EXPECT_DOUBLE_EQ(result.mse, 100);
  EXPECT_NEAR(result.psnr, 28.1308, 1e-4);
  EXPECT_EQ(result.maxAbsDiff, 10);
}

TEST(ImageMetrics, FlatImagesSsimIsTheLuminanceTerm) {
  // No variance: SSIM = (2 mu_a mu_b + C1) / (mu_a^2 + mu_b^2 + C1), C1 = (0.01 * 255)^2.
  const double c1 = 2.55 * 2.55;
  const double expected = (2 * 100.0 * 150.0 + c1) / (100.0 * 100.0 + 150.0 * 150.0 + c1);
  EXPECT_NEAR(compare(filled(20, 20, 100), filled(20, 20, 150)).ssim, expected, 1e-12);
}

TEST(ImageMetrics, InvertedStructureHasNegativeSsim) {
  // Same means and variances, perfectly anti-correlated: SSIM close to -1.
  const auto result = compare(checkerboard(24, 24, 50, 200), checkerboard(24, 24, 200, 50));
  EXPECT_LT(result.ssim, -0.9);
}

TEST(ImageMetrics, LumaUsesBt601Weights) {
  RgbImage image{1, 1, {255, 0, 0}};
  EXPECT_NEAR(luma(image)[0], 0.299 * 255, 1e-12);
  image.pixels = {0, 0, 255};
  EXPECT_NEAR(luma(image)[0], 0.114 * 255, 1e-12);
}

TEST(ImageMetrics, RejectsMismatchedOrTinyImages) {
  EXPECT_THROW(compare(filled(16, 16, 0), filled(16, 17, 0)), std::invalid_argument);
  EXPECT_THROW(compare(filled(10, 10, 0), filled(10, 10, 0)), std::invalid_argument);
}

TEST(ImageMetrics, DifferenceImageScalesAndClamps) {
  const auto diff = differenceImage(filled(2, 2, 100), filled(2, 2, 110), 4);
  EXPECT_EQ(diff.pixels[0], 40);
  const auto clamped = differenceImage(filled(2, 2, 0), filled(2, 2, 200), 4);
  EXPECT_EQ(clamped.pixels[0], 255);
}

}  // namespace
}  // namespace pa::fidelity
