#pragma once
// .skin files: which shader each MD3 surface uses.
#include <string>
#include <string_view>
#include <vector>

namespace q3 {

/// One `surface,shader` pair.
struct SkinSurface {
  std::string surface;  ///< surface name, lower case (the engine lower-cases it)
  std::string shader;   ///< shader or image name as written
};

/// A parsed skin.
struct Skin {
  std::vector<SkinSurface> surfaces;
  std::vector<std::string> warnings;  ///< "file:line: message" for lines that were skipped

  /// Shader for a surface name (case-insensitive); "" if the skin does not name it.
  std::string shaderFor(std::string_view surface) const;
};

/// Most surfaces a skin may name (the engine's MAX_SKIN_SURFACES); later lines are ignored.
inline constexpr size_t kMaxSkinSurfaces = 256;

/// Parses `surface,shader` lines. Lines naming a tag (`tag_...`) and lines without a shader are
/// skipped; spaces, tabs, CRLF, quotes and // comments are tolerated. Never throws for content.
Skin parseSkin(std::string_view text, const std::string& file);

}  // namespace q3
