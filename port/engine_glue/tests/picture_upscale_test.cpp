// The picture's copy into the window: RGBA -> BGRA, and the 2x bilinear stretch against GL's
// filter (texel centres at half-integers, edges clamped), value for value.
#include "port/engine_glue/picture_upscale.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

namespace {

constexpr int kBgraFromRgba[4] = {2, 1, 0, 3};   // BGRA byte d holds RGBA channel kBgraFromRgba[d]

// GL's bilinear filter of an RGBA8 texture drawn over (2w x 2h) window pixels, channel c of
// window pixel (x, y) (rows top first), rounded half up.
uint8_t glBilinear(const std::vector<uint8_t>& rgba, int w, int h, int x, int y, int c) {
  const double u = (x + 0.5) * w / (2.0 * w) - 0.5;
  const double v = (y + 0.5) * h / (2.0 * h) - 0.5;
  const int x0 = static_cast<int>(std::floor(u)), y0 = static_cast<int>(std::floor(v));
  const double fx = u - x0, fy = v - y0;
  const auto at = [&](int tx, int ty) {
    tx = std::clamp(tx, 0, w - 1);
    ty = std::clamp(ty, 0, h - 1);
    return static_cast<double>(rgba[(size_t(ty) * size_t(w) + size_t(tx)) * 4 + size_t(c)]);
  };
  const double value = (1 - fx) * (1 - fy) * at(x0, y0) + fx * (1 - fy) * at(x0 + 1, y0) +
                       (1 - fx) * fy * at(x0, y0 + 1) + fx * fy * at(x0 + 1, y0 + 1);
  return static_cast<uint8_t>(std::floor(value + 0.5));
}

std::vector<uint8_t> upscaled(const std::vector<uint8_t>& rgba, int w, int h) {
  std::vector<uint8_t> out(size_t(w) * size_t(h) * 16, 0xCD);
  std::vector<uint16_t> scratch;
  glue::upscale2xRgbaToBgra(rgba.data(), w, h, out.data(), scratch);
  return out;
}

// Every output value equals GL's filter; returns the number of values compared.
size_t expectMatchesGl(const std::vector<uint8_t>& rgba, int w, int h) {
  const std::vector<uint8_t> out = upscaled(rgba, w, h);
  size_t compared = 0;
  for (int y = 0; y < 2 * h; ++y)
    for (int x = 0; x < 2 * w; ++x)
      for (int d = 0; d < 4; ++d) {
        const uint8_t got = out[(size_t(y) * size_t(2 * w) + size_t(x)) * 4 + size_t(d)];
        const uint8_t want = glBilinear(rgba, w, h, x, y, kBgraFromRgba[d]);
        if (got != want) {
          ADD_FAILURE() << w << "x" << h << " pixel (" << x << ", " << y << ") byte " << d << ": " << int(got)
                        << ", GL " << int(want);
          return compared;
        }
        ++compared;
      }
  return compared;
}

std::vector<uint8_t> randomImage(int w, int h, unsigned seed) {
  std::mt19937 random(seed);
  std::vector<uint8_t> rgba(size_t(w) * size_t(h) * 4);
  for (uint8_t& value : rgba) value = static_cast<uint8_t>(random() & 0xFF);
  return rgba;
}

TEST(PictureUpscale, ConstantImageStaysConstant) {
  const int w = 9, h = 5;
  std::vector<uint8_t> rgba(size_t(w) * h * 4);
  for (size_t i = 0; i < rgba.size(); i += 4) {
    rgba[i] = 10;
    rgba[i + 1] = 200;
    rgba[i + 2] = 255;
    rgba[i + 3] = 255;
  }
  const std::vector<uint8_t> out = upscaled(rgba, w, h);
  for (size_t i = 0; i < out.size(); i += 4) {
    ASSERT_EQ(out[i], 255) << i;
    ASSERT_EQ(out[i + 1], 200) << i;
    ASSERT_EQ(out[i + 2], 10) << i;
    ASSERT_EQ(out[i + 3], 255) << i;
  }
}

TEST(PictureUpscale, RampTakesQuarterSteps) {
  // A horizontal ramp 0, 12, 24, ...: window pixel X samples at texel X / 2 - 1/4, so inside
  // the edges the stretch is the ramp 6 X - 3, and the outermost pixels repeat the edge texels.
  const int w = 20, h = 3;
  std::vector<uint8_t> rgba(size_t(w) * h * 4);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 4; ++c) rgba[(size_t(y) * w + x) * 4 + c] = static_cast<uint8_t>(12 * x);
  const std::vector<uint8_t> out = upscaled(rgba, w, h);
  for (int y = 0; y < 2 * h; ++y) {
    const uint8_t* row = &out[size_t(y) * 2 * w * 4];
    EXPECT_EQ(row[0], 0);
    EXPECT_EQ(row[4 * (2 * w - 1)], 12 * (w - 1));
    for (int x = 1; x < 2 * w - 1; ++x)
      for (int d = 0; d < 4; ++d) EXPECT_EQ(row[4 * x + d], 6 * x - 3) << "x " << x;
  }
  EXPECT_EQ(expectMatchesGl(rgba, w, h), size_t(w) * h * 16);
}

TEST(PictureUpscale, MatchesGlFilterOnRandomImagesOfOddSizes) {
  // Widths below, at and past the 2-pixel SIMD step and the 4-pixel vertical step, odd ones
  // leaving a tail; heights down to one row (both neighbours clamp to it).
  const int sizes[][2] = {{1, 1}, {1, 4}, {2, 1}, {3, 3}, {4, 2}, {5, 7}, {7, 1}, {17, 9}, {33, 4}, {320, 3}};
  unsigned seed = 1;
  for (const auto& size : sizes) {
    SCOPED_TRACE(testing::Message() << size[0] << "x" << size[1]);
    const std::vector<uint8_t> rgba = randomImage(size[0], size[1], seed++);
    EXPECT_EQ(expectMatchesGl(rgba, size[0], size[1]), size_t(size[0]) * size[1] * 16);
  }
}

TEST(PictureUpscale, EdgeTexelsExtremes) {
  // Alternating 0 / 255 texels: the largest differences between neighbours, no overflow.
  const int w = 6, h = 4;
  std::vector<uint8_t> rgba(size_t(w) * h * 4);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 4; ++c) rgba[(size_t(y) * w + x) * 4 + c] = ((x + y + c) % 2) != 0 ? 255 : 0;
  EXPECT_EQ(expectMatchesGl(rgba, w, h), size_t(w) * h * 16);
}

TEST(PictureUpscale, ScratchIsReusedAcrossSizes) {
  std::vector<uint16_t> scratch;
  const std::vector<uint8_t> big = randomImage(40, 2, 7), small = randomImage(3, 3, 8);
  std::vector<uint8_t> out(40 * 2 * 16);
  glue::upscale2xRgbaToBgra(big.data(), 40, 2, out.data(), scratch);
  const size_t capacity = scratch.size();
  glue::upscale2xRgbaToBgra(small.data(), 3, 3, out.data(), scratch);
  EXPECT_EQ(scratch.size(), capacity);
  EXPECT_EQ(expectMatchesGl(small, 3, 3), 3u * 3 * 16);
}

TEST(PictureUpscale, SameSizeCopySwapsRedAndBlue) {
  for (const int count : {1, 3, 4, 5, 17}) {   // pixels: under, at and past a 4-pixel step
    const std::vector<uint8_t> rgba = randomImage(count, 1, 20u + unsigned(count));
    std::vector<uint8_t> bgra(rgba.size(), 0xCD);
    glue::copyRgbaToBgra(rgba.data(), count, 1, bgra.data());
    for (size_t i = 0; i < rgba.size(); i += 4)
      for (int d = 0; d < 4; ++d) ASSERT_EQ(bgra[i + d], rgba[i + kBgraFromRgba[d]]) << count << " " << i;
  }
  const std::vector<uint8_t> rgba = randomImage(7, 3, 99);
  std::vector<uint8_t> bgra(rgba.size());
  glue::copyRgbaToBgra(rgba.data(), 7, 3, bgra.data());
  for (size_t i = 0; i < rgba.size(); i += 4)
    for (int d = 0; d < 4; ++d) ASSERT_EQ(bgra[i + d], rgba[i + kBgraFromRgba[d]]) << i;
}

}  // namespace
