// Automatic exposure (film/auto_exposure.h): known-answer metering and the clamps.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

#include "renderer/scene/film/auto_exposure.h"
#include "renderer/scene/film/film.h"

namespace pa {
namespace {

constexpr float kSky = std::numeric_limits<float>::infinity();

TEST(AutoExposure, LogAverageOfTheWorldPixelsIsBroughtToTheTargetKey) {
  // Two world pixels at grey 0.01 and 0.04: key = sqrt(0.01 * 0.04) = 0.02, gain 0.045 / 0.02 = 2.25.
  // The bright sky pixel does not take part.
  const std::vector<glm::vec3> radiance = {glm::vec3(0.01f), glm::vec3(0.04f), glm::vec3(50.0f)};
  const std::vector<float> depth = {3.0f, 7.0f, kSky};
  const AutoExposure a = meterAutoExposure(radiance, depth);
  EXPECT_NEAR(a.key, 0.02f, 1e-6f);
  EXPECT_NEAR(a.gain, 2.25f, 1e-5f);
  EXPECT_EQ(a.meteredPixels, 2u);
  EXPECT_FALSE(a.meteredSky);
  EXPECT_EQ(a.clamped, ExposureClamp::None);
}

TEST(AutoExposure, LuminanceUsesRec709Weights) {
  // Pure green 0.045 / 0.7152 has luminance 0.045: gain 1.
  const std::vector<glm::vec3> radiance = {glm::vec3(0.0f, 0.045f / 0.7152f, 0.0f)};
  const AutoExposure a = meterAutoExposure(radiance, std::vector<float>{1.0f});
  EXPECT_NEAR(a.gain, 1.0f, 1e-5f);
}

TEST(AutoExposure, BlackPixelsCountAtTheBlackLevel) {
  // Half black, half 0.01: key = sqrt(0.001 * 0.01) = 0.00316 (not 0), gain 14.2; a quarter
  // black: key 0.001^0.25 * 0.01^0.75 = 0.00562, gain 8.002.
  const std::vector<glm::vec3> radiance = {glm::vec3(0.0f), glm::vec3(0.01f)};
  const AutoExposure a = meterAutoExposure(radiance, std::vector<float>{1.0f, 1.0f});
  EXPECT_NEAR(a.key, std::sqrt(1e-5f), 1e-7f);
  EXPECT_NEAR(a.gain, 0.045f / std::sqrt(1e-5f), 1e-3f);
  EXPECT_EQ(a.clamped, ExposureClamp::None);
  const std::vector<glm::vec3> quarter = {glm::vec3(0.0f), glm::vec3(0.01f), glm::vec3(0.01f), glm::vec3(0.01f)};
  EXPECT_NEAR(meterAutoExposure(quarter, std::vector<float>(4, 1.0f)).gain,
              0.045f / (std::pow(0.001f, 0.25f) * std::pow(0.01f, 0.75f)), 1e-3f);
}

TEST(AutoExposure, BlackImageHitsTheUpperClampAndBrightImageTheLower) {
  const std::vector<glm::vec3> black(64, glm::vec3(0.0f));
  const std::vector<float> depth(64, 2.0f);
  const AutoExposure dark = meterAutoExposure(black, depth);
  EXPECT_FLOAT_EQ(dark.gain, 16.0f);
  EXPECT_EQ(dark.clamped, ExposureClamp::Max);
  const std::vector<glm::vec3> bright(64, glm::vec3(100.0f));
  const AutoExposure blown = meterAutoExposure(bright, depth);
  EXPECT_FLOAT_EQ(blown.gain, 0.125f);
  EXPECT_EQ(blown.clamped, ExposureClamp::Min);
}

TEST(AutoExposure, AllSkyMetersTheSkyAndNoDepthMetersEverything) {
  const std::vector<glm::vec3> radiance = {glm::vec3(0.09f), glm::vec3(0.0225f)};
  const AutoExposure sky = meterAutoExposure(radiance, std::vector<float>{kSky, kSky});
  EXPECT_TRUE(sky.meteredSky);
  EXPECT_EQ(sky.meteredPixels, 2u);
  EXPECT_NEAR(sky.gain, 1.0f, 1e-5f);   // key sqrt(0.09 * 0.0225) = 0.045
  const AutoExposure all = meterAutoExposure(radiance, {});
  EXPECT_FALSE(all.meteredSky);
  EXPECT_NEAR(all.gain, 1.0f, 1e-5f);
}

TEST(AutoExposure, NonFiniteRadianceIsSkippedAndNothingToMeterKeepsGainOne) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const std::vector<glm::vec3> radiance = {glm::vec3(nan), glm::vec3(0.045f)};
  const AutoExposure a = meterAutoExposure(radiance, std::vector<float>{1.0f, 1.0f});
  EXPECT_EQ(a.meteredPixels, 1u);
  EXPECT_NEAR(a.gain, 1.0f, 1e-5f);
  const AutoExposure none = meterAutoExposure({}, {});
  EXPECT_EQ(none.meteredPixels, 0u);
  EXPECT_FLOAT_EQ(none.gain, 1.0f);
  EXPECT_FLOAT_EQ(none.key, 0.0f);
}

TEST(AutoExposure, RejectsMismatchedDepthAndBadSettings) {
  const std::vector<glm::vec3> radiance(4, glm::vec3(0.1f));
  EXPECT_THROW(meterAutoExposure(radiance, std::vector<float>(3, 1.0f)), std::invalid_argument);
  AutoExposureSettings inverted;
  inverted.minGain = 4.0f;
  inverted.maxGain = 2.0f;
  EXPECT_THROW(meterAutoExposure(radiance, {}, inverted), std::invalid_argument);
  AutoExposureSettings zeroKey;
  zeroKey.targetKey = 0.0f;
  EXPECT_THROW(meterAutoExposure(radiance, {}, zeroKey), std::invalid_argument);
}

TEST(EncodeDisplay, AppliesExposureTonemapAndSrgbLikeTheFilm) {
  // Linear 0.05 x 4 = 0.2 -> sRGB 0.4845 -> 124; 0.5 x 4 clamps to 255.
  const std::vector<glm::vec3> linear = {glm::vec3(0.05f), glm::vec3(0.5f, 0.0f, 0.05f)};
  std::vector<uint8_t> rgba(8);
  encodeDisplay(linear, 4.0f, Tonemap::Clamp, rgba);
  EXPECT_EQ(rgba[0], 124);
  EXPECT_EQ(rgba[3], 255);
  EXPECT_EQ(rgba[4], 255);
  EXPECT_EQ(rgba[5], 0);
  EXPECT_EQ(rgba[6], 124);
  // The film's own encoding is the same function.
  Film film;
  film.resize(2, 1);
  for (uint32_t x = 0; x < 2; ++x) {
    PixelSample s;
    s.radiance = linear[x];
    film.pixel(x, 0).add(s);
  }
  film.finishFrame();
  film.resolveRows(0, 1, 4.0f, Tonemap::Clamp);
  EXPECT_EQ(film.rgba8(), rgba);
  std::vector<uint8_t> wrongSize(7);
  EXPECT_THROW(encodeDisplay(linear, 1.0f, Tonemap::Clamp, wrongSize), std::invalid_argument);
}

}  // namespace
}  // namespace pa
