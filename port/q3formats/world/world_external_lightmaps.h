#pragma once
// Lightmaps kept beside a map instead of in its lump: q3map2 writes them as
// "maps/<map>/lm_0000.tga", "lm_0001.tga", ... with -external (numbered like the lump's pages,
// which it leaves empty) and for lightmaps that are not the game's 128x128 (named by the
// shaders it writes, in place of $lightmap). Any size loads.
#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "port/q3formats/world/world_scene.h"
#include "port/q3formats/world/world_textures.h"

namespace q3 {

/// Where q3map2 puts a map's external lightmaps: "maps/<map>" for "maps/<map>.bsp" or any
/// other path of the .bsp file; "" for a name without a file name.
std::string externalLightmapFolder(std::string_view bspName);

/// The name of external lightmap `index` of a folder: "<folder>/lm_0003" (engine image lookup
/// adds the extension).
std::string externalLightmapName(std::string_view folder, size_t index);

/// External lightmap images appended to a scene's lightmaps, each file once.
class ExternalLightmaps {
 public:
  ExternalLightmaps(TextureCache& files, std::vector<WorldImage>& lightmaps, std::vector<std::string>& warnings)
      : files_(files), lightmaps_(lightmaps), warnings_(warnings) {}

  /// Index in the scene's lightmaps of image `name`, loaded on first use; -1 (one warning per
  /// name) when it is missing or does not decode.
  int32_t get(const std::string& name);
  /// Appends "<folder>/lm_0000", "lm_0001", ... up to the first one missing or broken, so that
  /// lightmap number n selects "lm_n"; returns how many were appended.
  size_t addNumbered(const std::string& folder);

 private:
  int32_t load(const std::string& name, bool warnIfMissing);
  TextureCache& files_;
  std::vector<WorldImage>& lightmaps_;
  std::vector<std::string>& warnings_;
  std::map<std::string, int32_t> indices_;   ///< by shaderKey(name)
};

}  // namespace q3
