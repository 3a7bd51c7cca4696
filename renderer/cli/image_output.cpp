// PNG via stb_image_write, multi-layer EXR via pa::image_io::encodeExr.
#include "renderer/cli/image_output.h"

#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <stb_image_write.h>

#include "renderer/image_io/exr_writer.h"

namespace pa::cli {
namespace {

void createParentFolder(const std::filesystem::path& path) {
  const std::filesystem::path parent = path.parent_path();
  if (parent.empty()) return;
  std::error_code error;
  std::filesystem::create_directories(parent, error);
  if (error) throw std::runtime_error(path.string() + ": cannot create folder " + parent.string() + ": " + error.message());
}

/// One named float plane.
struct Channel {
  std::string name;
  std::vector<float> values;
};

}  // namespace

void writePng(const std::filesystem::path& path, uint32_t width, uint32_t height, std::span<const uint8_t> rgba8) {
  if (width == 0 || height == 0 || rgba8.size() != size_t{width} * height * 4)
    throw std::runtime_error(path.string() + ": image size does not match its pixel array");
  createParentFolder(path);
  if (!stbi_write_png(path.string().c_str(), static_cast<int>(width), static_cast<int>(height), 4, rgba8.data(),
                      static_cast<int>(width * 4)))
    throw std::runtime_error(path.string() + ": cannot write PNG");
}

void writeExr(const std::filesystem::path& path, const ExrLayers& layers) {
  const size_t pixels = size_t{layers.width} * layers.height;
  if (pixels == 0 || layers.radiance.size() != pixels)
    throw std::runtime_error(path.string() + ": image size does not match its radiance array");
  std::vector<Channel> channels;
  auto addVec3 = [&](std::span<const glm::vec3> source, const std::string& prefix, const char* names) {
    if (source.empty()) return;
    if (source.size() != pixels) throw std::runtime_error(path.string() + ": layer " + prefix + " has the wrong size");
    for (int c = 0; c < 3; ++c) {
      Channel channel{prefix + names[c], std::vector<float>(pixels)};
      for (size_t i = 0; i < pixels; ++i) channel.values[i] = source[i][c];
      channels.push_back(std::move(channel));
    }
  };
  auto addScalar = [&](std::span<const float> source, const std::string& name) {
    if (source.empty()) return;
    if (source.size() != pixels) throw std::runtime_error(path.string() + ": layer " + name + " has the wrong size");
    channels.push_back({name, std::vector<float>(source.begin(), source.end())});
  };
  addVec3(layers.radiance, "", "RGB");
  addVec3(layers.albedo, "albedo.", "RGB");
  addVec3(layers.normal, "normal.", "XYZ");
  addScalar(layers.depth, "Z");
  addScalar(layers.variance, "variance.Y");
  std::vector<image_io::ExrChannel> planes;
  for (const Channel& channel : channels) planes.push_back({channel.name, channel.values});
  std::vector<uint8_t> bytes;
  try {
    bytes = image_io::encodeExr(layers.width, layers.height, std::move(planes));
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(path.string() + ": cannot write EXR: " + e.what());
  }
  createParentFolder(path);
  std::ofstream file(path, std::ios::binary);
  file.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  if (!file.flush()) throw std::runtime_error(path.string() + ": cannot write EXR");
}

}  // namespace pa::cli
