#pragma once
// Shader script parser: text of a scripts/*.shader file -> ShaderDef records + warnings.
#include <string>
#include <string_view>
#include <vector>

#include "port/q3formats/shader/shader_types.h"

namespace q3 {

/// A tolerated problem in a script. Unknown keywords are reported once per keyword and script.
struct ShaderWarning {
  std::string file;
  int line = 0;             ///< first line where it happened
  std::string shader;       ///< shader being parsed ("" outside one)
  std::string keyword;      ///< the keyword concerned (lower case)
  std::string message;
  bool unknownKeyword = false;  ///< true: the keyword (or surfaceparm) is not known at all
  int count = 1;            ///< how many times an unknown keyword occurred in the script
};

/// Everything parsed from one script.
struct ShaderScript {
  std::vector<ShaderDef> shaders;       ///< in file order (duplicates kept; the library decides)
  std::vector<ShaderWarning> warnings;
};

/// Sane limits applied while parsing (the stock renderer's are smaller: 8 stages, 4 tcMods, 3 deforms).
struct ShaderLimits {
  static constexpr size_t maxStages = 32;
  static constexpr size_t maxTcMods = 16;
  static constexpr size_t maxDeforms = 16;
  static constexpr size_t maxAnimFrames = 8;  ///< the engine's MAX_IMAGE_ANIMATIONS
  static constexpr size_t maxWarnings = 512;
};

/// Parses one shader script. Unknown keywords and bad arguments become warnings; a structural
/// error (a name without `{`, a missing closing brace) throws FormatError naming file and line,
/// which is where the stock renderer ignores the whole file.
ShaderScript parseShaderScript(std::string_view text, const std::string& file);

}  // namespace q3
