// PNG and EXR writers: write, read back with the decoders, compare.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include <stb_image.h>
#include <tinyexr.h>

#include "renderer/cli/image_output.h"
#include "renderer/cli/progress.h"

namespace pa::cli {
namespace {

namespace fs = std::filesystem;

fs::path scratch(const std::string& name) {
  return fs::temp_directory_path() / ("pa_cli_images_" + std::to_string(::getpid())) / name;
}

TEST(ImageOutput, PngRoundTripsAndCreatesFolders) {
  const uint32_t w = 5, h = 3;
  std::vector<uint8_t> rgba(w * h * 4);
  for (size_t i = 0; i < rgba.size(); ++i) rgba[i] = static_cast<uint8_t>(i * 7);
  for (size_t i = 3; i < rgba.size(); i += 4) rgba[i] = 255;
  const fs::path path = scratch("nested/folder/out.png");
  writePng(path, w, h, rgba);
  int width = 0, height = 0, channels = 0;
  stbi_uc* pixels = stbi_load(path.string().c_str(), &width, &height, &channels, 4);
  ASSERT_NE(pixels, nullptr);
  EXPECT_EQ(width, 5);
  EXPECT_EQ(height, 3);
  EXPECT_EQ(std::vector<uint8_t>(pixels, pixels + rgba.size()), rgba);
  stbi_image_free(pixels);
  fs::remove_all(scratch(""));
}

TEST(ImageOutput, PngRejectsMismatchedSizes) {
  std::vector<uint8_t> rgba(10);
  EXPECT_THROW(writePng(scratch("bad.png"), 4, 4, rgba), std::runtime_error);
}

TEST(ImageOutput, ExrHoldsRadianceAndAovLayers) {
  const uint32_t w = 4, h = 2;
  std::vector<glm::vec3> radiance(w * h), albedo(w * h), normal(w * h);
  std::vector<float> depth(w * h), variance(w * h);
  for (uint32_t i = 0; i < w * h; ++i) {
    radiance[i] = glm::vec3(0.5f * i, 10.0f, 0.001f * i);
    albedo[i] = glm::vec3(0.25f);
    normal[i] = glm::vec3(0, 0, 1);
    depth[i] = 3.0f + i;
    variance[i] = 0.01f * i;
  }
  const fs::path path = scratch("aov.exr");
  writeExr(path, {w, h, radiance, albedo, normal, depth, variance});

  EXRVersion version;
  ASSERT_EQ(ParseEXRVersionFromFile(&version, path.string().c_str()), TINYEXR_SUCCESS);
  EXRHeader header;
  InitEXRHeader(&header);
  const char* error = nullptr;
  ASSERT_EQ(ParseEXRHeaderFromFile(&header, &version, path.string().c_str(), &error), TINYEXR_SUCCESS);
  std::vector<std::string> names;
  for (int c = 0; c < header.num_channels; ++c) names.push_back(header.channels[c].name);
  EXPECT_EQ(names, (std::vector<std::string>{"B", "G", "R", "Z", "albedo.B", "albedo.G", "albedo.R", "normal.X",
                                             "normal.Y", "normal.Z", "variance.Y"}));
  EXRImage image;
  InitEXRImage(&image);
  ASSERT_EQ(LoadEXRImageFromFile(&image, &header, path.string().c_str(), &error), TINYEXR_SUCCESS);
  ASSERT_EQ(image.width, 4);
  ASSERT_EQ(header.pixel_types[2], TINYEXR_PIXELTYPE_FLOAT);
  const float* red = reinterpret_cast<const float*>(image.images[2]);
  const float* z = reinterpret_cast<const float*>(image.images[3]);
  EXPECT_FLOAT_EQ(red[5], 2.5f);
  EXPECT_FLOAT_EQ(z[7], 10.0f);
  FreeEXRImage(&image);
  FreeEXRHeader(&header);
  fs::remove_all(scratch(""));
}

TEST(Progress, FormatsDurations) {
  EXPECT_EQ(formatDuration(4.24), "4.2s");
  EXPECT_EQ(formatDuration(185.0), "3m05s");
  EXPECT_EQ(formatDuration(3720.0), "1h02m");
  EXPECT_EQ(formatDuration(-1.0), "?");
}

}  // namespace
}  // namespace pa::cli
