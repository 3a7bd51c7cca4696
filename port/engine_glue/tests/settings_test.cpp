// The stock picture settings' arithmetic: gamma ramp, texture intensity, picmip halving and the
// baked-light shift (known answers worked out from the stock formulas); the presets' own scale and
// TAAU behind r_pt_scale's and r_pt_taau's defaults.
#include <limits>

#include <gtest/gtest.h>

#include "port/engine_glue/settings.h"

namespace glue {
namespace {

TEST(PictureSettings, GammaRampKnownAnswers) {
  const auto identity = gammaRamp(1.0f, 0);
  EXPECT_TRUE(isIdentityRamp(identity));
  const auto bright = gammaRamp(2.0f, 0);   // 255 sqrt(i / 255) + 0.5, truncated
  EXPECT_EQ(bright[0], 0);
  EXPECT_EQ(bright[128], 181);
  EXPECT_EQ(bright[255], 255);
  EXPECT_FALSE(isIdentityRamp(bright));
  EXPECT_EQ(gammaRamp(1.5f, 0)[64], 101);
  EXPECT_EQ(gammaRamp(0.5f, 0)[128], 64);    // darker: (128 / 255)^2 x 255
  EXPECT_EQ(gammaRamp(3.0f, 0)[1], 40);
  const auto overbright = gammaRamp(1.0f, 1);   // shifted left, clamped
  EXPECT_EQ(overbright[100], 200);
  EXPECT_EQ(overbright[200], 255);
}

TEST(PictureSettings, IntensityScalesColourBytesNotAlpha) {
  std::vector<uint8_t> rgba = {100, 200, 10, 50};
  applyIntensity(rgba, 1.5f);
  EXPECT_EQ(rgba, (std::vector<uint8_t>{150, 255, 15, 50}));
  std::vector<uint8_t> same = {100, 200, 10, 50};
  applyIntensity(same, 1.0f);
  EXPECT_EQ(same, (std::vector<uint8_t>{100, 200, 10, 50}));
}

TEST(PictureSettings, PicmipHalvesWithBoxAverages) {
  // 4 x 2: left 2x2 block values 0, 40, 80, 120 (red), right block all 200.
  std::vector<uint8_t> rgba;
  const uint8_t reds[8] = {0, 40, 200, 200, 80, 120, 200, 200};
  for (uint8_t r : reds) rgba.insert(rgba.end(), {r, 0, 0, 255});
  int width = 4, height = 2;
  auto half = picmipImage(rgba, width, height, 1);
  EXPECT_EQ(width, 2);
  EXPECT_EQ(height, 1);
  ASSERT_EQ(half.size(), 8u);
  EXPECT_EQ(half[0], 60);    // (0 + 40 + 80 + 120) / 4
  EXPECT_EQ(half[4], 200);
  EXPECT_EQ(half[3], 255);
  // Never below 1 x 1.
  width = 4;
  height = 2;
  auto tiny = picmipImage(rgba, width, height, 5);
  EXPECT_EQ(width, 1);
  EXPECT_EQ(height, 1);
  EXPECT_EQ(tiny.size(), 4u);
  EXPECT_EQ(tiny[0], 130);   // (60 + 200) / 2 rounded, the odd row repeated
}

TEST(PictureSettings, BakedLightShiftFollowsMapOverBrightBits) {
  PictureSettings picture;
  EXPECT_EQ(picture.lightShift(), 2);   // stock defaults: x4
  picture.mapOverBrightBits = 1;
  EXPECT_EQ(picture.lightShift(), 1);
  picture.mapOverBrightBits = -3;
  EXPECT_EQ(picture.lightShift(), 0);
}

TEST(PictureSettings, OverbrightBitsOnlyFullscreenAsStock) {
  PictureSettings picture;   // r_overBrightBits 1, r_mapOverBrightBits 2
  EXPECT_EQ(picture.displayOverBrightBits(), 0);   // a window: never overbright
  EXPECT_EQ(picture.bakedLightScale(), 1.0f);
  picture.fullscreen = true;
  EXPECT_EQ(picture.displayOverBrightBits(), 1);
  EXPECT_EQ(picture.lightShift(), 1);              // baked light shifted one bit less...
  EXPECT_EQ(picture.bakedLightScale(), 2.0f);      // ...and the product doubled
  picture.overBrightBits = 5;
  EXPECT_EQ(picture.displayOverBrightBits(), 2);   // at most 2 with 24-bit colour
  EXPECT_EQ(picture.lightShift(), 0);
  picture.overBrightBits = -1;
  EXPECT_EQ(picture.displayOverBrightBits(), 0);
}

TEST(TracerSettings, DefaultScaleAndTaauAreThePresets) {
  // r_pt_scale 0 and r_pt_taau -1 (the defaults): direct and path trace 0.35 of the window and
  // upscale with TAAU; lightmap and reference trace half of it and stretch it.
  EXPECT_FLOAT_EQ(effectiveScale(0.0f, Preset::Direct), 0.35f);
  EXPECT_FLOAT_EQ(effectiveScale(0.0f, Preset::Path), 0.35f);
  EXPECT_FLOAT_EQ(effectiveScale(0.0f, Preset::Lightmap), 0.5f);
  EXPECT_FLOAT_EQ(effectiveScale(0.0f, Preset::Reference), 0.5f);
  EXPECT_EQ(effectiveTaau(-1, Preset::Direct), 1);
  EXPECT_EQ(effectiveTaau(-1, Preset::Path), 1);
  EXPECT_EQ(effectiveTaau(-1, Preset::Lightmap), 0);
  EXPECT_EQ(effectiveTaau(-1, Preset::Reference), 0);
}

TEST(TracerSettings, SetValuesWinOverThePresetsWithinTheirRanges) {
  EXPECT_FLOAT_EQ(effectiveScale(0.5f, Preset::Direct), 0.5f);
  EXPECT_FLOAT_EQ(effectiveScale(1.0f, Preset::Lightmap), 1.0f);
  EXPECT_FLOAT_EQ(effectiveScale(0.01f, Preset::Path), 0.1f);   // above 0: at least 0.1
  EXPECT_FLOAT_EQ(effectiveScale(7.0f, Preset::Path), 1.0f);
  EXPECT_FLOAT_EQ(effectiveScale(-0.5f, Preset::Lightmap), 0.5f);   // not a scale: the preset's
  EXPECT_FLOAT_EQ(effectiveScale(std::numeric_limits<float>::quiet_NaN(), Preset::Path), 0.35f);
  EXPECT_FLOAT_EQ(effectiveScale(std::numeric_limits<float>::infinity(), Preset::Path), 0.35f);
  EXPECT_EQ(effectiveTaau(0, Preset::Direct), 0);
  EXPECT_EQ(effectiveTaau(2, Preset::Lightmap), 2);
  EXPECT_EQ(effectiveTaau(9, Preset::Path), 2);
  EXPECT_EQ(effectiveTaau(-5, Preset::Lightmap), 0);
}

TEST(TracerSettings, TaauSizeStaysWithinItsRange) {
  EXPECT_FLOAT_EQ(effectiveTaauSize(1.0f), 1.0f);   // the default: the window
  EXPECT_FLOAT_EQ(effectiveTaauSize(0.5f), 0.5f);
  EXPECT_FLOAT_EQ(effectiveTaauSize(0.1f), 0.25f);
  EXPECT_FLOAT_EQ(effectiveTaauSize(3.0f), 1.0f);
  EXPECT_FLOAT_EQ(effectiveTaauSize(std::numeric_limits<float>::quiet_NaN()), 1.0f);
}

TEST(TracerSettings, TaauOutputIsThePartOfTheViewAndNeverSmallerThanTheTrace) {
  using Size = std::array<uint32_t, 2>;
  EXPECT_EQ(taauOutputSize(640, 360, 224, 126, 1.0f), (Size{640, 360}));
  // Half the window: the presentation's stretch by 2 on the CPU.
  EXPECT_EQ(taauOutputSize(640, 360, 224, 126, 0.5f), (Size{320, 180}));
  EXPECT_EQ(taauOutputSize(1281, 721, 448, 252, 0.5f), (Size{641, 361}));   // rounded
  // Traced larger than the part asked (dynamic resolution above it): the traced size.
  EXPECT_EQ(taauOutputSize(640, 360, 448, 252, 0.5f), (Size{448, 252}));
  EXPECT_EQ(taauOutputSize(8, 8, 8, 8, 0.25f), (Size{8, 8}));
}

}  // namespace
}  // namespace glue
