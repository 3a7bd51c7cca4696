#include "port/engine_glue/images.h"

#include <span>

#include "port/engine_glue/engine.h"
#include "port/q3formats/common/format_error.h"
#include "port/q3formats/image/image.h"

namespace glue {

std::shared_ptr<const Image> decodeImage(const std::vector<uint8_t>& bytes, std::string& reason) {
  // The same decoder and checks as the converter and pa-render (format allow-list, size limits,
  // JPEGs through libjpeg-turbo): a hostile pk3 reaches this from a game server.
  try {
    q3::Image decoded = q3::decodeImage(std::as_bytes(std::span(bytes)), "image");
    auto image = std::make_shared<Image>();
    image->width = decoded.width;
    image->height = decoded.height;
    image->rgba = std::move(decoded.rgba);
    return image;
  } catch (const q3::FormatError& e) {
    reason = std::string(e.what()).substr(e.file().size() + 2);  // "FIELD: DETAIL"
    return nullptr;
  }
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
