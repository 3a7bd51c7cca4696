#pragma once
// What the module needs from a shader: its first visible stage (image, blend, alpha test,
// colour source) and the surface flags. Scripts (scripts/*.shader) are parsed by q3formats
// (q3::ShaderLibrary, the same reader the converter uses); this file only turns a parsed
// q3::ShaderDef into the module's drawable summary.
#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "port/q3formats/shader/shader_library.h"

namespace glue {

class Engine;

/// OpenGL-style blend factors (values are the GL enums).
struct BlendFunc {
  unsigned src = 1;   ///< GL_ONE
  unsigned dst = 0;   ///< GL_ZERO
  /// True when the stage mixes with what is behind it.
  bool blends() const { return !(src == 1 && dst == 0); }
};

/// Alpha test of a stage (the library's enum).
using AlphaTest = q3::AlphaTest;

/// A shine stage over an opaque base: a later tcGen environment stage that adds to
/// (blendfunc add) or filters (gl_dst_color gl_src_color / gl_dst_alpha) the base, e.g. the chrome
/// of a weapon, or failing one a mesh-uv filter stage (paint brightened by itself). Drawn in the
/// same renderer material as the base (StockLook::shineTexture).
struct ShineLook {
  std::string image;                          ///< The stage's map (its first animMap frame).
  bool clamp = false;                         ///< clampMap.
  bool reflectionUv = true;                   ///< tcGen environment (else the mesh uvs).
  std::vector<q3::TcMod> tcMods;              ///< Applied to the reflection uvs.
  BlendFunc blend;                            ///< (GL_ONE, GL_ONE), (GL_DST_COLOR, GL_SRC_COLOR) or (GL_DST_COLOR, GL_DST_ALPHA).
  q3::RgbGen rgbGen = q3::RgbGen::Default;    ///< The stage's rgbGen as written.
  std::array<float, 3> constColor{1, 1, 1};   ///< rgbGen const.
  /// A later stage draws the base image again with blendfunc blend: the base's alpha hides the
  /// shine (OpenArena's grenade launcher: chrome only where the paint is transparent).
  bool baseRedrawn = false;
};

/// The drawable summary of a shader.
struct ShaderLook {
  std::vector<std::string> images;   ///< map/clampMap (one) or animMap frames; empty = white.
  float animFrequency = 0.0f;        ///< animMap frames per second.
  bool clamp = false;
  bool reflectionUv = false;         ///< tcGen environment: the image is a sphere map of the mirrored view.
  std::vector<q3::TcMod> tcMods;     ///< The stage's tcMods (applied to reflection uvs, reflection_look.h).
  BlendFunc blend;
  AlphaTest alphaTest = AlphaTest::None;
  bool vertexColor = false;          ///< rgbGen vertex: SetColor / polygon colours tint it.
  bool vertexAlpha = false;          ///< alphaGen vertex.
  q3::RgbGen rgbGen = q3::RgbGen::Default;   ///< The stage's rgbGen as written.
  std::array<float, 3> constColor{1, 1, 1};  ///< rgbGen const.
  q3::WaveForm rgbWave;                      ///< rgbGen wave.
  q3::AlphaGen alphaGen = q3::AlphaGen::Default;   ///< The stage's alphaGen as written.
  float constAlpha = 1.0f;                   ///< alphaGen const.
  q3::WaveForm alphaWave;                    ///< alphaGen wave.
  bool autosprite = false;           ///< deformVertexes autosprite: quads face the viewer.
  bool sky = false;                  ///< surfaceparm sky.
  bool nodraw = false;               ///< surfaceparm nodraw or no drawable stage.
  bool translucent = false;          ///< surfaceparm trans.
  bool noPicmip = false;             ///< nopicmip: r_picmip leaves its images alone.
  bool polygonOffset = false;        ///< polygonOffset: a decal drawn over the surface it lies on.
  float surfaceLight = 0.0f;         ///< q3map_surfacelight (emission, for the path tracer).
  bool fromScript = false;
  /// Every stage as written (2D draws them all in order, as the stock renderer does).
  std::vector<q3::ShaderStage> stages;
  /// When the first stage is additive: the shader's later additive image stages, each a look
  /// of its own (multi-layer glows such as muzzle flashes).
  std::vector<ShaderLook> layers;
  /// When the first stage is opaque: its shine stage, if any (see ShineLook).
  std::optional<ShineLook> shine;
};

/// The OpenGL enum of a shader blend factor.
unsigned glBlendFactor(q3::BlendFactor factor);

/// The drawable summary of a parsed shader: its first stage that is not the lightmap (plus the
/// later additive stages of an additive shader, as layers, or the shine stage of an opaque one).
ShaderLook lookOfShader(const q3::ShaderDef& shader);

/// The index of every shader script in the game file system, read once per registration.
class ShaderScripts {
 public:
  /// Reads scripts/*.shader through the engine in the engine's priority order into a new
  /// index (a World loaded earlier keeps the old one); a malformed script is skipped with a
  /// warning, as the engine does.
  void load(const Engine& engine);
  /// Parses one script's text into the index (first definition of a name wins). False (and
  /// nothing added) when the script is malformed.
  bool addScript(std::string_view text, const std::string& file = "<memory>");
  /// The look of shader `name` (case-insensitive, extension ignored), or nullopt when no
  /// script defines it.
  std::optional<ShaderLook> find(std::string_view name) const;
  /// Number of shader definitions indexed.
  size_t size() const { return library_->size(); }
  /// The parsed scripts, shared with the World loaded in this registration.
  std::shared_ptr<const q3::ShaderLibrary> shared() const { return library_; }

 private:
  std::shared_ptr<q3::ShaderLibrary> library_ = std::make_shared<q3::ShaderLibrary>();
};

}  // namespace glue
