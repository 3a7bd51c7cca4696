// encodeExr: encode, decode with tinyexr, compare names, order and values.
#include <gtest/gtest.h>

#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#include <tinyexr.h>

#include "renderer/image_io/exr_writer.h"

namespace pa::image_io {
namespace {

TEST(ExrWriter, ChannelsComeBackByNameWithTheirValues) {
  const uint32_t w = 3, h = 2;
  std::vector<std::vector<float>> planes(3, std::vector<float>(w * h));
  for (size_t p = 0; p < planes.size(); ++p)
    for (size_t i = 0; i < planes[p].size(); ++i) planes[p][i] = float(p) * 10.0f + float(i) * 0.25f;
  // Given out of name order: the file lists them sorted.
  const std::vector<uint8_t> bytes =
      encodeExr(w, h, {{"variance.Y", planes[0]}, {"R", planes[1]}, {"B", planes[2]}});
  ASSERT_FALSE(bytes.empty());

  EXRVersion version;
  ASSERT_EQ(ParseEXRVersionFromMemory(&version, bytes.data(), bytes.size()), TINYEXR_SUCCESS);
  EXRHeader header;
  InitEXRHeader(&header);
  const char* error = nullptr;
  ASSERT_EQ(ParseEXRHeaderFromMemory(&header, &version, bytes.data(), bytes.size(), &error), TINYEXR_SUCCESS);
  EXPECT_EQ(header.compression_type, TINYEXR_COMPRESSIONTYPE_ZIP);
  ASSERT_EQ(header.num_channels, 3);
  EXPECT_STREQ(header.channels[0].name, "B");
  EXPECT_STREQ(header.channels[1].name, "R");
  EXPECT_STREQ(header.channels[2].name, "variance.Y");
  EXRImage image;
  InitEXRImage(&image);
  ASSERT_EQ(LoadEXRImageFromMemory(&image, &header, bytes.data(), bytes.size(), &error), TINYEXR_SUCCESS);
  EXPECT_EQ(image.width, 3);
  EXPECT_EQ(image.height, 2);
  const std::vector<float>* expected[3] = {&planes[2], &planes[1], &planes[0]};
  for (int c = 0; c < 3; ++c) {
    const float* values = reinterpret_cast<const float*>(image.images[c]);
    EXPECT_EQ(std::vector<float>(values, values + w * h), *expected[c]) << header.channels[c].name;
  }
  FreeEXRImage(&image);
  FreeEXRHeader(&header);
}

TEST(ExrWriter, RejectsEmptyImagesAndPlanesOfTheWrongSize) {
  const std::vector<float> four(4, 1.0f);
  EXPECT_THROW(encodeExr(0, 2, {{"R", four}}), std::runtime_error);
  EXPECT_THROW(encodeExr(2, 2, {}), std::runtime_error);
  EXPECT_THROW(encodeExr(3, 2, {{"R", four}}), std::runtime_error);
}

}  // namespace
}  // namespace pa::image_io
