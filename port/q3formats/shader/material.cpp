#include "port/q3formats/shader/material.h"
#include "port/q3formats/shader/shader_time.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace q3 {

// How a shader maps to a MaterialInfo.
//
// | shader                                             | MaterialInfo                                  |
// |----------------------------------------------------|-----------------------------------------------|
// | first stage with an image, not $lightmap, not      | baseTexture (animMap: animFrames + frequency; |
// |   tcGen environment (else first image stage)       |   clampMap: clampUv)                          |
// | last non-blending stage (not $lightmap) is tcGen   | that stage is the base, baseReflects (see     |
// |   environment, no later alpha-blended image stage  |   environmentBase)                            |
// | first stage: no blendFunc / (ONE, ZERO)            | Opaque                                        |
// | first stage: alphaFunc GT0 / GE128 / LT128         | Mask, cutoff 0 / 0.5 / 0.5 (LT128: invert)    |
// | first stage: (SRC_ALPHA, ONE_MINUS_SRC_ALPHA),     | Blend                                         |
// |   (ONE, ONE_MINUS_SRC_ALPHA)                       |                                               |
// | first stage: dst factor ONE (add, SRC_ALPHA ONE,   | Additive (emissive)                           |
// |   DST_COLOR ONE, ...)                              |                                               |
// | first stage: filter (DST_COLOR, ZERO),             | Multiply, filterBlend (Modulate2x for         |
// |   (ZERO, SRC_COLOR), (DST_COLOR, SRC_COLOR),       |   DST_COLOR SRC_COLOR, MultiplyInverse for    |
// |   (ZERO, ONE_MINUS_SRC_COLOR)                      |   ZERO ONE_MINUS_SRC_COLOR)                   |
// | any $lightmap stage                                | lighting Lightmap                             |
// | first lightmap stage GL_DST_COLOR GL_SRC_COLOR     | lightmapScale 2 (else 1)                      |
// | first lightmap stage is q3map2's external image,   | lightmapImage (its path)                      |
// |   not additive (light style stages add)            |                                               |
// | base rgbGen vertex / exactVertex / oneMinusVertex  | lighting Vertex, vertexColor                  |
// | base rgbGen lightingDiffuse                        | lighting Diffuse                              |
// | no lightmap, rgbGen identity / const / wave / none | lighting Unlit (const colour kept)            |
// | base rgbGen entity / oneMinusEntity                | entityColor                                   |
// | q3map_surfacelight N                               | surfaceLight N, emissive                      |
// | q3map_lightimage / q3map_lightRGB                  | lightImageCandidates (q3map2 order: light     |
// |                                                    |   image, sky _up, first stage image, editor   |
// |                                                    |   image, shader name) / lightColor            |
// | later stage blendFunc with dst ONE, not env/lm,    | glowTextures, emissive                        |
// |   no multiplying $lightmap after it (filter, or    |                                               |
// |   DST_COLOR with a destination other than ONE)     |                                               |
// | the same over a reflecting base, multiplied by a   | reflectionOverlay (baseReflects only)         |
// |   later $lightmap (src DST_COLOR)                  |                                               |
// | later image stage after the base, same tcGen and   | baseModulations (scale 1; 2 for DST_COLOR     |
// |   tcMods, filter / DST_COLOR SRC_COLOR             |   SRC_COLOR): multiplies the base texture     |
// | the same on uvs of its own (tcGen base, other      | baseModulations, meanOnly: the base times the |
// |   tcMods), not the lightmap image                  |   image's mean colour                         |
// | surfaceparm sky or skyParms                        | sky, skyBox faces in cube order +X..-Z:       |
// |                                                    |   _rt _lf _bk _ft _up(turned 180) _dn         |
// | portal, sort portal                                | portal (mirror vs camera decided by entities) |
// | surfaceparm nodraw                                 | nodraw, invisible                             |
// | no stages (and not sky)                            | invisible                                     |
// | surfaceparm fog or fogParms                        | fogVolume                                     |
// | surfaceparm water / slime / lava                   | liquid                                        |
// | stage with tcGen environment                       | environmentMapped, environmentTexture         |
// | cull none / disable / twosided; cull back          | twoSided; backSided                           |
// | base stage tcMods                                  | uvAnimation (uvTransformAt(t) = affine map)   |
// | base stage rgbGen / alphaGen (wave)                | baseRgbGen/Wave, baseAlphaGen/Wave            |
// | first glow stage rgbGen wave, tcMods, clampMap     | glowWaves, glowWave, glowTcMods, glowClampUv  |
// | later image stage blendFunc blend over an opaque   | coverTexture, coverTcMods, coverClampUv,      |
// |   base, lit by a later $lightmap filter (see       |   coverVertexAlpha (alphaGen vertex); an      |
// |   coverStage)                                      |   opaque stage between them is the base; a    |
// |                                                    |   reflecting last solid stage is the base     |

namespace {


bool isImageStage(const ShaderStage& s) {
  return s.source == TextureSource::Image && !s.textures.empty();
}

/// The cutoff of an alpha test as `alpha >= cutoff` (or `<` when inverted) tests it: GT0 keeps any
/// alpha above zero, the smallest being one 8-bit step (a cutoff of 0 would keep every texel).
float alphaTestCutoff(AlphaTest test) { return test == AlphaTest::Gt0 ? 1.0f / 255.0f : 0.5f; }

AlphaMode blendMode(const ShaderStage& s) {
  if (!s.blends()) return AlphaMode::Opaque;
  const BlendFactor src = s.srcBlend, dst = s.dstBlend;
  if (dst == BlendFactor::One) return AlphaMode::Additive;
  if ((src == BlendFactor::DstColor && (dst == BlendFactor::Zero || dst == BlendFactor::SrcColor)) ||
      (src == BlendFactor::Zero && (dst == BlendFactor::SrcColor || dst == BlendFactor::OneMinusSrcColor)))
    return AlphaMode::Multiply;
  return AlphaMode::Blend;
}


/// q3map2 (shaders.c): the light image path is q3map_lightimage, else the sky's far box "_up"
/// image, else (without qer_editorimage) the first image named by a stage; the light image is
/// that path if it loads, else the shader image (editor image, then the shader's name, then that
/// path again, then q3map2's default image: here the first stage image).
std::vector<std::string> lightImageCandidates(const ShaderDef& shader) {
  std::string path = shader.lightImage;
  if (path.empty() && shader.sky && !shader.sky->farBox.empty()) path = shader.sky->farBox + "_up";
  std::string firstStageImage;
  for (const ShaderStage& s : shader.stages)
    if (isImageStage(s) && s.textures.front()[0] != '$' && s.textures.front()[0] != '*') {
      firstStageImage = s.textures.front();
      break;
    }
  if (path.empty() && shader.editorImage.empty()) path = firstStageImage;
  // Last, where q3map2 would take its default image: the first stage image (what the surface shows).
  std::vector<std::string> candidates;
  for (const std::string& name : {path, shader.editorImage, shader.name, firstStageImage})
    if (!name.empty() && std::find(candidates.begin(), candidates.end(), name) == candidates.end())
      candidates.push_back(name);
  return candidates;
}

/// The last stage (not $lightmap) that writes without blending, or null: it overwrites every
/// earlier one.
const ShaderStage* lastSolidStage(const std::vector<ShaderStage>& stages) {
  const ShaderStage* last = nullptr;
  for (const ShaderStage& s : stages)
    if (s.source != TextureSource::Lightmap && !s.blends()) last = &s;
  return last;
}

/// The environment-mapped stage that the stock renderer leaves as a surface's colour, or null:
/// the last stage (not $lightmap) that writes without blending overwrites every earlier one, so
/// when it is `tcGen environment` it is the base (later additive and filter stages compose with it
/// as glows and lightmap/detail filters). A later alpha-blended image stage (an opaque-ish texture
/// with chrome showing through its holes) keeps the plain texture as the base instead, since a
/// material has a single base texture and that texture covers most of the surface.
const ShaderStage* environmentBase(const std::vector<ShaderStage>& stages) {
  const ShaderStage* last = lastSolidStage(stages);
  if (last == nullptr || !isImageStage(*last) || last->tcGen != TcGen::Environment) return nullptr;
  for (const ShaderStage* s = last + 1; s < stages.data() + stages.size(); ++s)
    if (isImageStage(*s) && s->tcGen != TcGen::Environment && blendMode(*s) == AlphaMode::Blend) return nullptr;
  return last;
}

/// True when a later $lightmap stage multiplies what stage `index` drew (blendFunc filter, or
/// GL_DST_COLOR with a destination factor of alpha: the frame's alpha is 1 over a solid base;
/// not a light style that adds): an additive stage there is lit like the base
/// (bluemetalsupport2e's second texture, base_trim/tin's), not a glow.
bool litByLaterLightmap(const std::vector<ShaderStage>& stages, size_t index) {
  for (size_t i = index + 1; i < stages.size(); ++i)
    if (stages[i].source == TextureSource::Lightmap && stages[i].srcBlend == BlendFactor::DstColor &&
        stages[i].dstBlend != BlendFactor::One)
      return true;
  return false;
}

/// The stage a surface shows over its base where the stage's alpha covers it, or null: the
/// topmost image stage after `base` that blends by its alpha (SRC_ALPHA, ONE_MINUS_SRC_ALPHA) on
/// the mesh uvs, with white colour (rgbGen identity) and the texture's alpha (times the vertex
/// alpha with alphaGen vertex; no alphaFunc LT128), that a later $lightmap lights with the base.
const ShaderStage* coverStage(const std::vector<ShaderStage>& stages, const ShaderStage& base) {
  const ShaderStage* cover = nullptr;
  for (const ShaderStage* s = &base + 1; s < stages.data() + stages.size(); ++s) {
    if (!isImageStage(*s) || s->textures.size() != 1 || s->textures.front()[0] == '$' || s->tcGen != TcGen::Base)
      continue;
    if (!s->hasBlend || s->srcBlend != BlendFactor::SrcAlpha || s->dstBlend != BlendFactor::OneMinusSrcAlpha) continue;
    if (s->rgbGen != RgbGen::Default && s->rgbGen != RgbGen::Identity && s->rgbGen != RgbGen::IdentityLighting)
      continue;
    if (s->alphaGen != AlphaGen::Default && s->alphaGen != AlphaGen::Identity && s->alphaGen != AlphaGen::Vertex)
      continue;
    if (s->alphaTest == AlphaTest::Lt128 || !litByLaterLightmap(stages, size_t(s - stages.data()))) continue;
    cover = s;
  }
  return cover;
}

/// True when `cover` redraws the base's own image at the base's uvs: it covers the base with
/// itself (the effects drawn between show only through its holes).
bool redrawsBase(const ShaderStage& base, const ShaderStage& cover) {
  return base.tcGen == TcGen::Base && cover.textures.front() == base.textures.front() &&
         sameTcMods(cover.tcMods, base.tcMods) && cover.alphaGen != AlphaGen::Vertex;
}

}  // namespace

bool sameTcMods(const std::vector<TcMod>& a, const std::vector<TcMod>& b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i) {
    const TcMod &x = a[i], &y = b[i];
    if (x.kind != y.kind || x.scroll != y.scroll || x.degreesPerSecond != y.degreesPerSecond || x.matrix != y.matrix ||
        x.translate != y.translate || x.wave.func != y.wave.func || x.wave.base != y.wave.base ||
        x.wave.amplitude != y.wave.amplitude || x.wave.phase != y.wave.phase || x.wave.frequency != y.wave.frequency)
      return false;
  }
  return true;
}

bool modulateBase(std::vector<uint8_t>& base, uint32_t width, uint32_t height, const std::vector<uint8_t>& modulator,
                  uint32_t modulatorWidth, uint32_t modulatorHeight, float scale) {
  if (width == 0 || height == 0 || modulatorWidth == 0 || modulatorHeight == 0 ||
      base.size() != size_t(width) * height * 4 || modulator.size() != size_t(modulatorWidth) * modulatorHeight * 4 ||
      !(scale >= 0.0f) || !std::isfinite(scale))
    return false;
  for (uint32_t y = 0; y < height; ++y) {
    const uint32_t my = uint32_t((uint64_t(y) * modulatorHeight + modulatorHeight / 2) / height) % modulatorHeight;
    for (uint32_t x = 0; x < width; ++x) {
      const uint32_t mx = uint32_t((uint64_t(x) * modulatorWidth + modulatorWidth / 2) / width) % modulatorWidth;
      uint8_t* out = &base[(size_t(y) * width + x) * 4];
      const uint8_t* by = &modulator[(size_t(my) * modulatorWidth + mx) * 4];
      for (int c = 0; c < 3; ++c)
        out[c] = static_cast<uint8_t>(std::min(255.0f, std::round(float(out[c]) * float(by[c]) * scale / 255.0f)));
    }
  }
  return true;
}

SkyFaceImage skyFaceImage(int face) {
  // tr_sky.c: the box sides in its st_to_vec order (+X, -X, +Y, -Y, +Z, -Z) bind the images
  // loaded as rt, bk, lf, ft, up, dn through sky_texorder {0, 2, 1, 3, 4, 5}; MakeSkyVec maps a
  // side's (s, t) to texture (s, 1 - t), which for the four walls is the SkyBox layout and for
  // +Z runs s along -Y and t along -X: the SkyBox layout turned by 180 degrees.
  static constexpr std::array<SkyFaceImage, 6> kFaces{{
      {"_rt", false}, {"_lf", false}, {"_bk", false}, {"_ft", false}, {"_up", true}, {"_dn", false}}};
  return kFaces[static_cast<size_t>(std::clamp(face, 0, 5))];
}

UvAffine UvAffine::after(const UvAffine& f) const {
  UvAffine r;
  r.a = a * f.a + b * f.c;
  r.b = a * f.b + b * f.d;
  r.c = c * f.a + d * f.c;
  r.d = c * f.b + d * f.d;
  r.tx = a * f.tx + b * f.ty + tx;
  r.ty = c * f.tx + d * f.ty + ty;
  return r;
}

UvAffine uvTransformAt(const std::vector<TcMod>& mods, double seconds) { return tcModsAt(mods, seconds).affine; }

MaterialInfo deriveMaterial(const ShaderDef& shader) {
  MaterialInfo m;
  m.name = shader.name;
  m.surfaceParms = shader.surfaceParms;
  const auto& stages = shader.stages;

  // Base stage: the first image stage that is not an environment reflection nor a `detail`
  // texture (a tiled noise filter over the surface: the texture may come after it, as in
  // lightmap, detail, texture-as-filter walls), else the first that is not a reflection.
  const ShaderStage* base = nullptr;
  for (const auto& s : stages)
    if (isImageStage(s) && s.tcGen != TcGen::Environment && !s.detail) {
      base = &s;
      break;
    }
  if (!base)
    for (const auto& s : stages)
      if (isImageStage(s) && s.tcGen != TcGen::Environment) {
        base = &s;
        break;
      }
  if (!base)
    for (const auto& s : stages)
      if (isImageStage(s)) {
        base = &s;
        break;
      }
  if (const ShaderStage* reflecting = environmentBase(stages)) base = reflecting;
  // The cover of a solid base (coverStage) lies over what the last solid stage before it drew: a
  // later opaque image stage overwrote the first (a scrolling glow under a panel with holes) and
  // is the base the cover covers.
  // Chrome under a texture with holes (the last solid stage reflects; then the texture blended
  // by its alpha; then the lightmap): the reflection is the base and the texture its cover.
  const ShaderStage* cover = nullptr;
  if (base && !stages.front().blends()) {
    const ShaderStage* chrome = lastSolidStage(stages);
    if (base->tcGen != TcGen::Environment && chrome != nullptr && isImageStage(*chrome) &&
        chrome->tcGen == TcGen::Environment)
      if ((cover = coverStage(stages, *chrome)) != nullptr) base = chrome;
  }
  if (base && cover == nullptr && base->tcGen != TcGen::Environment && !stages.front().blends()) {
    cover = coverStage(stages, *base);
    for (const ShaderStage* s = base + 1; cover != nullptr && s < cover; ++s)
      if (isImageStage(*s) && !s->blends() && s->tcGen == TcGen::Base && s->textures.front()[0] != '$') base = s;
    if (cover != nullptr && redrawsBase(*base, *cover)) cover = nullptr;
  }

  bool hasLightmap = false;
  for (const auto& s : stages) {
    const bool lightmap = s.source == TextureSource::Lightmap;
    // The stage that lights the surface; q3map2's light style stages add to it (blend add).
    if (lightmap && !hasLightmap && !s.textures.empty() && s.textures.front()[0] != '$' &&
        blendMode(s) != AlphaMode::Additive)
      m.lightmapImage = s.textures.front();
    // GL_DST_COLOR GL_SRC_COLOR: what is drawn x the lightmap x 2 (islandctf's terrain).
    if (lightmap && !hasLightmap && s.hasBlend && s.srcBlend == BlendFactor::DstColor &&
        s.dstBlend == BlendFactor::SrcColor)
      m.lightmapScale = 2.0f;
    hasLightmap |= lightmap;
  }

  if (base) {
    m.baseTexture = base->textures.front();
    if (base->textures.size() > 1 || base->animFrequency > 0) {
      m.animFrames = base->textures;
      m.animFrequency = base->animFrequency;
    }
    m.clampUv = base->clamp;
    m.baseReflects = base->tcGen == TcGen::Environment;
    m.uvAnimation = base->tcMods;
    m.baseRgbGen = base->rgbGen;
    m.baseRgbWave = base->rgbWave;
    m.baseAlphaGen = base->alphaGen;
    m.baseAlphaWave = base->alphaWave;
    for (const auto& t : base->tcMods) m.hasTurbulence |= t.kind == TcModKind::Turb;
  }

  // Coverage comes from the first stage: it is the one that meets the framebuffer.
  if (!stages.empty()) {
    const ShaderStage& first = stages.front();
    m.alphaMode = blendMode(first);
    if (m.alphaMode == AlphaMode::Multiply)
      m.filterBlend = first.srcBlend == BlendFactor::DstColor && first.dstBlend == BlendFactor::SrcColor
                          ? FilterBlend::Modulate2x
                      : first.dstBlend == BlendFactor::OneMinusSrcColor ? FilterBlend::MultiplyInverse
                                                                         : FilterBlend::Multiply;
    const ShaderStage& tested = (first.alphaTest == AlphaTest::None && base) ? *base : first;
    if (tested.alphaTest != AlphaTest::None && m.alphaMode == AlphaMode::Opaque) {
      m.alphaMode = AlphaMode::Mask;
      m.alphaCutoff = alphaTestCutoff(tested.alphaTest);
      m.alphaInvert = tested.alphaTest == AlphaTest::Lt128;
    }
    if (m.alphaMode == AlphaMode::Additive) {
      m.additiveSource = first.srcBlend;
      if (first.alphaTest != AlphaTest::None) {   // the test discards fragments before they blend
        m.additiveAlphaTest = true;
        m.alphaCutoff = alphaTestCutoff(first.alphaTest);
        m.alphaInvert = first.alphaTest == AlphaTest::Lt128;
      }
    }
  }

  // Lighting of the base colour.
  const RgbGen gen = base ? base->rgbGen : RgbGen::Default;
  if (hasLightmap) m.lighting = LightingMode::Lightmap;
  else if (gen == RgbGen::Vertex || gen == RgbGen::ExactVertex || gen == RgbGen::OneMinusVertex)
    m.lighting = LightingMode::Vertex;
  else if (gen == RgbGen::LightingDiffuse) m.lighting = LightingMode::Diffuse;
  else m.lighting = LightingMode::Unlit;
  m.vertexColor = gen == RgbGen::Vertex || gen == RgbGen::ExactVertex || gen == RgbGen::OneMinusVertex;
  m.entityColor = gen == RgbGen::Entity || gen == RgbGen::OneMinusEntity;
  if (gen == RgbGen::Const && base) m.constColor = base->constColor;

  // Emission.
  m.surfaceLight = shader.surfaceLight;
  m.lightImageCandidates = lightImageCandidates(shader);
  if (!m.lightImageCandidates.empty()) m.lightImage = m.lightImageCandidates.front();
  if (shader.lightColor) {
    m.lightColor = *shader.lightColor;
    m.hasLightColor = true;
  }
  // Later stages that multiply the base texel for texel (self-multiplied metal, stains), and
  // detail filters before the base (they multiply the frame whatever their order).
  if (base) {
    for (const auto* s = stages.data(); s < stages.data() + stages.size(); ++s) {
      if (s == base || (s < base && !s->detail)) continue;
      if (!isImageStage(*s) || !s->blends()) continue;
      const bool texelForTexel = s->tcGen == base->tcGen && sameTcMods(s->tcMods, base->tcMods);
      // On uvs of its own: only plain image stages (not the lightmap image, not a reflection).
      if (!texelForTexel && (s->tcGen != TcGen::Base || base->tcGen != TcGen::Base ||
                             s->textures.front() == m.lightmapImage))
        continue;
      const bool byDst = s->srcBlend == BlendFactor::DstColor, bySrc = s->dstBlend == BlendFactor::SrcColor;
      if ((byDst && s->dstBlend == BlendFactor::Zero) || (s->srcBlend == BlendFactor::Zero && bySrc))
        m.baseModulations.push_back({s->textures.front(), 1.0f, !texelForTexel});
      else if (byDst && bySrc)
        m.baseModulations.push_back({s->textures.front(), 2.0f, !texelForTexel});
    }
  }
  for (const auto& s : stages) {
    if (&s == base || &s == &stages.front() || !isImageStage(s) || s.tcGen == TcGen::Environment) continue;
    if (litByLaterLightmap(stages, size_t(&s - stages.data()))) continue;
    if (!s.blends() || s.dstBlend != BlendFactor::One) continue;
    if (m.glowTextures.empty() && s.rgbGen == RgbGen::Wave) {
      m.glowWaves = true;
      m.glowWave = s.rgbWave;
    }
    if (m.glowTextures.empty()) {
      m.glowTcMods = s.tcMods;
      m.glowClampUv = s.clamp;
    }
    m.glowTextures.push_back(s.textures.front());
  }
  m.emissive = m.surfaceLight > 0 || !m.glowTextures.empty() || m.alphaMode == AlphaMode::Additive;
  if (cover != nullptr) {
    m.coverTexture = cover->textures.front();
    m.coverTcMods = cover->tcMods;
    m.coverClampUv = cover->clamp;
    m.coverVertexAlpha = cover->alphaGen == AlphaGen::Vertex;
    // GT0 keeps every alpha that blends anything in: no test.
    m.coverAlphaCutoff = cover->alphaTest == AlphaTest::Ge128 ? 0.5f : 0.0f;
  }
  // Shiny floors and trims (texture, chrome tcGen environment, the texture again with blendFunc
  // add, then $lightmap multiplying the frame: filter or DST_COLOR ONE_MINUS_SRC_ALPHA): the
  // added, lit texture is what the surface shows under the sheen.
  if (m.baseReflects)
    for (const auto* s = base + 1; s < stages.data() + stages.size(); ++s) {
      if (!isImageStage(*s) || s->textures.front()[0] == '$' || s->tcGen == TcGen::Environment || !s->blends() ||
          s->dstBlend != BlendFactor::One)
        continue;
      const bool lit = std::any_of(s + 1, stages.data() + stages.size(), [](const ShaderStage& later) {
        return later.source == TextureSource::Lightmap && later.srcBlend == BlendFactor::DstColor;
      });
      if (lit) {
        m.reflectionOverlay = s->textures.front();
        break;
      }
    }

  // Sky.
  m.sky = shader.has(SurfaceParm::Sky) || shader.sky.has_value();
  if (shader.sky) {
    for (int i = 0; i < 6; ++i) {
      const SkyFaceImage image = skyFaceImage(i);
      if (!shader.sky->farBox.empty()) m.skyBox.farFaces[i] = shader.sky->farBox + image.suffix;
      if (!shader.sky->nearBox.empty()) m.skyBox.nearFaces[i] = shader.sky->nearBox + image.suffix;
      m.skyBox.turned180[i] = image.turned180;
    }
    m.skyBox.cloudHeight = shader.sky->cloudHeight;
  }

  m.portal = shader.portal || (shader.sort && *shader.sort == sort_key::Portal);
  m.nodraw = shader.has(SurfaceParm::NoDraw);
  m.fogVolume = shader.has(SurfaceParm::Fog) || shader.fog.has_value();
  m.invisible = m.nodraw || (stages.empty() && !m.sky && !m.portal);
  m.liquid = shader.has(SurfaceParm::Water) || shader.has(SurfaceParm::Slime) || shader.has(SurfaceParm::Lava);
  for (const auto& s : stages)
    if (s.tcGen == TcGen::Environment && isImageStage(s)) {
      m.environmentMapped = true;
      m.environmentTexture = s.textures.front();
      break;
    }
  m.twoSided = shader.cull == CullMode::TwoSided;
  m.backSided = shader.cull == CullMode::BackSided;
  m.polygonOffset = shader.polygonOffset;
  m.hasDeforms = !shader.deforms.empty();
  return m;
}

}  // namespace q3
