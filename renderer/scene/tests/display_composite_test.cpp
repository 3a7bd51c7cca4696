// Known answers for the Lightmap preset's display-value compositing (DisplayComposite).
#include "renderer/scene/integrator/display_composite.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <vector>

#include "renderer/scene/textures/texture.h"

namespace pa {
namespace {

glm::vec3 linear(float display) { return glm::vec3(srgbToLinear(display)); }

/// A query's hits: the layers at their distances, left in drawing order as a query leaves them.
AdditiveHits hits(std::initializer_list<std::pair<float, DisplayComposite::Layer>> list) {
  AdditiveHits h;
  for (const auto& [t, layer] : list) {
    h.entries[h.count] = {t, h.count, 0, layer.color, layer.transmit};
    ++h.count;
  }
  std::sort(h.entries.begin(), h.entries.begin() + h.count, AdditiveHits::drawnBefore);
  return h;
}

TEST(DisplayComposite, FastSrgbCurveMatchesTheExactOne) {
  // Every 64th float in [0, 1] (17 million values) against the powf curve of texture.h.
  float worstEncode = 0.0f, worstDecode = 0.0f;
  uint32_t one;
  const float oneF = 1.0f;
  std::memcpy(&one, &oneF, sizeof one);
  for (uint32_t bits = 0; bits <= one; bits += 64) {
    float c;
    std::memcpy(&c, &bits, sizeof c);
    worstEncode = std::max(worstEncode, std::abs(fastLinearToSrgb(c) - linearToSrgb(c)));
    worstDecode = std::max(worstDecode, std::abs(fastSrgbToLinear(c) - srgbToLinear(c)));
  }
  std::printf("largest difference: encode %.3g, decode %.3g\n", worstEncode, worstDecode);
  EXPECT_LT(worstEncode, 2.5e-7f);   // measured 1.2e-7 and 1.8e-7: one or two float steps near 1
  EXPECT_LT(worstDecode, 2.5e-7f);
  EXPECT_FLOAT_EQ(fastLinearToSrgb(1.0f), linearToSrgb(1.0f));
  EXPECT_FLOAT_EQ(fastSrgbToLinear(1.0f), srgbToLinear(1.0f));
  EXPECT_EQ(fastLinearToSrgb(-2.0f), 0.0f);   // clamped to [0, 1]
  EXPECT_FLOAT_EQ(fastLinearToSrgb(7.0f), linearToSrgb(1.0f));
}

TEST(DisplayComposite, ColoursAtOnceEncodeAndDecodeAsOneByOne) {
  // encodeColors (vertex light, encoded at commit and interpolated in display values) and the
  // colour decode give each channel exactly the single-value functions' bits, over [-0.5, 1.5]
  // with NaN and infinities.
  std::vector<float> values;
  for (int k = -5000; k <= 15000; ++k) values.push_back(static_cast<float>(k) * 1e-4f + 1e-7f * static_cast<float>(k % 7));
  values.insert(values.end(), {std::nanf(""), std::numeric_limits<float>::infinity(),
                               -std::numeric_limits<float>::infinity(), 0.0f, -0.0f, 1.0f});
  const auto same = [](float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; };
  std::vector<glm::vec4> colours;
  for (size_t i = 0; i + 3 <= values.size(); i += 3) colours.push_back({values[i], values[i + 1], values[i + 2], 1.0f});
  std::vector<glm::vec3> encoded;
  encodeColors(colours, encoded);
  ASSERT_EQ(encoded.size(), colours.size());
  for (size_t k = 0; k < colours.size(); ++k) {
    const glm::vec3 decoded = fastSrgbToLinear(glm::vec3(colours[k]));
    for (int c = 0; c < 3; ++c) {
      ASSERT_TRUE(same(encoded[k][c], fastLinearToSrgb(colours[k][c]))) << colours[k][c];
      ASSERT_TRUE(same(decoded[c], fastSrgbToLinear(colours[k][c]))) << colours[k][c];
    }
  }
}

TEST(DisplayComposite, MeshColoursEncodeAsOneByOne) {
  // encodeColors (a mesh's vertex colours at commit) gives each RGB channel fastLinearToSrgb's
  // bits, alpha ignored, for counts whose channels fill eight lanes or leave a tail; the output
  // is resized to the input, also when it shrinks.
  std::vector<glm::vec4> colours;
  for (int k = 0; k < 40; ++k)
    colours.push_back({static_cast<float>(k) * 0.031f - 0.2f, static_cast<float>(k * k % 17) * 0.07f,
                       k % 5 == 0 ? std::nanf("") : 1.0f / static_cast<float>(k + 1), -7.0f});
  colours[3] = {std::numeric_limits<float>::infinity(), -0.0f, 1.0f, 0.0f};
  const auto same = [](float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; };
  std::vector<glm::vec3> display(100, glm::vec3(9.0f));
  for (const size_t count : {size_t{40}, size_t{0}, size_t{1}, size_t{2}, size_t{3}, size_t{5}, size_t{8}, size_t{11}}) {
    encodeColors(std::span<const glm::vec4>(colours.data(), count), display);
    ASSERT_EQ(display.size(), count);
    for (size_t i = 0; i < count; ++i)
      for (int c = 0; c < 3; ++c)
        ASSERT_TRUE(same(display[i][c], fastLinearToSrgb(colours[i][c]))) << "colour " << i << " channel " << c;
  }
}

TEST(DisplayComposite, TableDecodeMatchesTheExactCurve) {
  // Every 64th float in [0, 1] against the powf curve; decodeColour decodes each channel alike.
  float worst = 0.0f;
  uint32_t one;
  const float oneF = 1.0f;
  std::memcpy(&one, &oneF, sizeof one);
  for (uint32_t bits = 0; bits <= one; bits += 64) {
    float c;
    std::memcpy(&c, &bits, sizeof c);
    worst = std::max(worst, std::abs(tableSrgbToLinear(c) - srgbToLinear(c)));
  }
  std::printf("largest difference: table decode %.3g\n", worst);
  EXPECT_LT(worst, 6e-7f);   // measured 4.8e-7: interpolation error 3.9e-7 at 1024 steps, plus rounding
  EXPECT_EQ(tableSrgbToLinear(0.0f), 0.0f);
  EXPECT_EQ(tableSrgbToLinear(-3.0f), 0.0f);   // clamped to [0, 1]
  EXPECT_NEAR(tableSrgbToLinear(7.0f), 1.0f, 1e-7f);
  EXPECT_EQ(decodeColour(glm::vec3(0.2f, 0.5f, 0.9f)),
            glm::vec3(tableSrgbToLinear(0.2f), tableSrgbToLinear(0.5f), tableSrgbToLinear(0.9f)));
  EXPECT_EQ(decodeColour(glm::vec3(1.0f, 0.0f, 0.04f)),
            glm::vec3(tableSrgbToLinear(1.0f), 0.0f, tableSrgbToLinear(0.04f)));
  EXPECT_EQ(decodeColour(glm::vec3(std::nanf(""))), glm::vec3(0.0f));   // NaN becomes 0
  EXPECT_EQ(decodeColour(glm::vec3(-1.0f)), glm::vec3(0.0f));
}

TEST(DisplayComposite, ProductOfDisplayValues) {
  // Texture 0.3 x lightmap 0.1 in 8-bit values is 0.03; the linear product would display 0.0094.
  const glm::vec3 p = displayProduct(linear(0.3f), linear(0.1f));
  EXPECT_NEAR(linearToSrgb(p.x), 0.03f, 1e-5f);
  EXPECT_NEAR(linearToSrgb(displayProduct(glm::vec3(1.0f), linear(0.6f)).y), 0.6f, 1e-5f);
}

TEST(DisplayComposite, AnOverbrightProductClampsAtWhiteWhenDecoded) {
  // The compositor doubles texture x light in display values per overbright bit, then decodes:
  // 0.3 x 0.5 = 0.15 doubled shows 0.3; 0.8 x 0.9 = 0.72 doubled clamps at white.
  const glm::vec3 doubled = decodeColour(glm::vec3(0.15f * 2.0f)), clamped = decodeColour(glm::vec3(0.72f * 2.0f));
  EXPECT_NEAR(linearToSrgb(doubled.x), 0.3f, 1e-5f);
  EXPECT_NEAR(clamped.x, 1.0f, 1e-6f);
}

TEST(DisplayComposite, NoLayersLeaveTheColourAlone) {
  const DisplayComposite none;
  EXPECT_EQ(none.over(glm::vec3(0.25f, 2.0f, 0.0f)), glm::vec3(0.25f, 2.0f, 0.0f));
}

TEST(DisplayComposite, AdditiveLayersAddDisplayValues) {
  // Two additive layers of display 0.5 over black: stock framebuffer blending gives 1.0 (white);
  // summing linear radiance would give linear 0.43, displayed 0.69.
  DisplayComposite c;
  c.appendBefore(hits({{1.0f, {linear(0.5f), glm::vec3(1.0f)}}, {2.0f, {linear(0.5f), glm::vec3(1.0f)}}}), 10.0f);
  EXPECT_EQ(c.size(), 2u);
  EXPECT_NEAR(c.over(glm::vec3(0.0f)).x, 1.0f, 1e-5f);
  // 0.25 + 0.25 over display 0.25 -> 0.75.
  DisplayComposite d;
  d.appendBefore(hits({{1.0f, {linear(0.25f), glm::vec3(1.0f)}}, {2.0f, {linear(0.25f), glm::vec3(1.0f)}}}), 10.0f);
  EXPECT_NEAR(linearToSrgb(d.over(linear(0.25f)).x), 0.75f, 1e-5f);
}

TEST(DisplayComposite, DisplayValueHitsAreAddedAsTheyAre) {
  // Hits worked out in display values (the Lightmap preset's) compose as the same layers given
  // in linear values: 0.25 + 0.25 over display 0.25 -> 0.75.
  AdditiveHits shown = hits({{1.0f, {glm::vec3(0.25f), glm::vec3(1.0f)}}, {2.0f, {glm::vec3(0.25f), glm::vec3(1.0f)}}});
  shown.displayValues = true;
  DisplayComposite c;
  c.appendBefore(shown, 10.0f);
  EXPECT_NEAR(linearToSrgb(c.over(linear(0.25f)).x), 0.75f, 1e-5f);
  DisplayComposite d;
  d.appendBefore(hits({{1.0f, {linear(0.25f), glm::vec3(1.0f)}}, {2.0f, {linear(0.25f), glm::vec3(1.0f)}}}), 10.0f);
  EXPECT_NEAR(c.over(linear(0.25f)).x, d.over(linear(0.25f)).x, 1e-6f);
}

TEST(DisplayComposite, PremultipliedLayersHideWhatIsBehindInOrder) {
  // Behind 0.8; the far layer (t = 3) covers half with 0.1, the near one (t = 1) adds 0.2:
  // (0.8 * 0.5 + 0.1) + 0.2 = 0.7. The other order gives (0.8 + 0.2) * 0.5 + 0.1 = 0.6.
  DisplayComposite c;
  c.appendBefore(hits({{1.0f, {linear(0.2f), glm::vec3(1.0f)}}, {3.0f, {linear(0.1f), glm::vec3(0.5f)}}}), 10.0f);
  EXPECT_NEAR(linearToSrgb(c.over(linear(0.8f)).x), 0.7f, 1e-5f);
  DisplayComposite swapped;
  swapped.appendBefore(hits({{3.0f, {linear(0.2f), glm::vec3(1.0f)}}, {1.0f, {linear(0.1f), glm::vec3(0.5f)}}}), 10.0f);
  EXPECT_NEAR(linearToSrgb(swapped.over(linear(0.8f)).x), 0.6f, 1e-5f);
}

TEST(DisplayComposite, LayersBehindTheSurfaceAndOverflowAreLeftOut) {
  DisplayComposite c;
  c.appendBefore(hits({{5.0f, {linear(0.5f), glm::vec3(1.0f)}}, {1.0f, {linear(0.25f), glm::vec3(1.0f)}}}), 4.0f);
  ASSERT_EQ(c.size(), 1u);
  EXPECT_NEAR(linearToSrgb(c.over(glm::vec3(0.0f)).x), 0.25f, 1e-5f);
  DisplayComposite full;
  for (uint32_t i = 0; i < DisplayComposite::kCapacity + 5; ++i) full.append({glm::vec3(0.0f), glm::vec3(1.0f)});
  EXPECT_EQ(full.size(), DisplayComposite::kCapacity);
}

TEST(DisplayComposite, EachBlendClampsLikeAnEightBitFramebuffer) {
  // White + 0.5 clamps to 1 before the near layer hides half: 1 * 0.5 + 0 = 0.5 (not 0.75).
  DisplayComposite c;
  c.append({glm::vec3(0.0f), glm::vec3(0.5f)});
  c.append({linear(0.5f), glm::vec3(1.0f)});
  EXPECT_NEAR(linearToSrgb(c.over(glm::vec3(1.0f)).x), 0.5f, 1e-5f);
}

TEST(DisplayComposite, MultiplyingLayersScaleWhatIsBehindPerChannel) {
  // A filter (dst * src) and the stock dynamic-light pass (dst * (1 + src)) over display 0.4.
  DisplayComposite c;
  c.append({glm::vec3(0.0f), glm::vec3(1.5f, 1.0f, 3.0f)});   // near: dst * (1 + (0.5, 0, 2))
  c.append({glm::vec3(0.0f), glm::vec3(0.5f, 0.25f, 1.0f)});  // far: dst * src
  const glm::vec3 out = c.over(linear(0.4f));
  EXPECT_NEAR(linearToSrgb(out.x), 0.4f * 0.5f * 1.5f, 1e-5f);
  EXPECT_NEAR(linearToSrgb(out.y), 0.4f * 0.25f, 1e-5f);
  EXPECT_NEAR(linearToSrgb(out.z), 1.0f, 1e-5f);   // 0.4 * 3 clamps
}

TEST(ComposeShine, AddedShineAddsDisplayValues) {
  // Base 0.4 + chrome 0.3 (blendfunc add) = 0.7 in display values; white + anything stays white.
  const glm::vec3 c = composeShine(linear(0.4f), glm::vec4(linear(0.3f), 1.0f), LayerBlend::Add, 0.0f);
  EXPECT_NEAR(linearToSrgb(c.x), 0.7f, 1e-5f);
  const glm::vec3 white = composeShine(glm::vec3(1.0f), glm::vec4(linear(0.3f), 1.0f), LayerBlend::Add, 0.0f);
  EXPECT_NEAR(white.x, 1.0f, 1e-6f);
}

TEST(ComposeShine, FilterShinesFollowTheStockBlendEquations) {
  const glm::vec4 src(linear(0.3f).x, linear(0.75f).x, linear(0.5f).x, 1.0f);
  // gl_dst_color gl_src_color: dst src + src dst = 2 dst src (0.5 keeps the base).
  const glm::vec3 m = composeShine(linear(0.4f), src, LayerBlend::Modulate2x, 0.0f);
  EXPECT_NEAR(linearToSrgb(m.x), 2.0f * 0.4f * 0.3f, 1e-5f);
  EXPECT_NEAR(linearToSrgb(m.y), 2.0f * 0.4f * 0.75f, 1e-5f);
  EXPECT_NEAR(linearToSrgb(m.z), 0.4f, 1e-5f);
  // Brightening past white clamps: 2 x 0.8 x 0.75 = 1.2 -> 1.
  EXPECT_NEAR(composeShine(linear(0.8f), src, LayerBlend::Modulate2x, 0.0f).y, 1.0f, 1e-6f);
  // gl_dst_color gl_dst_alpha over an opaque base (alpha 1): dst src + dst = dst (1 + src).
  const glm::vec3 a = composeShine(linear(0.4f), src, LayerBlend::MultiplyAdd, 0.0f);
  EXPECT_NEAR(linearToSrgb(a.x), 0.4f * 1.3f, 1e-5f);
}

TEST(ComposeShine, RedrawnBaseHidesTheShineByItsAlpha) {
  // Base, shine added, base again blended with alpha 0.75: 0.4 * 0.75 + (0.4 + 0.3) * 0.25.
  const glm::vec3 c = composeShine(linear(0.4f), glm::vec4(linear(0.3f), 1.0f), LayerBlend::Add, 0.75f);
  EXPECT_NEAR(linearToSrgb(c.x), 0.4f + 0.25f * 0.3f, 1e-5f);
  // Fully opaque paint: no shine at all.
  EXPECT_NEAR(linearToSrgb(composeShine(linear(0.4f), glm::vec4(1.0f), LayerBlend::Add, 1.0f).x), 0.4f, 1e-5f);
}

}  // namespace
}  // namespace pa
