#pragma once
// A renderer-neutral reading of a shader: what a physically based renderer needs to know.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "port/q3formats/shader/shader_types.h"

namespace q3 {

/// How a surface covers what is behind it.
enum class AlphaMode {
  Opaque,    ///< first stage writes without blending
  Mask,      ///< alpha test: texel kept if alpha > cutoff (or < cutoff when `alphaInvert`)
  Blend,     ///< alpha blend: colour*a + behind*(1-a)
  Additive,  ///< adds light: colour + behind (glows, flames, beams)
  Multiply,  ///< filters what is behind: colour*behind (tinted glass)
};

/// How the stock renderer lights the base texture.
enum class LightingMode {
  Lightmap,  ///< baked lightmap ($lightmap stage)
  Vertex,    ///< baked vertex colours (rgbGen vertex / exactVertex)
  Diffuse,   ///< light grid + dynamic lights (rgbGen lightingDiffuse, models)
  Unlit,     ///< drawn at full brightness (identity / const / wave colours, no lightmap)
};

/// Affine texture-coordinate map: s' = a*s + b*t + tx, t' = c*s + d*t + ty.
struct UvAffine {
  float a = 1, b = 0, c = 0, d = 1, tx = 0, ty = 0;
  /// Applies the map to (s, t).
  std::array<float, 2> apply(float s, float t) const { return {a * s + b * t + tx, c * s + d * t + ty}; }
  /// The map `this` applied after `first`.
  UvAffine after(const UvAffine& first) const;
};

/// tcMod lines as a function of time (seconds). Turb is not affine and is left out
/// (`hasTurbulence` tells it was there); entityTranslate needs the entity and is left out.
UvAffine uvTransformAt(const std::vector<TcMod>& mods, double seconds);

/// Sky box images as a cube in world axes (Z up): faces +X, -X, +Y, -Y, +Z, -Z, each seen from
/// inside along its axis with the image top toward +Z (+X for the two Z faces) and the image
/// right = axis x top. The stock renderer (tr_sky.c) shows the skyParms images _rt, _lf, _bk,
/// _ft, _up, _dn on these faces, the _up image turned by 180 degrees (`turned180`).
struct SkyBox {
  std::array<std::string, 6> farFaces;   ///< cube order; empty if the shader has no far box
  std::array<std::string, 6> nearFaces;  ///< cube order; empty if none
  std::array<bool, 6> turned180{};       ///< the face's image must be turned by 180 degrees
  float cloudHeight = 128;
};

/// The skyParms image suffix (`_rt` ...) the stock renderer shows on cube face `face` (0..5,
/// SkyBox order; clamped) and whether it is turned by 180 degrees there.
struct SkyFaceImage {
  const char* suffix;
  bool turned180;
};
SkyFaceImage skyFaceImage(int face);

/// A later stage that multiplies the base colour by an image: `blendFunc filter`, (GL_DST_COLOR,
/// GL_ZERO) or (GL_ZERO, GL_SRC_COLOR) scale 1; (GL_DST_COLOR, GL_SRC_COLOR) scale 2. Laid on
/// the base stage's texture coordinates (same tcGen and tcMods) it multiplies texel for texel;
/// on uvs of its own (other tcMods: scrolling cloud shadows on terrain, detail textures) the
/// base is multiplied by the image's mean colour (`meanOnly`), its pattern left out.
struct BaseModulation {
  std::string texture;
  float scale = 1;
  bool meanOnly = false;
};

/// Multiplies RGBA8 `base` (width x height) by RGBA8 `modulator` (its own size, sampled at the
/// nearest texel of the same relative position) times `scale`, per colour channel in 8-bit
/// display values as the stock blend does, clamped; alpha kept. Returns false (base untouched)
/// when a size does not match its pixel count.
bool modulateBase(std::vector<uint8_t>& base, uint32_t width, uint32_t height, const std::vector<uint8_t>& modulator,
                  uint32_t modulatorWidth, uint32_t modulatorHeight, float scale);

/// Neutral description of a shader for renderers and exporters (no renderer dependency).
struct MaterialInfo {
  std::string name;
  std::string baseTexture;                ///< first image of the base stage ("" if none)
  bool baseReflects = false;              ///< base stage is tcGen environment: baseTexture is a sphere
                                          ///< map read at the mirrored view direction, not at mesh uvs
  std::string reflectionOverlay;          ///< baseReflects: the surface's own texture, added over the
                                          ///< reflection by a later lightmap-lit stage ("" if none)
  std::vector<std::string> animFrames;    ///< animMap frames of the base stage (empty otherwise)
  float animFrequency = 0;                ///< animMap frames per second
  bool clampUv = false;
  AlphaMode alphaMode = AlphaMode::Opaque;
  float alphaCutoff = 0.5f;               ///< Mask: threshold in [0,1]
  bool alphaInvert = false;               ///< Mask with LT128: keep texels below the cutoff
  /// Additive: the first stage's source factor (its destination factor is GL_ONE): One adds the
  /// stage's colour, SrcAlpha its colour x alpha (flames), DstColor what is behind x the colour
  /// (team decals: dst x (1 + src)).
  BlendFactor additiveSource = BlendFactor::One;
  bool additiveAlphaTest = false;         ///< Additive with alphaFunc: texels failing it (alphaCutoff, alphaInvert) add nothing
  FilterBlend filterBlend = FilterBlend::Multiply;   ///< Multiply: how the first stage filters what is behind
  LightingMode lighting = LightingMode::Lightmap;
  /// Multiplier of the lit colour by the first lightmap stage's blend: 2 for GL_DST_COLOR
  /// GL_SRC_COLOR (what is drawn x the lightmap x 2), else 1.
  float lightmapScale = 1;
  std::string lightmapImage;              ///< the lightmap stage's own image (q3map2's external
                                          ///< "maps/<map>/lm_NNNN"); "" for $lightmap or none
  std::array<float, 3> constColor{1, 1, 1};  ///< base stage rgbGen const colour (else white)
  bool vertexColor = false;               ///< base colour is multiplied by vertex colours
  bool entityColor = false;               ///< base colour comes from the entity (shaderRGBA)
  float surfaceLight = 0;                 ///< q3map_surfacelight intensity (0 = not a light)
  std::string lightImage;                 ///< first of lightImageCandidates ("" if none)
  /// Images whose average colour is the light colour, in q3map2's order: the first one that
  /// loads is used (q3map_lightimage, else the sky's far box _up, else the first stage image when
  /// there is no qer_editorimage; then qer_editorimage, the shader's name, the first stage image).
  /// None loads: white light.
  std::vector<std::string> lightImageCandidates;
  std::array<float, 3> lightColor{1, 1, 1};  ///< q3map_lightRGB if given (else use lightImage)
  bool hasLightColor = false;
  std::vector<BaseModulation> baseModulations;  ///< later stages multiplying the base on its uvs
  std::vector<std::string> glowTextures;  ///< additive stages over the base (self-illumination)
  /// An image stage blended over the base by its alpha (blendFunc blend) before a later $lightmap
  /// filter lights both: a launch pad's frame over its scrolling arrows, a terrain's second
  /// texture faded in by vertex alpha ("" if none; of several, the topmost). See coverStage.
  std::string coverTexture;
  std::vector<TcMod> coverTcMods;         ///< The cover stage's tcMods (on the mesh uvs)
  bool coverClampUv = false;              ///< The cover stage is clampMap
  bool coverVertexAlpha = false;          ///< alphaGen vertex: the cover's alpha x the vertex alpha
  float coverAlphaCutoff = 0;             ///< alphaFunc GE128: 0.5 (a cover alpha below it covers nothing)
  bool emissive = false;                  ///< surfaceLight > 0, or glow stages, or additive base
  bool sky = false;
  SkyBox skyBox;
  bool portal = false;                    ///< portal surface: camera or mirror, chosen by the map's
                                          ///< misc_portal_surface entity (no target = mirror)
  bool nodraw = false;                    ///< surfaceparm nodraw
  bool invisible = false;                 ///< nothing to draw (nodraw, or no stages and not sky)
  bool fogVolume = false;                 ///< surfaceparm fog / fogParms
  bool liquid = false;                    ///< water, slime or lava
  bool environmentMapped = false;         ///< a tcGen environment stage (shiny / chrome)
  std::string environmentTexture;
  bool twoSided = false;
  bool backSided = false;
  bool polygonOffset = false;             ///< decal
  bool hasTurbulence = false;             ///< tcMod turb present (not in uvAnimation)
  bool hasDeforms = false;                ///< deformVertexes present (autosprite, wave, ...)
  std::vector<TcMod> uvAnimation;         ///< tcMods of the base stage; see uvTransformAt
  RgbGen baseRgbGen = RgbGen::Default;    ///< The base stage's rgbGen (Wave: baseRgbWave)
  WaveForm baseRgbWave;
  AlphaGen baseAlphaGen = AlphaGen::Default;   ///< The base stage's alphaGen (Wave: baseAlphaWave)
  WaveForm baseAlphaWave;
  bool glowWaves = false;                 ///< The first glow stage is rgbGen wave (glowWave)
  WaveForm glowWave;
  std::vector<TcMod> glowTcMods;          ///< The first glow stage's tcMods
  bool glowClampUv = false;               ///< The first glow stage is clampMap
  uint64_t surfaceParms = 0;
};

/// True when two stages' tcMod lists are the same, kind by kind and value by value (the stages
/// read the same texture coordinates).
bool sameTcMods(const std::vector<TcMod>& a, const std::vector<TcMod>& b);

/// Derives the neutral material of a shader (see the mapping table in material.cpp).
MaterialInfo deriveMaterial(const ShaderDef& shader);

}  // namespace q3
