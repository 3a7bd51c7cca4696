// JPEG decoding through libjpeg-turbo: known answers from images encoded here with libjpeg's
// encoder, and corrupt files that drove stb_image 2.27 into undefined behaviour.
#include <cstdio>
// clang-format off
#include <jpeglib.h>
// clang-format on

#include <gtest/gtest.h>

#include <cstdlib>
#include <random>
#include <vector>

#include "renderer/image_codecs/jpeg_decode.h"
#include "renderer/image_codecs/tests/jpeg_test_encoder.h"

namespace {

using Bytes = std::vector<std::byte>;
using Rgba = std::array<uint8_t, 4>;
using pa::test::encodeJpeg;

Rgba pixel(const pa::JpegImage& img, int x, int y) {
  const size_t i = (static_cast<size_t>(y) * static_cast<size_t>(img.width) + static_cast<size_t>(x)) * 4;
  return {img.rgba[i], img.rgba[i + 1], img.rgba[i + 2], img.rgba[i + 3]};
}

/// 16x16 RGB: four flat 8x8 quadrants (one JPEG block each, so they decode nearly exactly).
std::vector<uint8_t> quadrants() {
  const uint8_t colours[4][3] = {{200, 30, 40}, {20, 180, 60}, {30, 40, 220}, {250, 250, 250}};
  std::vector<uint8_t> p(16 * 16 * 3);
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 16; ++x)
      for (int c = 0; c < 3; ++c) p[(y * 16 + x) * 3 + c] = colours[(y / 8) * 2 + x / 8][c];
  return p;
}

void expectNear(const Rgba& got, const Rgba& want, int tolerance) {
  for (int c = 0; c < 4; ++c) EXPECT_NEAR(got[c], want[c], tolerance) << "channel " << c;
}

TEST(JpegDecode, BaselineAndProgressiveKnownAnswer) {
  for (bool progressive : {false, true}) {
    SCOPED_TRACE(progressive ? "progressive" : "baseline");
    const Bytes jpg = encodeJpeg(quadrants(), 16, 16, JCS_RGB, 3, 100, progressive);
    ASSERT_TRUE(pa::isJpeg(jpg));
    EXPECT_EQ(pa::jpegSize(jpg), (std::array<int, 2>{16, 16}));
    const pa::JpegImage img = pa::decodeJpeg(jpg);
    ASSERT_EQ(img.width, 16);
    ASSERT_EQ(img.height, 16);
    ASSERT_EQ(img.rgba.size(), 16u * 16u * 4u);
    // Colour conversion to YCbCr and back rounds: within 2 per channel at quality 100.
    expectNear(pixel(img, 3, 3), {200, 30, 40, 255}, 2);
    expectNear(pixel(img, 12, 4), {20, 180, 60, 255}, 2);
    expectNear(pixel(img, 4, 12), {30, 40, 220, 255}, 2);
    expectNear(pixel(img, 15, 15), {250, 250, 250, 255}, 2);
  }
}

TEST(JpegDecode, GreyscaleBecomesOpaqueGreyRgba) {
  std::vector<uint8_t> grey(8 * 8);
  for (int i = 0; i < 64; ++i) grey[i] = i < 32 ? 40 : 200;  // top half dark, bottom half light
  const pa::JpegImage img = pa::decodeJpeg(encodeJpeg(grey, 8, 8, JCS_GRAYSCALE, 1, 100));
  ASSERT_EQ(img.width, 8);
  // One 8x8 block with a sharp edge: ringing stays within a few levels away from the edge.
  expectNear(pixel(img, 2, 0), {40, 40, 40, 255}, 3);
  expectNear(pixel(img, 5, 7), {200, 200, 200, 255}, 3);
  EXPECT_EQ(pixel(img, 5, 7)[0], pixel(img, 5, 7)[1]);
  EXPECT_EQ(pixel(img, 5, 7)[1], pixel(img, 5, 7)[2]);
}

TEST(JpegDecode, AdobeCmykIsMultipliedByBlack) {
  // libjpeg writes CMYK with an Adobe marker; values are stored as given (Adobe's inverted
  // convention: 255 is no ink), and R = C * K / 255 as stb_image does.
  std::vector<uint8_t> cmyk(8 * 8 * 4);
  for (int i = 0; i < 64; ++i) {
    cmyk[i * 4 + 0] = 200;
    cmyk[i * 4 + 1] = 100;
    cmyk[i * 4 + 2] = 50;
    cmyk[i * 4 + 3] = 128;
  }
  const pa::JpegImage img = pa::decodeJpeg(encodeJpeg(cmyk, 8, 8, JCS_CMYK, 4, 100));
  expectNear(pixel(img, 4, 4), {100, 50, 25, 255}, 2);
}

TEST(JpegDecode, RefusesOversizeBeforeDecoding) {
  // A real header for 9000x8 (the encoder writes it), refused on the size, not in libjpeg.
  const Bytes jpg = encodeJpeg(std::vector<uint8_t>(9000 * 8, 128), 9000, 8, JCS_GRAYSCALE, 1, 50);
  EXPECT_EQ(pa::jpegSize(jpg), (std::array<int, 2>{9000, 8}));
  try {
    pa::decodeJpeg(jpg);
    FAIL() << "accepted";
  } catch (const pa::JpegError& e) {
    EXPECT_EQ(e.stage(), pa::JpegError::Stage::Size);
  }
  EXPECT_EQ(pa::decodeJpeg(jpg, {.maxDimension = 9000}).width, 9000);
}

TEST(JpegDecode, TruncatedAndHeaderlessFilesGiveClearErrors) {
  const Bytes jpg = encodeJpeg(quadrants(), 16, 16, JCS_RGB, 3, 90);
  // Cut inside the headers: libjpeg's message, no decode.
  const Bytes cut(jpg.begin(), jpg.begin() + 40);
  try {
    pa::decodeJpeg(cut);
    FAIL() << "accepted";
  } catch (const pa::JpegError& e) {
    EXPECT_EQ(e.stage(), pa::JpegError::Stage::Header);
  }
  EXPECT_THROW(pa::jpegSize(cut), pa::JpegError);
  // Cut inside the entropy-coded data: libjpeg fills the rest, as for the engine.
  const Bytes shortScan(jpg.begin(), jpg.end() - 20);
  const pa::JpegImage img = pa::decodeJpeg(shortScan);
  EXPECT_EQ(img.rgba.size(), 16u * 16u * 4u);
}

/// Offset of the first byte after the SOS segment (the entropy-coded data).
size_t scanStart(const Bytes& jpg) {
  for (size_t i = 2; i + 3 < jpg.size(); ++i)
    if (jpg[i] == std::byte{0xFF} && jpg[i + 1] == std::byte{0xDA})
      return i + 2 + ((static_cast<size_t>(jpg[i + 2]) << 8) | static_cast<size_t>(jpg[i + 3]));
  return jpg.size();
}

TEST(JpegDecode, CorruptHuffmanStreamsDecodeOrFailCleanly) {
  // Corrupt baseline entropy-coded data, the kind that drove stb_image 2.27's bit count negative
  // (port/q3formats/FUZZING.md, finding 6; these particular streams do not trip stb). Streams of
  // codes that are not in the tables, all-zero bits, an unexpected marker, and random bytes give
  // an image of the right size or a JpegError (the image and glTF fuzzers run libjpeg under ASan).
  std::vector<uint8_t> noise(32 * 32 * 3);
  std::mt19937 rng(17);
  for (auto& v : noise) v = static_cast<uint8_t>(rng());
  const Bytes jpg = encodeJpeg(noise, 32, 32, JCS_RGB, 3, 75);
  const size_t start = scanStart(jpg);
  ASSERT_LT(start + 64, jpg.size());
  std::vector<Bytes> corrupt;
  Bytes ones = jpg;  // 0xFF 0x00 stuffing: all-ones bits, no valid code
  for (size_t i = start; i + 2 < ones.size(); i += 2) ones[i] = std::byte{0xFF}, ones[i + 1] = std::byte{0x00};
  corrupt.push_back(ones);
  Bytes zeros = jpg;
  for (size_t i = start; i + 2 < zeros.size(); ++i) zeros[i] = std::byte{0x00};
  corrupt.push_back(zeros);
  Bytes earlyMarker = jpg;  // a restart marker where none is expected, then EOI
  earlyMarker.resize(start + 8);
  for (int b : {0xFF, 0xD3, 0x12, 0x34, 0xFF, 0xD9}) earlyMarker.push_back(std::byte(b));
  corrupt.push_back(earlyMarker);
  for (int k = 0; k < 200; ++k) {
    Bytes r = jpg;
    for (int n = 0; n < 8; ++n) r[start + rng() % (r.size() - 2 - start)] = std::byte(rng() & 0xFF);
    corrupt.push_back(r);
  }
  int decoded = 0, refused = 0;
  for (const Bytes& c : corrupt) {
    try {
      const pa::JpegImage img = pa::decodeJpeg(c);
      EXPECT_EQ(img.rgba.size(), 32u * 32u * 4u);
      ++decoded;
    } catch (const pa::JpegError& e) {
      EXPECT_NE(e.stage(), pa::JpegError::Stage::Size);
      ++refused;
    }
  }
  EXPECT_EQ(decoded + refused, static_cast<int>(corrupt.size()));
  EXPECT_GT(decoded, 0);  // libjpeg decodes corrupt data with warnings, as the engine shows it
}

TEST(JpegDecode, RefusesFilesWithTooManyScans) {
  // A progressive file whose scans are repeated past the limit: refused before its pixels.
  const Bytes jpg = encodeJpeg(quadrants(), 16, 16, JCS_RGB, 3, 90, true);
  const size_t firstScan = scanStart(jpg);
  size_t sos = firstScan;
  while (sos > 0 && !(jpg[sos] == std::byte{0xFF} && jpg[sos + 1] == std::byte{0xDA})) --sos;
  // Every scan segment after the first (SOS header + data up to the next marker) repeated.
  size_t next = firstScan;
  while (next + 1 < jpg.size() && !(jpg[next] == std::byte{0xFF} && jpg[next + 1] != std::byte{0x00})) ++next;
  Bytes many(jpg.begin(), jpg.begin() + static_cast<std::ptrdiff_t>(next));
  // The last scan of jpeg_simple_progression refines AC bits of one component; a DC-first scan
  // of component 0 repeated is legal enough for libjpeg to keep counting scans.
  const Bytes firstScanBytes(jpg.begin() + static_cast<std::ptrdiff_t>(sos), jpg.begin() + static_cast<std::ptrdiff_t>(next));
  for (int i = 0; i < pa::JpegLimits{}.maxScans + 10; ++i) many.insert(many.end(), firstScanBytes.begin(), firstScanBytes.end());
  many.push_back(std::byte{0xFF});
  many.push_back(std::byte{0xD9});
  try {
    pa::decodeJpeg(many);
    FAIL() << "accepted";
  } catch (const pa::JpegError& e) {
    EXPECT_EQ(e.stage(), pa::JpegError::Stage::Data);
    EXPECT_NE(std::string(e.what()).find("more than 256 scans"), std::string::npos) << e.what();
  }
}

}  // namespace
