#pragma once
// All shader scripts of a game, looked up by name the way the stock renderer does.
#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "port/q3formats/shader/shader_parser.h"

namespace q3 {

/// How an implicit shader (an image without a script) is lit; the engine picks it by usage.
enum class ImplicitLighting {
  Lightmap,  ///< world surface with a lightmap: texture * lightmap
  Vertex,    ///< world surface lit by vertex colours (rgbGen exactVertex)
  Diffuse,   ///< models: lit by the light grid (rgbGen lightingDiffuse)
  TwoD,      ///< 2D pictures: vertex colour, alpha blended
};

/// Lookup key of a shader or texture name: lower case, '\\' as '/', extension removed.
std::string shaderKey(std::string_view name);

/// Image files the engine tries for a texture name, in its order: the name as given
/// (if it has an extension), then .tga, .jpg, .jpeg, .png, .bmp of the extension-less name.
std::vector<std::string> imageCandidates(std::string_view name);

/// The shader the stock renderer builds for a bare image (`imagePath` is the file found).
ShaderDef makeImplicitShader(std::string_view name, const std::string& imagePath, ImplicitLighting lighting);

/// Sorts script file names into the order to pass to ShaderLibrary::addScript so that the
/// engine's rule holds: it lists scripts alphabetically (FS_PathCmp) and concatenates them
/// in reverse, so the alphabetically *last* script's definition of a name wins.
std::vector<std::string> scriptsInPriorityOrder(std::vector<std::string> scriptNames);

/// A set of parsed scripts. The first definition of a name added wins (as in the engine).
class ShaderLibrary {
 public:
  /// Parses a script and adds its shaders. A malformed script is ignored entirely (as the engine
  /// does): returns false and records the message in errors().
  bool addScript(std::string_view text, const std::string& file);

  /// Reads (with `read`; nullopt = skip) and adds every script of `scriptNames` in the engine's
  /// priority order (see scriptsInPriorityOrder). Returns the number of scripts added.
  size_t addScriptsInEngineOrder(std::vector<std::string> scriptNames,
                                 const std::function<std::optional<std::vector<std::byte>>(const std::string&)>& read);

  /// The script definition of a name (case-insensitive, extension ignored); nullptr if none.
  /// The pointer stays valid until the next addScript.
  const ShaderDef* find(std::string_view name) const;

  /// The shader for a name: its script definition, else an implicit shader from the first
  /// existing file of imageCandidates(name); nullopt if neither exists (the engine's default shader).
  std::optional<ShaderDef> resolve(std::string_view name, ImplicitLighting lighting,
                                   const std::function<bool(const std::string&)>& fileExists) const;

  /// Number of distinct shader names.
  size_t size() const { return shaders_.size(); }
  /// All definitions that won, in the order they were added.
  const std::vector<ShaderDef>& shaders() const { return shaders_; }
  /// Warnings of every script added (unknown keywords once per keyword and script).
  const std::vector<ShaderWarning>& warnings() const { return warnings_; }
  /// One message per script that was ignored.
  const std::vector<std::string>& errors() const { return errors_; }
  /// Names defined again by a later script (ignored definitions), for diagnostics.
  size_t shadowedDefinitions() const { return shadowed_; }

 private:
  std::vector<ShaderDef> shaders_;
  std::unordered_map<std::string, size_t> index_;
  std::vector<ShaderWarning> warnings_;
  std::vector<std::string> errors_;
  size_t shadowed_ = 0;
};

}  // namespace q3
