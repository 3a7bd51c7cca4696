#pragma once
// TextureCache: game textures decoded once per (path, clamp), with the engine's extension
// fallbacks and a visible fallback image for missing or broken files.
#include <map>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "port/q3formats/image/image.h"
#include "port/q3formats/world/world_scene.h"

namespace q3 {

/// Loads textures into WorldScene::textures, sharing repeated requests.
class TextureCache {
 public:
  TextureCache(const FileLoader& loadFile, bool decode, std::vector<WorldTexture>& textures,
               std::vector<std::string>& warnings)
      : loadFile_(loadFile), decode_(decode), textures_(textures), warnings_(warnings) {}

  /// Index of the texture for a shader's image name; a fallback texture (and one warning) if missing.
  int32_t get(const std::string& name, bool clamp, bool warnIfMissing = true);
  /// True when one of the name's image candidates exists (bytes kept for a later get()).
  bool exists(const std::string& name);
  /// The decoded image of a name (decoded even when textures are not), adding no texture;
  /// nullopt when no candidate file exists or it does not decode (one warning).
  std::optional<WorldImage> image(const std::string& name);
  /// Mean linear colour of a texture (alpha-weighted), {0.5} when unknown.
  glm::vec3 averageColor(int32_t index) const;

 private:
  std::optional<std::pair<std::string, std::vector<std::byte>>> read(const std::string& name);
  const FileLoader& loadFile_;
  bool decode_;
  std::vector<WorldTexture>& textures_;
  std::vector<std::string>& warnings_;
  std::map<std::pair<std::string, bool>, int32_t> indices_;
  std::map<std::string, std::optional<std::pair<std::string, std::vector<std::byte>>>> files_;
};

/// Converts a decoded q3::Image (port/q3formats/image) to a WorldImage.
WorldImage toWorldImage(Image image);

}  // namespace q3
