// TextureCache: texture lookup with the engine's extension fallbacks and a fallback image.
#include "port/q3formats/world/world_textures.h"

#include <cmath>

#include "port/q3formats/common/format_error.h"
#include "port/q3formats/image/image.h"
#include "port/q3formats/shader/shader_library.h"

namespace q3 {
namespace {

float srgbToLinear(uint8_t v) {
  float c = v / 255.0f;
  return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

}  // namespace

WorldImage toWorldImage(Image image) {
  return WorldImage{uint32_t(image.width), uint32_t(image.height), std::move(image.rgba)};
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

int32_t TextureCache::get(const std::string& name, bool clamp, bool warnIfMissing) {
  auto cacheKey = std::make_pair(shaderKey(name), clamp);
  if (auto it = indices_.find(cacheKey); it != indices_.end()) return it->second;

  WorldTexture texture;
  texture.requestedPath = name;
  texture.clamp = clamp;
  auto file = read(name);
  if (file) {
    texture.resolvedPath = file->first;
    if (decode_) {
      try {
        texture.image = toWorldImage(decodeImage(file->second, file->first));
      } catch (const FormatError& e) {
        warnings_.push_back(std::string(e.what()) + ": using the fallback texture");
        texture.resolvedPath.clear();
        texture.isFallback = true;
      }
    }
  } else {
    if (warnIfMissing) warnings_.push_back("texture '" + name + "': not found, using the fallback texture");
    texture.isFallback = true;
  }
  if (texture.isFallback && decode_) texture.image = toWorldImage(fallbackImage());

  int32_t index = int32_t(textures_.size());
  textures_.push_back(std::move(texture));
  indices_.emplace(cacheKey, index);
  return index;
}

std::optional<WorldImage> TextureCache::image(const std::string& name) {
  auto file = read(name);
  if (!file) return std::nullopt;
  try {
    return toWorldImage(decodeImage(file->second, file->first));
  } catch (const FormatError& e) {
    warnings_.push_back(std::string(e.what()) + ": image left out");
    return std::nullopt;
  }
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
