// TextureCache: texture lookup with the engine's extension fallbacks and a fallback image.
#include "port/q3formats/world/world_textures.h"

#include <cmath>

#include <stb_image.h>

#include "port/q3formats/shader/shader_library.h"

namespace q3 {
namespace {

float srgbToLinear(uint8_t v) {
  float c = v / 255.0f;
  return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

}  // namespace

WorldImage fallbackImage() {
  WorldImage image{64, 64, std::vector<uint8_t>(64 * 64 * 4)};
  for (uint32_t y = 0; y < 64; ++y)
    for (uint32_t x = 0; x < 64; ++x) {
      bool magenta = ((x / 8) + (y / 8)) % 2 == 0;
      uint8_t* p = &image.rgba8[(y * 64 + x) * 4];
      p[0] = magenta ? 255 : 0;
      p[1] = 0;
      p[2] = magenta ? 255 : 0;
      p[3] = 255;
    }
  return image;
}

std::optional<WorldImage> decodeTextureImage(std::span<const std::byte> bytes) {
  if (bytes.empty() || bytes.size() > size_t(INT32_MAX)) return std::nullopt;
  int w = 0, h = 0, channels = 0;
  const auto* data = reinterpret_cast<const stbi_uc*>(bytes.data());
  if (!stbi_info_from_memory(data, int(bytes.size()), &w, &h, &channels) || w <= 0 || h <= 0 || w > 8192 || h > 8192)
    return std::nullopt;
  stbi_uc* pixels = stbi_load_from_memory(data, int(bytes.size()), &w, &h, &channels, 4);
  if (!pixels) return std::nullopt;
  WorldImage image{uint32_t(w), uint32_t(h), std::vector<uint8_t>(pixels, pixels + size_t(w) * h * 4)};
  stbi_image_free(pixels);
  return image;
}

std::optional<std::pair<std::string, std::vector<std::byte>>> TextureCache::read(const std::string& name) {
  const std::string key = shaderKey(name);
  if (auto it = files_.find(key); it != files_.end()) return it->second;
  std::optional<std::pair<std::string, std::vector<std::byte>>> found;
  for (const std::string& candidate : imageCandidates(name)) {
    if (auto bytes = loadFile_(candidate)) {
      found.emplace(candidate, std::move(*bytes));
      break;
    }
  }
  files_[key] = found;
  return found;
}

bool TextureCache::exists(const std::string& name) { return read(name).has_value(); }

int32_t TextureCache::get(const std::string& name, bool clamp) {
  auto cacheKey = std::make_pair(shaderKey(name), clamp);
  if (auto it = indices_.find(cacheKey); it != indices_.end()) return it->second;

  WorldTexture texture;
  texture.requestedPath = name;
  texture.clamp = clamp;
  auto file = read(name);
  if (file) {
    texture.resolvedPath = file->first;
    if (decode_) {
      if (auto image = decodeTextureImage(file->second)) {
        texture.image = std::move(*image);
      } else {
        warnings_.push_back("texture '" + file->first + "': cannot decode, using the fallback texture");
        texture.resolvedPath.clear();
        texture.isFallback = true;
      }
    }
  } else {
    warnings_.push_back("texture '" + name + "': not found, using the fallback texture");
    texture.isFallback = true;
  }
  if (texture.isFallback && decode_) texture.image = fallbackImage();

  int32_t index = int32_t(textures_.size());
  textures_.push_back(std::move(texture));
  indices_.emplace(cacheKey, index);
  return index;
}

glm::vec3 TextureCache::averageColor(int32_t index) const {
  if (index < 0 || size_t(index) >= textures_.size()) return glm::vec3(0.5f);
  const WorldImage& image = textures_[size_t(index)].image;
  if (image.rgba8.empty()) return glm::vec3(0.5f);
  glm::dvec3 sum(0.0);
  double weight = 0.0;
  for (size_t i = 0; i + 3 < image.rgba8.size(); i += 4) {
    double a = image.rgba8[i + 3] / 255.0;
    sum += a * glm::dvec3(srgbToLinear(image.rgba8[i]), srgbToLinear(image.rgba8[i + 1]), srgbToLinear(image.rgba8[i + 2]));
    weight += a;
  }
  return weight > 0.0 ? glm::vec3(sum / weight) : glm::vec3(0.5f);
}

}  // namespace q3
