// ExternalLightmaps: lm_NNNN images beside a map, loaded through the game's file loader.
#include "port/q3formats/world/world_external_lightmaps.h"

#include <cstdio>

#include "port/q3formats/shader/shader_library.h"

namespace q3 {
namespace {

/// q3map2 numbers with four digits; beyond that, a folder this full is not a lightmap folder.
constexpr size_t kMaxNumberedLightmaps = 10000;

}  // namespace

std::string externalLightmapFolder(std::string_view bspName) {
  const size_t slash = bspName.find_last_of("/\\");
  std::string_view file = slash == std::string_view::npos ? bspName : bspName.substr(slash + 1);
  if (const size_t dot = file.rfind('.'); dot != std::string_view::npos && dot > 0) file = file.substr(0, dot);
  if (file.empty()) return {};
  return "maps/" + std::string(file);
}

std::string externalLightmapName(std::string_view folder, size_t index) {
  char number[16];
  std::snprintf(number, sizeof(number), "%04zu", index);
  return std::string(folder) + "/lm_" + number;
}

int32_t ExternalLightmaps::get(const std::string& name) { return load(name, true); }

size_t ExternalLightmaps::addNumbered(const std::string& folder) {
  size_t count = 0;
  while (count < kMaxNumberedLightmaps && load(externalLightmapName(folder, count), false) >= 0) ++count;
  return count;
}

int32_t ExternalLightmaps::load(const std::string& name, bool warnIfMissing) {
  const std::string key = shaderKey(name);
  if (const auto found = indices_.find(key); found != indices_.end()) return found->second;
  int32_t index = -1;
  if (std::optional<WorldImage> image = files_.image(name)) {
    if (image->width > 0 && image->height > 0 && image->rgba8.size() == size_t(image->width) * image->height * 4) {
      for (size_t i = 3; i < image->rgba8.size(); i += 4) image->rgba8[i] = 255;   // light has no coverage
      index = int32_t(lightmaps_.size());
      lightmaps_.push_back(std::move(*image));
    }
  } else if (warnIfMissing) {
    warnings_.push_back("external lightmap '" + name + "' not found: its surfaces drawn vertex-lit");
  }
  indices_.emplace(key, index);
  return index;
}

}  // namespace q3
