#pragma once
// Parsed Quake III shader script records (scripts/*.shader), kept close to the script's words.
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace q3 {

/// Periodic functions of `wave` arguments (rgbGen wave, alphaGen wave, deformVertexes, stretch).
enum class WaveFunc { Sin, Triangle, Square, Sawtooth, InverseSawtooth, Noise };

/// `<func> <base> <amplitude> <phase> <frequency>`: value(t) = base + amplitude * f(phase + t * frequency).
struct WaveForm {
  WaveFunc func = WaveFunc::Sin;
  float base = 0, amplitude = 0, phase = 0, frequency = 0;
  /// Value at `seconds`, read from the stock wave tables (shader_time.h; noise: waveNoise).
  float evaluate(double seconds) const;
};

/// `surfaceparm` names known to q3map/q3map2 and the renderer, as bits of ShaderDef::surfaceParms.
enum class SurfaceParm : uint64_t {
  Water = 1ull << 0, Slime = 1ull << 1, Lava = 1ull << 2, PlayerClip = 1ull << 3,
  MonsterClip = 1ull << 4, NoDrop = 1ull << 5, NonSolid = 1ull << 6, Origin = 1ull << 7,
  Trans = 1ull << 8, Detail = 1ull << 9, Structural = 1ull << 10, AreaPortal = 1ull << 11,
  ClusterPortal = 1ull << 12, DoNotEnter = 1ull << 13, Fog = 1ull << 14, Sky = 1ull << 15,
  LightFilter = 1ull << 16, AlphaShadow = 1ull << 17, Hint = 1ull << 18, Slick = 1ull << 19,
  NoImpact = 1ull << 20, NoMarks = 1ull << 21, Ladder = 1ull << 22, NoDamage = 1ull << 23,
  MetalSteps = 1ull << 24, Flesh = 1ull << 25, NoSteps = 1ull << 26, NoDraw = 1ull << 27,
  PointLight = 1ull << 28, NoLightmap = 1ull << 29, NoDlight = 1ull << 30, Dust = 1ull << 31,
  BotClip = 1ull << 32, AntiPortal = 1ull << 33, LightGrid = 1ull << 34, Skip = 1ull << 35,
  NoBotClip = 1ull << 36, Ice = 1ull << 37,
};

/// Bit of a surfaceparm name (case-insensitive); nullopt if unknown.
std::optional<SurfaceParm> surfaceParmFromName(std::string_view name);

/// Which faces are drawn (`cull`): front (default), back, or both.
enum class CullMode { FrontSided, BackSided, TwoSided };

/// `deformVertexes` kinds.
enum class DeformKind { Wave, Normal, Bulge, Move, AutoSprite, AutoSprite2, ProjectionShadow, Text };

/// One `deformVertexes` line (kept for completeness; a renderer may approximate or ignore it).
struct Deform {
  DeformKind kind = DeformKind::Wave;
  float spread = 0;                   ///< wave: the <div> argument
  std::array<float, 3> params{};      ///< bulge: width, height, speed; normal: amplitude, frequency; move: x y z
  WaveForm wave;                      ///< wave, move
  int textIndex = 0;                  ///< text0..text7
};

/// Where a stage's texture comes from. Lightmap: `$lightmap`, or an image q3map2 wrote beside the
/// map in its place ("maps/<map>/lm_NNNN", tcGen lightmap; `textures` then holds its path).
enum class TextureSource { Image, Lightmap, WhiteImage, Video };

/// OpenGL blend factors of `blendFunc`.
enum class BlendFactor {
  Zero, One, SrcColor, OneMinusSrcColor, DstColor, OneMinusDstColor,
  SrcAlpha, OneMinusSrcAlpha, DstAlpha, OneMinusDstAlpha, SrcAlphaSaturate,
};

/// How a first stage that multiplies (MaterialInfo's AlphaMode::Multiply) filters what is behind
/// it (dst: the framebuffer's values, src: the stage's colour).
enum class FilterBlend {
  Multiply,         ///< dst x src: blendFunc filter, (GL_DST_COLOR, GL_ZERO), (GL_ZERO, GL_SRC_COLOR)
  MultiplyInverse,  ///< dst x (1 - src): (GL_ZERO, GL_ONE_MINUS_SRC_COLOR)
  Modulate2x,       ///< 2 dst src: (GL_DST_COLOR, GL_SRC_COLOR)
};

/// `alphaFunc`: alpha test of the stage texture.
enum class AlphaTest { None, Gt0, Lt128, Ge128 };

/// `rgbGen` modes; Default means the script did not say (the engine picks by context).
enum class RgbGen {
  Default, Identity, IdentityLighting, Vertex, ExactVertex, OneMinusVertex, LightingDiffuse,
  Entity, OneMinusEntity, Wave, Const,
};

/// `alphaGen` modes.
enum class AlphaGen {
  Default, Identity, Vertex, OneMinusVertex, Entity, OneMinusEntity, LightingSpecular, Wave,
  Const, Portal,
};

/// `tcGen` modes.
enum class TcGen { Base, Lightmap, Environment, Vector };

/// `tcMod` kinds.
enum class TcModKind { Scroll, Scale, Rotate, Stretch, Turb, Transform, EntityTranslate };

/// One `tcMod` line.
struct TcMod {
  TcModKind kind = TcModKind::Scroll;
  std::array<float, 2> scroll{};      ///< scroll: units per second; scale: factors
  float degreesPerSecond = 0;         ///< rotate
  WaveForm wave;                      ///< stretch; turb uses base/amplitude/phase/frequency
  std::array<float, 4> matrix{1, 0, 0, 1};  ///< transform: m00 m01 m10 m11
  std::array<float, 2> translate{};   ///< transform: t0 t1
};

/// One `{ ... }` stage of a shader.
struct ShaderStage {
  TextureSource source = TextureSource::Image;
  std::vector<std::string> textures;  ///< map/clampMap: one path; animMap: the frames; videoMap: the video
  bool clamp = false;                 ///< clampMap
  float animFrequency = 0;            ///< animMap frames per second
  bool hasBlend = false;              ///< a blendFunc line was given
  BlendFactor srcBlend = BlendFactor::One;
  BlendFactor dstBlend = BlendFactor::Zero;
  AlphaTest alphaTest = AlphaTest::None;
  bool depthEqual = false;            ///< depthFunc equal
  bool depthWrite = false;            ///< explicit depthWrite
  bool detail = false;
  RgbGen rgbGen = RgbGen::Default;
  WaveForm rgbWave;
  std::array<float, 3> constColor{1, 1, 1};  ///< rgbGen const ( r g b )
  AlphaGen alphaGen = AlphaGen::Default;
  WaveForm alphaWave;
  float constAlpha = 1;               ///< alphaGen const
  float portalRange = 256;            ///< alphaGen portal
  TcGen tcGen = TcGen::Base;
  std::array<std::array<float, 3>, 2> tcGenVectors{};  ///< tcGen vector ( s ) ( t )
  std::vector<TcMod> tcMods;

  /// True for blendFunc other than (ONE, ZERO): the stage mixes with what is behind.
  bool blends() const { return hasBlend && !(srcBlend == BlendFactor::One && dstBlend == BlendFactor::Zero); }
};

/// `q3map_sun` / `q3map_sunExt`: colour, intensity and the direction the light comes from.
struct SunParms {
  std::array<float, 3> color{1, 1, 1};
  float intensity = 0;
  float degrees = 0;    ///< azimuth, degrees counter-clockwise from +X
  float elevation = 0;  ///< degrees above the horizon
  float deviation = 0;  ///< q3map_sunExt penumbra angle (0 = hard)
};

/// `skyParms <farbox> <cloudheight> <nearbox>`; a box name is empty for "-".
struct SkyParms {
  std::string farBox;
  float cloudHeight = 128;
  std::string nearBox;
};

/// `fogParms ( r g b ) <distance to opaque>`.
struct FogParms {
  std::array<float, 3> color{};
  float depthForOpaque = 0;
};

/// `sort` values of the stock renderer (numbers are kept as given).
namespace sort_key {
inline constexpr float Portal = 1, Environment = 2, Opaque = 3, Decal = 4, SeeThrough = 5,
                       Banner = 6, Fog = 7, Underwater = 8, Blend0 = 9, Blend1 = 10, Blend2 = 11,
                       Blend3 = 12, Blend6 = 13, StencilShadow = 14, AlmostNearest = 15,
                       Nearest = 16;
}

/// A compile-time (q3map / radiant) line kept verbatim: keyword plus arguments.
struct CompilerDirective {
  std::string keyword;
  std::vector<std::string> args;
};

/// One shader record of a script.
struct ShaderDef {
  std::string name;                 ///< as written (lookups are case-insensitive)
  std::string file;                 ///< script it came from
  int line = 0;                     ///< line of the name
  uint64_t surfaceParms = 0;        ///< SurfaceParm bits
  CullMode cull = CullMode::FrontSided;
  std::vector<Deform> deforms;
  std::optional<float> sort;
  float surfaceLight = 0;           ///< q3map_surfacelight (0 = none)
  std::string lightImage;           ///< q3map_lightimage
  std::optional<std::array<float, 3>> lightColor;  ///< q3map_lightRGB
  std::string editorImage;          ///< qer_editorimage
  std::optional<SunParms> sun;
  std::optional<SkyParms> sky;
  std::optional<FogParms> fog;
  bool portal = false;
  bool polygonOffset = false;
  bool noPicmip = false, noMipmaps = false, entityMergable = false;
  std::vector<CompilerDirective> compilerDirectives;  ///< other q3map_*/qer_*/tess* lines
  std::vector<ShaderStage> stages;
  bool implicit = false;            ///< made from an image, not from a script
  int unknownKeywords = 0;          ///< unknown keywords met; the stock renderer would fall back
                                    ///< to its default shader when > 0, we keep what we understood

  /// True if the SurfaceParm bit is set.
  bool has(SurfaceParm p) const { return (surfaceParms & static_cast<uint64_t>(p)) != 0; }
};

}  // namespace q3
