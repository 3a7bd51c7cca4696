// Texture decoding, mip chain, filtering and addressing.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "renderer/scene/textures/texture.h"
#include "scene_builders.h"

namespace pa {
namespace {

/// A 4x2 checker of black and white texels (linear data), mipmapped, repeating.
Texture checker4x2() {
  std::vector<uint8_t> px;
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 4; ++x) {
      const uint8_t v = ((x + y) % 2) ? 255 : 0;
      px.insert(px.end(), {v, v, v, 255});
    }
  return Texture::fromDesc({4, 2, px, false}, "checker");
}

TEST(Texture, SrgbDecodeAndLinearData) {
  const std::vector<uint8_t> px = test::solidPixels(1, 1, 128, 255, 0, 64);
  TextureDesc d{1, 1, px};
  const Texture srgb = Texture::fromDesc(d, "t");
  EXPECT_NEAR(srgb.sampleFull({0.5f, 0.5f}).r, 0.2158605f, 1e-5f);   // sRGB 128 -> 0.2159
  EXPECT_NEAR(srgb.sampleFull({0.5f, 0.5f}).g, 1.0f, 1e-6f);
  EXPECT_NEAR(srgb.sampleFull({0.5f, 0.5f}).a, 64.0f / 255.0f, 1e-6f);   // alpha stays linear
  d.srgb = false;
  EXPECT_NEAR(Texture::fromDesc(d, "t").sampleFull({0.5f, 0.5f}).r, 128.0f / 255.0f, 1e-6f);
  EXPECT_NEAR(linearToSrgb(srgbToLinear(0.3f)), 0.3f, 1e-6f);
}

TEST(Texture, MipChainAveragesAndFinerLevelsKeepDetail) {
  // Every coarser level of the checker is 0.5 grey, stored as the nearest byte (127 or 128:
  // within half a byte step).
  const Texture t = checker4x2();
  ASSERT_EQ(t.levelCount(), 3u);   // 4x2, 2x1, 1x1
  EXPECT_EQ(t.level(1).width, 2u);
  EXPECT_EQ(t.level(1).height, 1u);
  constexpr float kHalfByte = 0.5f / 255.0f;
  EXPECT_NEAR(t.texel(1, 0, 0).r, 0.5f, kHalfByte + 1e-6f);
  EXPECT_NEAR(t.average().r, 0.5f, 1e-6f);   // average() is taken before rounding to bytes
  // Texel centre at level 0 is exact; lod 2 gives the average.
  EXPECT_NEAR(t.sample({0.125f, 0.25f}, 0.0f).r, 0.0f, 1e-6f);
  EXPECT_NEAR(t.sample({0.375f, 0.25f}, 0.0f).r, 1.0f, 1e-6f);
  EXPECT_NEAR(t.sample({0.125f, 0.25f}, 2.0f).r, 0.5f, kHalfByte + 1e-6f);
  EXPECT_NEAR(t.sample({0.125f, 0.25f}, 0.5f).r, 0.25f, kHalfByte + 1e-6f);   // halfway between 0 and 0.5
}

TEST(Texture, CoarserSrgbLevelsKeepTheByteNearestTheLinearMean) {
  // 2x1 of sRGB 0 and 255: the linear mean 0.5 lies between the decoded bytes 187 (0.4969) and
  // 188 (0.5029), nearer 188.
  const std::vector<uint8_t> px{0, 0, 0, 255, 255, 255, 255, 255};
  const Texture t = Texture::fromDesc({2, 1, px}, "t");
  ASSERT_EQ(t.levelCount(), 2u);
  EXPECT_EQ(t.level(1).texels[0][0], 188);
  EXPECT_EQ(t.level(1).texels[0][3], 255);
  EXPECT_NEAR(t.texel(1, 0, 0).r, srgbToLinear(188.0f / 255.0f), 1e-7f);
  EXPECT_NEAR(t.average().r, 0.5f, 1e-6f);
}

TEST(Texture, StoredLookupsFilterTheBytesAsStored) {
  // 2x1 sRGB, black and white, clamped: halfway between the texel centres the stored values
  // blend to 0.5 (a raster texture unit's 8-bit blend), the linear ones to 0.5 linear.
  const std::vector<uint8_t> px{0, 0, 0, 0, 255, 255, 255, 255};
  const Texture t = Texture::fromDesc({2, 1, px, true, TextureWrap::Clamp, false}, "t");
  EXPECT_TRUE(t.srgb());
  EXPECT_NEAR(t.sampleStored({0.5f, 0.5f}, 0.0f).r, 0.5f, 1e-6f);
  EXPECT_NEAR(t.sampleStored({0.5f, 0.5f}, 0.0f).a, 0.5f, 1e-6f);
  EXPECT_NEAR(t.sample({0.5f, 0.5f}, 0.0f).r, 0.5f, 1e-6f);
  EXPECT_NEAR(t.sampleStored({0.75f, 0.5f}, 0.0f).g, 1.0f, 1e-6f);   // texel centre: its byte / 255
  const std::vector<uint8_t> grey{51, 102, 153, 204};
  EXPECT_NEAR(Texture::fromDesc({1, 1, grey}, "g").sampleStored({0.3f, 0.9f}, 0.0f).b, 0.6f, 1e-6f);
}

TEST(Texture, TextureUnitFiltersPickLevelsAndTexelsAsOpenGl) {
  // Levels 4x2 (the checker), 2x1 and 1x1 (grey).
  const Texture t = checker4x2();
  ASSERT_EQ(t.levelCount(), 3u);
  constexpr float kHalfByte = 0.5f / 255.0f + 1e-6f;
  const glm::vec2 black(0.125f, 0.25f);   // a black texel's centre at level 0
  const TextureFilter nearestMip{MipFilter::Nearest, false};
  EXPECT_NEAR(t.sample(black, 0.5f, nearestMip).r, 0.0f, 1e-6f);       // level 0 up to 0.5
  EXPECT_NEAR(t.sample(black, 0.6f, nearestMip).r, 0.5f, kHalfByte);   // then the nearest level: 1
  EXPECT_NEAR(t.sample(black, 1.5f, nearestMip).r, 0.5f, kHalfByte);   // 1.5 rounds down
  EXPECT_NEAR(t.sample(black, 1e30f, nearestMip).r, 0.5f, kHalfByte);  // the last level
  EXPECT_NEAR(t.sample(black, std::nanf(""), nearestMip).r, 0.0f, 1e-6f);
  EXPECT_NEAR(t.sample(black, 0.5f).r, 0.25f, kHalfByte);   // trilinear blends levels 0 and 1
  EXPECT_NEAR(t.sample(black, 2.0f, {MipFilter::None, false}).r, 0.0f, 1e-6f);   // level 0 only
  // Nearest texels: the texel the point falls in, where bilinear blends the neighbour in.
  const TextureFilter point{MipFilter::None, true};
  EXPECT_NEAR(t.sample({0.2f, 0.25f}, 0.0f).r, 0.3f, 1e-6f);
  EXPECT_NEAR(t.sample({0.2f, 0.25f}, 0.0f, point).r, 0.0f, 1e-6f);
  EXPECT_NEAR(t.sample({1.0f, 0.25f}, 0.0f, point).r, 0.0f, 1e-6f);    // repeat: wraps to texel 0
  EXPECT_NEAR(t.sample({-0.1f, 0.25f}, 0.0f, point).r, 1.0f, 1e-6f);   // -0.1 == 0.9: texel 3
  EXPECT_NEAR(t.sample({0.2f, 0.25f}, 0.5f, {MipFilter::Linear, true}).r, 0.25f, kHalfByte);
  EXPECT_NEAR(t.sampleStored({0.2f, 0.25f}, 0.0f, point).r, 0.0f, 1e-6f);
  // The default filter is sample() itself, bit for bit; sampleInto() is sample() with a filter.
  for (const float lod : {0.0f, 0.3f, 1.7f, 5.0f})
    EXPECT_EQ(t.sample({0.31f, 0.77f}, lod, TextureFilter{}), t.sample({0.31f, 0.77f}, lod));
  for (const TextureFilter filter : {TextureFilter{}, nearestMip, point, TextureFilter{MipFilter::Linear, true}})
    for (const float lod : {-1.0f, 0.0f, 0.3f, 0.6f, 1.7f, 5.0f, std::nanf("")}) {
      glm::vec4 into(-1.0f);
      t.sampleInto({0.31f, 0.77f}, lod, filter, into);
      EXPECT_EQ(into, t.sample({0.31f, 0.77f}, lod, filter));
    }
  // Clamped, without a mip chain: bilinear at level 0 whatever the filter (as stock reads images
  // without mipmaps), and the nearest texel at the edge when asked of a mip chain.
  const std::vector<uint8_t> pair{0, 0, 0, 255, 255, 255, 255, 255};
  const Texture plain = Texture::fromDesc({2, 1, pair, false, TextureWrap::Clamp, false}, "plain");
  EXPECT_NEAR(plain.sample({0.5f, 0.5f}, 3.0f, point).r, 0.5f, 1e-6f);
  const Texture clamped = Texture::fromDesc({2, 1, pair, false, TextureWrap::Clamp, true}, "clamped");
  EXPECT_NEAR(clamped.sample({5.0f, 0.5f}, 0.0f, point).r, 1.0f, 1e-6f);
  EXPECT_NEAR(clamped.sample({-5.0f, 0.5f}, 0.0f, point).r, 0.0f, 1e-6f);
}

TEST(Texture, BilinearRepeatWrapsAndClampHoldsTheEdge) {
  // 2x1: left black, right white.
  const std::vector<uint8_t> px{0, 0, 0, 255, 255, 255, 255, 255};
  TextureDesc d{2, 1, px, false, TextureWrap::Repeat, false};
  const Texture rep = Texture::fromDesc(d, "rep");
  EXPECT_NEAR(rep.sampleFull({0.0f, 0.5f}).r, 0.5f, 1e-6f);    // edge blends with the wrapped texel
  EXPECT_NEAR(rep.sampleFull({1.25f, 0.5f}).r, 0.0f, 1e-6f);   // 1.25 == 0.25: black texel centre
  EXPECT_NEAR(rep.sampleFull({-0.25f, 0.5f}).r, 1.0f, 1e-6f);  // -0.25 == 0.75: white texel centre
  d.wrap = TextureWrap::Clamp;
  const Texture clamp = Texture::fromDesc(d, "clamp");
  EXPECT_NEAR(clamp.sampleFull({0.0f, 0.5f}).r, 0.0f, 1e-6f);
  EXPECT_NEAR(clamp.sampleFull({5.0f, 0.5f}).r, 1.0f, 1e-6f);
  EXPECT_EQ(clamp.levelCount(), 1u);
  EXPECT_NEAR(clamp.average().r, 0.5f, 1e-6f);
}

TEST(Texture, BilinearLookupIsTheBlendOfItsFourTexels) {
  // A 5x3 sRGB texture of varied bytes, repeat: sampleFull at many points is the bilinear blend
  // of the four decoded texels around it, (b fx + a (1 - fx)) (1 - fy) + (d fx + c (1 - fx)) fy,
  // bit for bit where the blend is fused (FMA), within rounding elsewhere.
  std::vector<uint8_t> px;
  for (int i = 0; i < 5 * 3 * 4; ++i) px.push_back(uint8_t((i * 97 + 13) % 256));
  const Texture t = Texture::fromDesc({5, 3, px, true, TextureWrap::Repeat, false}, "t");
  for (int i = 0; i < 400; ++i) {
    const glm::vec2 uv(float((i * 37) % 400) / 400.0f + 0.0013f, float((i * 53) % 400) / 400.0f + 0.0007f);
#if defined(__FMA__)
    const float x = std::fma(uv.x, 5.0f, -0.5f), y = std::fma(uv.y, 3.0f, -0.5f);
#else
    const float x = uv.x * 5.0f - 0.5f, y = uv.y * 3.0f - 0.5f;
#endif
    const float fx = x - std::floor(x), fy = y - std::floor(y);
    const int x0 = (int(std::floor(x)) + 5) % 5, y0 = (int(std::floor(y)) + 3) % 3;
    const int x1 = (x0 + 1) % 5, y1 = (y0 + 1) % 3;
    const glm::vec4 got = t.sampleFull(uv);
    for (int c = 0; c < 4; ++c) {
      const float a = t.texel(0, x0, y0)[c], b = t.texel(0, x1, y0)[c];
      const float cc = t.texel(0, x0, y1)[c], d = t.texel(0, x1, y1)[c];
#if defined(__FMA__)
      const float top = std::fma(b, fx, a * (1.0f - fx)), bottom = std::fma(d, fx, cc * (1.0f - fx));
      EXPECT_EQ(got[c], std::fma(bottom, fy, top * (1.0f - fy))) << "uv " << uv.x << " " << uv.y << " channel " << c;
#else
      const float want = (a * (1.0f - fx) + b * fx) * (1.0f - fy) + (cc * (1.0f - fx) + d * fx) * fy;
      EXPECT_NEAR(got[c], want, 1e-6f) << "uv " << uv.x << " " << uv.y << " channel " << c;
#endif
    }
  }
}

TEST(Texture, NonFiniteCoordinatesAreSafe) {
  const std::vector<uint8_t> px = test::solidPixels(2, 2, 10, 20, 30, 255);
  const Texture t = Texture::fromDesc({2, 2, px}, "t");
  EXPECT_TRUE(std::isfinite(t.sample({std::nanf(""), 1e30f}, std::nanf("")).r));
  EXPECT_TRUE(std::isfinite(t.sample({-1e30f, INFINITY}, 100.0f).r));
}

TEST(Texture, InvalidDescriptionsThrowWithTheReason) {
  const std::vector<uint8_t> px = test::solidPixels(2, 2, 0, 0, 0, 0);
  EXPECT_THROW(Texture::fromDesc({0, 2, px}, "t"), SceneError);
  EXPECT_THROW(Texture::fromDesc({3, 2, px}, "t"), SceneError);   // size mismatch
  EXPECT_THROW(Texture::fromDesc({kMaxTextureSize + 1, 1, px}, "t"), SceneError);
  try {
    Texture::fromDesc({3, 2, px}, "tex 7");
    FAIL();
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("tex 7"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("rgba8"), std::string::npos);
  }
}

}  // namespace
}  // namespace pa
