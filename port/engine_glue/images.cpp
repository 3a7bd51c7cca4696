#include "port/engine_glue/images.h"

#include <stb_image.h>

#include <climits>

#include "port/engine_glue/engine.h"

namespace glue {

std::shared_ptr<const Image> decodeImage(const std::vector<uint8_t>& bytes, std::string& reason) {
  if (bytes.empty() || bytes.size() > static_cast<size_t>(INT_MAX)) {
    reason = "empty or oversized file";
    return nullptr;
  }
  int width = 0, height = 0, channels = 0;
  stbi_uc* pixels = stbi_load_from_memory(bytes.data(), static_cast<int>(bytes.size()), &width,
                                          &height, &channels, 4);
  if (pixels == nullptr) {
    const char* why = stbi_failure_reason();
    reason = why != nullptr ? why : "undecodable";
    return nullptr;
  }
  if (width <= 0 || height <= 0 || width > 8192 || height > 8192) {
    stbi_image_free(pixels);
    reason = "unreasonable size " + std::to_string(width) + "x" + std::to_string(height);
    return nullptr;
  }
  auto image = std::make_shared<Image>();
  image->width = width;
  image->height = height;
  image->rgba.assign(pixels, pixels + static_cast<size_t>(width) * height * 4);
  stbi_image_free(pixels);
  return image;
}

std::shared_ptr<const Image> ImageCache::load(const Engine& engine, const std::string& name) {
  const std::string key = normalizeName(stripExtension(name));
  if (key == "*white" || key == "$whiteimage") return whiteImage();
  if (auto found = images_.find(key); found != images_.end()) return found->second;

  std::shared_ptr<const Image> image;
  // The name as given first (it may carry the right extension), then the usual ones.
  const std::string candidates[] = {normalizeName(name), key + ".tga", key + ".jpg", key + ".png"};
  for (const std::string& candidate : candidates) {
    auto bytes = engine.readFile(candidate);
    if (!bytes) continue;
    std::string reason;
    image = decodeImage(*bytes, reason);
    if (image) break;
    engine.warn("image " + candidate + ": " + reason);
  }
  images_.emplace(key, image);
  return image;
}

std::shared_ptr<const Image> whiteImage() {
  static const std::shared_ptr<const Image> white = [] {
    auto image = std::make_shared<Image>();
    image->width = image->height = 8;
    image->rgba.assign(8 * 8 * 4, 255);
    return image;
  }();
  return white;
}

std::shared_ptr<const Image> defaultImage() {
  static const std::shared_ptr<const Image> pattern = [] {
    // The stock renderer's missing-texture look: a dark grid with light borders.
    auto image = std::make_shared<Image>();
    image->width = image->height = 16;
    image->rgba.resize(16 * 16 * 4);
    for (int y = 0; y < 16; ++y)
      for (int x = 0; x < 16; ++x) {
        const bool edge = x == 0 || y == 0 || x == 15 || y == 15;
        uint8_t* p = &image->rgba[(y * 16 + x) * 4];
        p[0] = p[1] = p[2] = edge ? 255 : 32;
        p[3] = 255;
      }
    return image;
  }();
  return pattern;
}

}  // namespace glue
