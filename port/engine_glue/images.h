#pragma once
// Images read through the engine's file system and decoded to RGBA8 (TGA, JPG, PNG), cached by
// name. A name's extension is only a hint: like the stock renderer we try .tga, .jpg and .png.
#include <cstdint>
#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

namespace glue {

class Engine;

/// Decoded RGBA8 pixels, row-major from the top row.
struct Image {
  int width = 0;
  int height = 0;
  std::vector<uint8_t> rgba;
};

/// Decodes TGA/JPG/PNG/BMP bytes; nullptr (and a reason) when the data is not an image.
std::shared_ptr<const Image> decodeImage(const std::vector<uint8_t>& bytes, std::string& reason);

/// Name -> decoded image cache. Missing images are remembered too (no repeated file lookups).
class ImageCache {
 public:
  /// The image named `name` (any of its extensions), or nullptr when none can be read.
  std::shared_ptr<const Image> load(const Engine& engine, const std::string& name);
  /// Forgets every image (map change).
  void clear() { images_.clear(); }

 private:
  std::unordered_map<std::string, std::shared_ptr<const Image>> images_;
};

/// The built-in images: "*white" and the default (missing texture) pattern.
std::shared_ptr<const Image> whiteImage();
std::shared_ptr<const Image> defaultImage();

}  // namespace glue
