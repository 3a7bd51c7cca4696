// Film accumulation (exactness over 100k frames), Welford variance, tonemapping.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <vector>

#include "renderer/core/srgb.h"

#include "renderer/scene/film/film.h"
#include "renderer/scene/sampling/sobol_sampler.h"

namespace pa {
namespace {

TEST(Film, RunningMeanOverHundredThousandFramesStaysExact) {
  // 200k frames of values whose exact mean is known: a constant that float sums would drift
  // on (0.1f), and a deterministic pseudo-random stream compared with a long-double sum.
  PixelAccumulator acc;
  long double exact = 0.0L;
  constexpr uint32_t kFrames = 200000;
  for (uint32_t i = 0; i < kFrames; ++i) {
    const float v = 0.1f + 10.0f * sampling::toUnitFloat(sampling::hash32(i));
    PixelSample s;
    s.radiance = glm::vec3(v, 0.1f, 1e4f);
    acc.add(s);
    exact += v;
  }
  const double mean0 = acc.radiance[0] / static_cast<double>(acc.samples);
  EXPECT_NEAR(mean0, static_cast<double>(exact / kFrames), 1e-9 * mean0);
  EXPECT_NEAR(acc.radiance[1] / acc.samples, double{0.1f}, 1e-12);
  EXPECT_NEAR(acc.radiance[2] / acc.samples, 1e4, 1e-8);
  // Resolved through the Film, the float output is the correctly rounded mean.
  Film film;
  film.resize(1, 1);
  film.pixel(0, 0) = acc;
  film.finishFrame();
  film.resolveRows(0, 1, 1.0f, Tonemap::Clamp);
  EXPECT_EQ(film.radiance()[0].y, 0.1f);
}

TEST(Film, WelfordVarianceMatchesTwoPass) {
  RunningStats stats;
  std::vector<double> xs;
  for (uint32_t i = 0; i < 1000; ++i) {
    const double x = 1e6 + sampling::toUnitFloat(sampling::hash32(i + 7));   // large offset: naive sums fail
    xs.push_back(x);
    stats.add(x);
  }
  double mean = 0.0;
  for (double x : xs) mean += x;
  mean /= xs.size();
  double var = 0.0;
  for (double x : xs) var += (x - mean) * (x - mean);
  var /= (xs.size() - 1);
  EXPECT_NEAR(stats.mean(), mean, 1e-8);   // 1e-14 relative
  EXPECT_NEAR(stats.variance(), var, 1e-9);
  EXPECT_NEAR(stats.varianceOfMean(), var / xs.size(), 1e-12);
  EXPECT_NEAR(stats.variance(), 1.0 / 12.0, 0.01);   // uniform [0,1)
}

TEST(Film, NonFiniteSamplesCountAsBlackAndSkyDepthIsInfinite) {
  PixelAccumulator acc;
  PixelSample bad;
  bad.radiance = glm::vec3(NAN, INFINITY, 1.0f);
  acc.add(bad);
  PixelSample good;
  good.radiance = glm::vec3(2.0f);
  acc.add(good);
  EXPECT_DOUBLE_EQ(acc.radiance[0], 2.0);
  EXPECT_DOUBLE_EQ(acc.radiance[2], 2.0);
  Film film;
  film.resize(1, 1);
  film.pixel(0, 0) = acc;
  film.resolveRows(0, 1, 1.0f, Tonemap::AcesFitted);
  EXPECT_TRUE(std::isinf(film.depth()[0]));
}

TEST(Film, TonemapCurvesAndSrgbEncoding) {
  EXPECT_EQ(tonemap(glm::vec3(0.0f), Tonemap::AcesFitted), glm::vec3(0.0f));
  EXPECT_NEAR(tonemap(glm::vec3(1e6f), Tonemap::AcesFitted).r, 1.0f, 1e-3f);
  EXPECT_NEAR(tonemap(glm::vec3(1.0f), Tonemap::Reinhard).g, 0.5f, 1e-6f);
  EXPECT_EQ(tonemap(glm::vec3(2.0f, 0.5f, -1.0f), Tonemap::Clamp), glm::vec3(1.0f, 0.5f, 0.0f));
  Film film;
  film.resize(2, 1);
  PixelSample s;
  s.radiance = glm::vec3(0.2158605f);   // sRGB 128
  film.pixel(0, 0).add(s);
  s.radiance = glm::vec3(1.0f);
  film.pixel(1, 0).add(s);
  film.resolveRows(0, 1, 1.0f, Tonemap::Clamp);
  EXPECT_EQ(film.rgba8()[0], 128);
  EXPECT_EQ(film.rgba8()[3], 255);
  EXPECT_EQ(film.rgba8()[4], 255);
  film.resolveRows(0, 1, 0.5f, Tonemap::Clamp);   // exposure halves radiance before encoding
  EXPECT_EQ(film.rgba8()[4], 188);                // sRGB(0.5) = 0.7354 -> 188
}

TEST(Film, DisplaySpaceLightingShowsLightAsALightMapTexel) {
  // Texture byte 128 (albedo 0.2158605) under light 0.5 (half of full bright), as a light map
  // shows it: byte 128 x 0.5 = 64 -> linear srgbToLinear(64/255); physical radiance would be
  // 0.108 (byte 92).
  const float albedo = 0.2158605f;
  const glm::vec3 lit = lightingLook(glm::vec3(albedo * 0.5f), glm::vec3(0.0f), glm::vec3(albedo),
                                     LightingLook::DisplaySpace);
  EXPECT_NEAR(lit.r, srgbToLinear(64.0f / 255.0f), 2e-4f);
  EXPECT_EQ(lightingLook(glm::vec3(albedo * 0.5f), glm::vec3(0.0f), glm::vec3(albedo), LightingLook::Physical),
            glm::vec3(albedo * 0.5f));
  // Full bright (light 1) shows the texture unmodified; brighter light is clamped to it, and an
  // over-bright coloured light is scaled down as a whole (hue kept), as the engine's shift does.
  EXPECT_NEAR(lightingLook(glm::vec3(albedo), glm::vec3(0.0f), glm::vec3(albedo), LightingLook::DisplaySpace).g,
              albedo, 1e-5f);
  const glm::vec3 over = lightingLook(glm::vec3(4.0f, 2.0f, 0.0f) * 0.5f, glm::vec3(0.0f), glm::vec3(0.5f),
                                      LightingLook::DisplaySpace);
  EXPECT_NEAR(over.r, 0.5f, 1e-5f);
  EXPECT_NEAR(over.g, srgbToLinear(0.5f * linearToSrgb(0.5f)), 1e-5f);
  EXPECT_EQ(over.b, 0.0f);
  // Emission (a glow stage) is added in display values, as a stock framebuffer adds it; a channel
  // without albedo (sky) keeps its radiance.
  const glm::vec3 glow = lightingLook(glm::vec3(0.3f + albedo * 0.25f, 2.0f, 0.0f), glm::vec3(0.3f, 2.0f, 0.0f),
                                      glm::vec3(albedo, 0.0f, albedo), LightingLook::DisplaySpace);
  EXPECT_NEAR(glow.r, srgbToLinear(32.0f / 255.0f + linearToSrgb(0.3f)), 2e-4f);
  EXPECT_EQ(glow.g, 2.0f);
  EXPECT_EQ(glow.b, 0.0f);
  // Through the film: encodeRows applies the look with the emission and albedo AOVs.
  Film film;
  film.resize(1, 1);
  PixelSample s;
  s.radiance = glm::vec3(albedo * 0.5f);
  s.albedo = glm::vec3(albedo);
  film.pixel(0, 0).add(s);
  film.resolveRows(0, 1, 1.0f, Tonemap::Clamp, LightingLook::DisplaySpace);
  EXPECT_EQ(film.rgba8()[0], 64);
  EXPECT_NEAR(film.radiance()[0].r, albedo * 0.5f, 1e-6f);   // the float radiance stays as traced
  film.resolveRows(0, 1, 1.0f, Tonemap::Clamp);
  EXPECT_EQ(film.rgba8()[0], 92);
}

}  // namespace
}  // namespace pa

namespace pa {
namespace {

TEST(Film, DisplaySpaceAddsEffectsInDisplayValuesAsTheStockFramebuffer) {
  // An additive effect of display value 0.5 over a wall shown at 0.3 (full-bright light) shows
  // 0.8, as GL_ONE GL_ONE over 8-bit display values does (added in linear values it was 0.58),
  // and two bright ones saturate at 1.
  const float wall = srgbToLinear(0.3f);
  const float effect = srgbToLinear(0.5f);
  const glm::vec3 shown = lightingLook(glm::vec3(wall + effect), glm::vec3(effect), glm::vec3(wall),
                                       LightingLook::DisplaySpace);
  EXPECT_NEAR(linearToSrgb(shown.r), 0.8f, 1e-4f);
  const glm::vec3 saturated = lightingLook(glm::vec3(wall + 3.0f), glm::vec3(3.0f), glm::vec3(wall),
                                           LightingLook::DisplaySpace);
  EXPECT_FLOAT_EQ(saturated.r, 1.0f);
  // Black emission changes nothing.
  const glm::vec3 plain = lightingLook(glm::vec3(wall), glm::vec3(0.0f), glm::vec3(wall), LightingLook::DisplaySpace);
  EXPECT_NEAR(plain.r, wall, 1e-6f);
}

TEST(Film, LightingLookRowsFollowLightingLook) {
  // The film's chunked look (sRGB curves without powf, eight values at a time) against the
  // per-pixel one: 1003 pixels (chunks of 256 and a partial register at the end) with dark,
  // over-bright, emissive and albedo-less channels.
  constexpr size_t kPixels = 1003;
  std::vector<glm::vec3> radiance(kPixels), emission(kPixels), albedo(kPixels), shown(kPixels);
  uint32_t state = 12345u;
  const auto unit = [&] {
    state = state * 1664525u + 1013904223u;
    return float(state >> 8) / float(1u << 24);
  };
  for (size_t i = 0; i < kPixels; ++i) {
    for (int c = 0; c < 3; ++c) {
      albedo[i][c] = i % 11 == 0 && c == 1 ? 0.5f / 255.0f : unit();
      emission[i][c] = i % 5 == 0 ? (i % 3 == 0 ? 2.0f : 0.5f) * unit() : 0.0f;   // some above 1
      radiance[i][c] = emission[i][c] + albedo[i][c] * (i % 7 == 0 ? 4.0f * unit() : unit());
    }
  }
  lightingLookRows(radiance, emission, albedo, LightingLook::DisplaySpace, shown);
  for (size_t i = 0; i < kPixels; ++i) {
    const glm::vec3 exact = lightingLook(radiance[i], emission[i], albedo[i], LightingLook::DisplaySpace);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(shown[i][c], exact[c], 1e-6f + 1e-6f * exact[c]) << i << " " << c;
  }
  lightingLookRows(radiance, emission, albedo, LightingLook::Physical, shown);
  EXPECT_EQ(shown, radiance);
}

TEST(SrgbByteEncoder, EveryFloatEncodesAsTheExactCurve) {
  // lround(clamp(linearToSrgb(x)) x 255) over every 64th float in [0, 1.25], plus the edges.
  const SrgbByteEncoder encode;
  const auto exact = [](float x) {
    const float e = std::clamp(linearToSrgb(x), 0.0f, 1.0f);
    return e >= 0.0f ? static_cast<uint8_t>(std::lround(e * 255.0f)) : uint8_t{0};
  };
  uint64_t checked = 0;
  for (uint32_t bits = 0; bits <= std::bit_cast<uint32_t>(1.25f); bits += 64, ++checked) {
    const float x = std::bit_cast<float>(bits);
    ASSERT_EQ(encode(x), exact(x)) << "x = " << x;
  }
  EXPECT_GT(checked, 15'000'000u);
  for (const float x : {-1.0f, -0.0f, 1.0f, 2.0f, std::numeric_limits<float>::infinity(),
                        -std::numeric_limits<float>::infinity()})
    EXPECT_EQ(encode(x), exact(x)) << "x = " << x;
  EXPECT_EQ(encode(std::numeric_limits<float>::quiet_NaN()), 0);
  EXPECT_EQ(encode(0.5f), 188);   // sRGB 0.7354 -> 187.5 rounds up
}

}  // namespace
}  // namespace pa
