// glTF images: JPEGs are decoded by libjpeg-turbo (renderer/image_codecs), PNGs by stb_image.
#include <cstdio>
// clang-format off
#include <jpeglib.h>
// clang-format on

#include <gtest/gtest.h>

#include <cstdlib>
#include <string>
#include <vector>

#include "renderer/gltf_io/gltf_loader.h"
#include "renderer/image_codecs/tests/jpeg_test_encoder.h"

namespace pa::gltf {
namespace {

/// An 8x8 flat-colour baseline JPEG from libjpeg's encoder (quality 100, no subsampling).
std::vector<unsigned char> flatJpeg(uint8_t r, uint8_t g, uint8_t b) {
  std::vector<uint8_t> pixels(8 * 8 * 3);
  for (size_t i = 0; i < pixels.size(); i += 3) pixels[i] = r, pixels[i + 1] = g, pixels[i + 2] = b;
  const std::vector<std::byte> jpeg = pa::test::encodeJpeg(pixels, 8, 8, JCS_RGB, 3, 100);
  const auto* bytes = reinterpret_cast<const unsigned char*>(jpeg.data());
  return {bytes, bytes + jpeg.size()};
}

std::string base64(const std::vector<unsigned char>& bytes) {
  static const char* digits = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (size_t i = 0; i < bytes.size(); i += 3) {
    const uint32_t n = (uint32_t{bytes[i]} << 16) | (i + 1 < bytes.size() ? uint32_t{bytes[i + 1]} << 8 : 0) |
                       (i + 2 < bytes.size() ? uint32_t{bytes[i + 2]} : 0);
    out += digits[(n >> 18) & 63];
    out += digits[(n >> 12) & 63];
    out += i + 1 < bytes.size() ? digits[(n >> 6) & 63] : '=';
    out += i + 2 < bytes.size() ? digits[n & 63] : '=';
  }
  return out;
}

GltfScene sceneWithImage(const std::vector<unsigned char>& jpeg) {
  const std::string json = R"({"asset":{"version":"2.0"},"images":[{"uri":"data:image/jpeg;base64,)" +
                           base64(jpeg) + R"("}],"textures":[{"source":0}]})";
  return loadSceneFromMemory(std::as_bytes(std::span(json)), "jpeg.gltf");
}

void appendLittleEndian32(std::vector<unsigned char>& out, uint32_t value) {
  for (int i = 0; i < 4; ++i) out.push_back(static_cast<unsigned char>(value >> (8 * i)));
}

/// A GLB whose one image is stored in buffer view 0 (`viewOffset`, `viewLength`) of a binary
/// chunk holding `bin`.
std::vector<unsigned char> glbWithBufferViewImage(std::vector<unsigned char> bin, size_t viewOffset,
                                                  size_t viewLength) {
  std::string json = R"({"asset":{"version":"2.0"},"buffers":[{"byteLength":)" + std::to_string(bin.size()) +
                     R"(}],"bufferViews":[{"buffer":0,"byteOffset":)" + std::to_string(viewOffset) +
                     R"(,"byteLength":)" + std::to_string(viewLength) +
                     R"(}],"images":[{"bufferView":0,"mimeType":"image/jpeg"}],"textures":[{"source":0}]})";
  while (json.size() % 4) json += ' ';
  while (bin.size() % 4) bin.push_back(0);
  std::vector<unsigned char> glb = {'g', 'l', 'T', 'F'};
  appendLittleEndian32(glb, 2);
  appendLittleEndian32(glb, static_cast<uint32_t>(12 + 8 + json.size() + 8 + bin.size()));
  appendLittleEndian32(glb, static_cast<uint32_t>(json.size()));
  appendLittleEndian32(glb, 0x4E4F534Au);  // "JSON"
  glb.insert(glb.end(), json.begin(), json.end());
  appendLittleEndian32(glb, static_cast<uint32_t>(bin.size()));
  appendLittleEndian32(glb, 0x004E4942u);  // "BIN\0"
  glb.insert(glb.end(), bin.begin(), bin.end());
  return glb;
}

TEST(GltfImages, JpegInABufferViewDecodes) {
  const std::vector<unsigned char> jpeg = flatJpeg(20, 200, 40);
  std::vector<unsigned char> bin(16, 0);  // the image starts 16 bytes into the buffer
  bin.insert(bin.end(), jpeg.begin(), jpeg.end());
  const std::vector<unsigned char> glb = glbWithBufferViewImage(bin, 16, jpeg.size());
  const GltfScene scene = loadSceneFromMemory(std::as_bytes(std::span(glb)), "view.glb");
  ASSERT_EQ(scene.images.size(), 1u);
  ASSERT_EQ(scene.images[0].width, 8u);
  EXPECT_NEAR(scene.images[0].rgba8[4 * 20 + 1], 200, 2);
  EXPECT_TRUE(scene.warnings.empty());
}

TEST(GltfImages, BufferViewPastItsBufferIsAWarningNotARead) {
  // A hostile view that starts inside the buffer and runs 64 KiB past its end: the image is
  // left empty with a warning instead of being decoded from memory beyond the buffer.
  const std::vector<unsigned char> jpeg = flatJpeg(20, 200, 40);
  const std::vector<unsigned char> glb = glbWithBufferViewImage(jpeg, 4, jpeg.size() + 65536);
  const GltfScene scene = loadSceneFromMemory(std::as_bytes(std::span(glb)), "overrun.glb");
  ASSERT_EQ(scene.images.size(), 1u);
  EXPECT_TRUE(scene.images[0].rgba8.empty());
  ASSERT_FALSE(scene.warnings.empty());
  EXPECT_NE(scene.warnings[0].find("overruns its buffer"), std::string::npos) << scene.warnings[0];
}

TEST(GltfImages, JpegDecodesToRgba) {
  const GltfScene scene = sceneWithImage(flatJpeg(200, 30, 40));
  ASSERT_EQ(scene.images.size(), 1u);
  ASSERT_EQ(scene.images[0].width, 8u);
  ASSERT_EQ(scene.images[0].rgba8.size(), 8u * 8u * 4u);
  EXPECT_NEAR(scene.images[0].rgba8[4 * 20 + 0], 200, 2);
  EXPECT_NEAR(scene.images[0].rgba8[4 * 20 + 1], 30, 2);
  EXPECT_NEAR(scene.images[0].rgba8[4 * 20 + 2], 40, 2);
  EXPECT_EQ(scene.images[0].rgba8[4 * 20 + 3], 255);
  EXPECT_TRUE(scene.warnings.empty());
}

TEST(GltfImages, CorruptJpegIsAWarningNotAFailure) {
  std::vector<unsigned char> jpeg = flatJpeg(10, 20, 30);
  jpeg.resize(30);  // cut inside the headers
  const GltfScene scene = sceneWithImage(jpeg);
  ASSERT_EQ(scene.images.size(), 1u);
  EXPECT_TRUE(scene.images[0].rgba8.empty());
  ASSERT_EQ(scene.warnings.size(), 1u);
  EXPECT_NE(scene.warnings[0].find("cannot decode image"), std::string::npos) << scene.warnings[0];
}

}  // namespace
}  // namespace pa::gltf
