#include "port/q3formats/image/image.h"

#include <gtest/gtest.h>
#include <stb_image_write.h>

#include "port/q3formats/common/format_error.h"

namespace {

using Bytes = std::vector<std::byte>;

/// An 18-byte TGA header.
Bytes tgaHeader(uint8_t type, uint16_t w, uint16_t h, uint8_t bpp, uint8_t descriptor,
                uint8_t colorMapType = 0, uint16_t mapLength = 0, uint8_t mapEntryBits = 0) {
  Bytes b(18, std::byte{0});
  b[1] = std::byte{colorMapType};
  b[2] = std::byte{type};
  b[5] = std::byte(mapLength & 0xFF);
  b[6] = std::byte(mapLength >> 8);
  b[7] = std::byte{mapEntryBits};
  b[12] = std::byte(w & 0xFF);
  b[13] = std::byte(w >> 8);
  b[14] = std::byte(h & 0xFF);
  b[15] = std::byte(h >> 8);
  b[16] = std::byte{bpp};
  b[17] = std::byte{descriptor};
  return b;
}

void put(Bytes& b, std::initializer_list<int> values) {
  for (int v : values) b.push_back(std::byte(v));
}

using Rgba = std::array<uint8_t, 4>;

TEST(Image, Tga24BottomUpIsFlippedToTopRowFirst) {
  // 2x2, bottom-left origin (descriptor 0): file rows are bottom row first; pixels are BGR.
  Bytes b = tgaHeader(2, 2, 2, 24, 0);
  put(b, {0, 0, 255, /**/ 0, 255, 0});    // bottom row: red, green
  put(b, {255, 0, 0, /**/ 255, 255, 255});  // top row: blue, white
  q3::Image img = q3::decodeImage(b, "a.tga");
  ASSERT_EQ(img.width, 2);
  ASSERT_EQ(img.height, 2);
  EXPECT_EQ(img.pixel(0, 0), (Rgba{0, 0, 255, 255}));
  EXPECT_EQ(img.pixel(1, 0), (Rgba{255, 255, 255, 255}));
  EXPECT_EQ(img.pixel(0, 1), (Rgba{255, 0, 0, 255}));
  EXPECT_EQ(img.pixel(1, 1), (Rgba{0, 255, 0, 255}));
}

TEST(Image, Tga32TopDownKeepsRowsAndAlpha) {
  Bytes b = tgaHeader(2, 2, 2, 32, 0x28);  // top-left origin, 8 alpha bits
  put(b, {0, 0, 255, 10, /**/ 0, 255, 0, 20});
  put(b, {255, 0, 0, 30, /**/ 1, 2, 3, 40});
  q3::Image img = q3::decodeImage(b, "b.tga");
  EXPECT_EQ(img.pixel(0, 0), (Rgba{255, 0, 0, 10}));
  EXPECT_EQ(img.pixel(1, 0), (Rgba{0, 255, 0, 20}));
  EXPECT_EQ(img.pixel(0, 1), (Rgba{0, 0, 255, 30}));
  EXPECT_EQ(img.pixel(1, 1), (Rgba{3, 2, 1, 40}));
}

TEST(Image, TgaRunLengthEncoded24And32) {
  // 3x2 RLE, bottom-up. Bottom row: run of 3 red. Top row: raw packet of 2 then a run of 1.
  Bytes b = tgaHeader(10, 3, 2, 24, 0);
  put(b, {0x82, 0, 0, 255});
  put(b, {0x01, 255, 0, 0, 0, 255, 0, /**/ 0x80, 9, 8, 7});
  q3::Image img = q3::decodeImage(b, "rle.tga");
  EXPECT_EQ(img.pixel(0, 1), (Rgba{255, 0, 0, 255}));
  EXPECT_EQ(img.pixel(2, 1), (Rgba{255, 0, 0, 255}));
  EXPECT_EQ(img.pixel(0, 0), (Rgba{0, 0, 255, 255}));
  EXPECT_EQ(img.pixel(1, 0), (Rgba{0, 255, 0, 255}));
  EXPECT_EQ(img.pixel(2, 0), (Rgba{7, 8, 9, 255}));

  // A run that crosses a row boundary (the encoder is allowed to do that), top-down, 32 bit.
  Bytes c = tgaHeader(10, 2, 2, 32, 0x28);
  put(c, {0x82, 10, 20, 30, 128, /**/ 0x00, 1, 2, 3, 4});
  q3::Image img2 = q3::decodeImage(c, "rle32.tga");
  EXPECT_EQ(img2.pixel(0, 0), (Rgba{30, 20, 10, 128}));
  EXPECT_EQ(img2.pixel(0, 1), (Rgba{30, 20, 10, 128}));
  EXPECT_EQ(img2.pixel(1, 1), (Rgba{3, 2, 1, 4}));
}

TEST(Image, TgaGreyscaleRawAndRle) {
  Bytes g = tgaHeader(3, 2, 1, 8, 0);
  put(g, {0, 200});
  q3::Image img = q3::decodeImage(g, "g.tga");
  EXPECT_EQ(img.pixel(1, 0), (Rgba{200, 200, 200, 255}));
  Bytes r = tgaHeader(11, 3, 1, 8, 0);
  put(r, {0x82, 77});
  EXPECT_EQ(q3::decodeImage(r, "g_rle.tga").pixel(2, 0), (Rgba{77, 77, 77, 255}));
}

TEST(Image, Tga16BitExpandsFiveBitChannels) {
  Bytes b = tgaHeader(2, 1, 1, 16, 0);
  // A1R5G5B5 little-endian: R=31, G=0, B=15 -> 0b0_11111_00000_01111 = 0x7C0F.
  put(b, {0x0F, 0x7C});
  q3::Image img = q3::decodeImage(b, "c16.tga");
  EXPECT_EQ(img.pixel(0, 0)[0], 255);
  EXPECT_EQ(img.pixel(0, 0)[1], 0);
  EXPECT_NEAR(img.pixel(0, 0)[2], 123, 1);  // 15 * 255 / 31
}

TEST(Image, TgaColorMapped) {
  Bytes b = tgaHeader(1, 2, 1, 8, 0x20, 1, 2, 24);
  put(b, {0, 0, 255, /**/ 255, 0, 0});  // palette: red, blue (BGR)
  put(b, {1, 0});
  q3::Image img = q3::decodeImage(b, "pal.tga");
  EXPECT_EQ(img.pixel(0, 0), (Rgba{0, 0, 255, 255}));
  EXPECT_EQ(img.pixel(1, 0), (Rgba{255, 0, 0, 255}));
}

void appendToVector(void* context, void* data, int size) {
  auto* out = static_cast<Bytes*>(context);
  auto* p = static_cast<const std::byte*>(data);
  out->insert(out->end(), p, p + size);
}

TEST(Image, PngAndJpgRoundTrip) {
  const uint8_t pixels[2 * 2 * 4] = {255, 0, 0, 255, 0, 255, 0, 128, 0, 0, 255, 0, 255, 255, 255, 255};
  Bytes png;
  ASSERT_TRUE(stbi_write_png_to_func(appendToVector, &png, 2, 2, 4, pixels, 8));
  q3::Image p = q3::decodeImage(png, "x.png");
  EXPECT_EQ(p.pixel(1, 0), (Rgba{0, 255, 0, 128}));
  EXPECT_EQ(p.pixel(0, 1), (Rgba{0, 0, 255, 0}));

  std::vector<uint8_t> grey(16 * 16 * 3, 100);
  Bytes jpg;
  ASSERT_TRUE(stbi_write_jpg_to_func(appendToVector, &jpg, 16, 16, 3, grey.data(), 95));
  q3::Image j = q3::decodeImage(jpg, "x.jpg");
  EXPECT_EQ(j.width, 16);
  EXPECT_NEAR(j.pixel(5, 5)[0], 100, 2);
  EXPECT_EQ(j.pixel(5, 5)[3], 255);
}

TEST(Image, RefusesOversizeBeforeDecoding) {
  // Header claims 9000x1 but carries no pixels: refused on the size check, not in the decoder.
  Bytes b = tgaHeader(2, 9000, 1, 24, 0);
  try {
    q3::decodeImage(b, "huge.tga");
    FAIL();
  } catch (const q3::FormatError& e) {
    EXPECT_EQ(e.field(), "image size");
    EXPECT_EQ(e.file(), "huge.tga");
  }
  EXPECT_EQ(q3::imageSize(b, "huge.tga"), (std::array<int, 2>{9000, 1}));
}

TEST(Image, MalformedInputsThrow) {
  EXPECT_THROW(q3::decodeImage({}, "empty.tga"), q3::FormatError);
  Bytes junk(64, std::byte{0x5A});
  EXPECT_THROW(q3::decodeImage(junk, "junk.jpg"), q3::FormatError);
  Bytes truncated = tgaHeader(2, 4, 4, 32, 0);
  put(truncated, {1, 2, 3});
  EXPECT_THROW(q3::decodeImage(truncated, "short.tga"), q3::FormatError);
  // A 45-byte RLE TGA claiming 6168x6168 (found by the fuzzer): refused, not zero-filled.
  Bytes bomb = tgaHeader(10, 6168, 6168, 8, 0);
  put(bomb, {0x80, 1, 0x80, 2});
  try {
    q3::decodeImage(bomb, "bomb.tga");
    FAIL() << "accepted";
  } catch (const q3::FormatError& e) {
    EXPECT_EQ(e.field(), "TGA pixel data");
  }
  Bytes badRle = tgaHeader(10, 4, 4, 24, 0);
  put(badRle, {0xFF, 1, 2, 3});  // run of 128 for a 16-pixel image, then EOF
  EXPECT_NO_FATAL_FAILURE({
    try {
      q3::decodeImage(badRle, "bad_rle.tga");
    } catch (const q3::FormatError&) {
    }
  });
}

TEST(Image, FallbackIsAMagentaBlackChecker) {
  q3::Image f = q3::fallbackImage(16, 2);
  ASSERT_EQ(f.rgba.size(), 16u * 16u * 4u);
  EXPECT_EQ(f.pixel(0, 0), (Rgba{255, 0, 255, 255}));
  EXPECT_EQ(f.pixel(8, 0), (Rgba{0, 0, 0, 255}));
  EXPECT_EQ(f.pixel(8, 8), (Rgba{255, 0, 255, 255}));
  auto mean = q3::averageColor(f);
  EXPECT_NEAR(mean[0], 0.5f, 1e-6);
  EXPECT_NEAR(mean[1], 0.0f, 1e-6);
  EXPECT_NEAR(mean[3], 1.0f, 1e-6);
}

}  // namespace

namespace {
TEST(Image, RefusesJpegHuffmanTablesWithMoreThan256Codes) {
  // stb_image 2.27 wrote past its Huffman tables for these (found by q3_fuzz_image); libjpeg
  // refuses them.
  Bytes b;
  put(b, {0xFF, 0xD8});                                                  // SOI
  put(b, {0xFF, 0xC0, 0x00, 0x0B, 8, 0x00, 0x08, 0x00, 0x08, 1, 1, 0x11, 0});  // SOF0 8x8 grey
  const int codes = 16 * 20;
  const int length = 2 + 17 + codes;
  put(b, {0xFF, 0xC4, length >> 8, length & 0xFF, 0x00});  // DHT, DC table 0
  for (int i = 0; i < 16; ++i) put(b, {20});
  for (int i = 0; i < codes; ++i) put(b, {i & 0xFF});
  put(b, {0xFF, 0xD9});  // EOI
  try {
    q3::decodeImage(b, "evil.jpg");
    FAIL() << "accepted";
  } catch (const q3::FormatError& e) {
    EXPECT_EQ(e.field(), "JPEG header");
    EXPECT_NE(std::string(e.what()).find("Huffman"), std::string::npos) << e.what();
  }
  // The header-only size query parses the tables too (a DHT before SOF), so it checks as well.
  Bytes early;
  put(early, {0xFF, 0xD8});
  put(early, {0xFF, 0xC4, length >> 8, length & 0xFF, 0x00});
  for (int i = 0; i < 16; ++i) put(early, {20});
  for (int i = 0; i < codes; ++i) put(early, {i & 0xFF});
  EXPECT_THROW(q3::imageSize(early, "early.jpg"), q3::FormatError);
  // A table header cut off by the end of the file (stb read the missing counts as zeros but
  // still used the ones present: third fuzz finding).
  Bytes cut;
  put(cut, {0xFF, 0xD8, 0xFF, 0xC4, 0x01, 0x00, 0x00});
  for (int i = 0; i < 5; ++i) put(cut, {255});
  EXPECT_THROW(q3::imageSize(cut, "cut.jpg"), q3::FormatError);
}
}  // namespace

namespace {
TEST(Image, RefusesFormatsTheEngineDoesNotLoad) {
  Bytes gif;
  for (char c : std::string("GIF89a")) gif.push_back(std::byte(c));
  put(gif, {1, 0, 1, 0, 0, 0, 0, 0x2C, 0, 0, 0, 0, 1, 0, 1, 0, 0, 2, 2, 0x44, 0x01, 0, 0x3B});
  try {
    q3::decodeImage(gif, "x.gif");
    FAIL() << "accepted";
  } catch (const q3::FormatError& e) {
    EXPECT_EQ(e.field(), "image format");
  }
  Bytes pnm;
  for (char c : std::string("P6\n1 1\n255\n")) pnm.push_back(std::byte(c));
  put(pnm, {1, 2, 3, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0});
  EXPECT_THROW(q3::decodeImage(pnm, "x.ppm"), q3::FormatError);
  Bytes tgaBadType = tgaHeader(7, 1, 1, 24, 0);
  put(tgaBadType, {1, 2, 3});
  EXPECT_THROW(q3::decodeImage(tgaBadType, "x.tga"), q3::FormatError);
}
}  // namespace

namespace {
TEST(Image, JpegFailuresNameTheFileAndStage) {
  // JPEGs go to libjpeg-turbo (renderer/image_codecs); its errors become FormatErrors.
  std::vector<uint8_t> grey(9000 * 8, 100);
  Bytes wide;
  ASSERT_TRUE(stbi_write_jpg_to_func(appendToVector, &wide, 9000, 8, 1, grey.data(), 50));
  EXPECT_EQ(q3::imageSize(wide, "wide.jpg"), (std::array<int, 2>{9000, 8}));
  try {
    q3::decodeImage(wide, "wide.jpg");
    FAIL() << "accepted";
  } catch (const q3::FormatError& e) {
    EXPECT_EQ(e.field(), "image size");
    EXPECT_EQ(e.file(), "wide.jpg");
  }
  Bytes small;
  ASSERT_TRUE(stbi_write_jpg_to_func(appendToVector, &small, 16, 16, 1, grey.data(), 90));
  const Bytes cut(small.begin(), small.begin() + 40);
  try {
    q3::decodeImage(cut, "cut.jpg");
    FAIL() << "accepted";
  } catch (const q3::FormatError& e) {
    EXPECT_EQ(e.field(), "JPEG header");
    EXPECT_EQ(e.file(), "cut.jpg");
  }
}
}  // namespace
