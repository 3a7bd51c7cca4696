#pragma once
// What the module needs from a shader: its first visible stage (image, blend, alpha test,
// colour source) and the surface flags. Scripts (scripts/*.shader) are indexed once per
// registration; the first definition of a name wins, like the stock renderer.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

namespace glue {

class Engine;

/// OpenGL-style blend factors (values are the GL enums).
struct BlendFunc {
  unsigned src = 1;   ///< GL_ONE
  unsigned dst = 0;   ///< GL_ZERO
  /// True when the stage mixes with what is behind it.
  bool blends() const { return !(src == 1 && dst == 0); }
};

/// Alpha test of a stage.
enum class AlphaTest : uint8_t { None, Gt0, Lt128, Ge128 };

/// The drawable summary of a shader.
struct ShaderLook {
  std::vector<std::string> images;   ///< map/clampMap (one) or animMap frames; empty = white.
  float animFrequency = 0.0f;        ///< animMap frames per second.
  bool clamp = false;
  BlendFunc blend;
  AlphaTest alphaTest = AlphaTest::None;
  bool vertexColor = false;          ///< rgbGen vertex: SetColor / polygon colours tint it.
  bool vertexAlpha = false;          ///< alphaGen vertex.
  bool sky = false;                  ///< surfaceparm sky.
  bool nodraw = false;               ///< surfaceparm nodraw or no drawable stage.
  bool translucent = false;          ///< surfaceparm trans.
  float surfaceLight = 0.0f;         ///< q3map_surfacelight (emission, for the path tracer).
  bool fromScript = false;
};

/// The index of every shader script in the game file system.
class ShaderScripts {
 public:
  /// Reads scripts/*.shader through the engine (replaces any earlier index).
  void load(const Engine& engine);
  /// Parses one script's text into the index (first definition of a name wins).
  void addScript(std::string_view text);
  /// The look of shader `name`, or nullopt when no script defines it.
  std::optional<ShaderLook> find(std::string_view name) const;
  /// Number of shader definitions indexed.
  size_t size() const { return bodies_.size(); }

 private:
  std::unordered_map<std::string, std::string> bodies_;   ///< lower-case name -> "{...}" text
};

/// Parses the body ("{ ... }") of one shader into a look.
ShaderLook parseShaderBody(std::string_view body);

}  // namespace glue
