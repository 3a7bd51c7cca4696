#include "port/engine_glue/shader_scripts.h"

#include <GL/gl.h>

#include <utility>

#include "port/engine_glue/engine.h"

namespace glue {

unsigned glBlendFactor(q3::BlendFactor factor) {
  switch (factor) {
    case q3::BlendFactor::Zero: return GL_ZERO;
    case q3::BlendFactor::One: return GL_ONE;
    case q3::BlendFactor::SrcColor: return GL_SRC_COLOR;
    case q3::BlendFactor::OneMinusSrcColor: return GL_ONE_MINUS_SRC_COLOR;
    case q3::BlendFactor::DstColor: return GL_DST_COLOR;
    case q3::BlendFactor::OneMinusDstColor: return GL_ONE_MINUS_DST_COLOR;
    case q3::BlendFactor::SrcAlpha: return GL_SRC_ALPHA;
    case q3::BlendFactor::OneMinusSrcAlpha: return GL_ONE_MINUS_SRC_ALPHA;
    case q3::BlendFactor::DstAlpha: return GL_DST_ALPHA;
    case q3::BlendFactor::OneMinusDstAlpha: return GL_ONE_MINUS_DST_ALPHA;
    case q3::BlendFactor::SrcAlphaSaturate: return GL_SRC_ALPHA_SATURATE;
  }
  return GL_ONE;
}

namespace {

/// Copies one stage's image, blend, test and colour sources into `look`.
void takeStage(const q3::ShaderStage& stage, ShaderLook& look) {
  if (stage.source == q3::TextureSource::Image) look.images = stage.textures;
  look.animFrequency = stage.animFrequency;
  look.clamp = stage.clamp;
  look.reflectionUv = stage.tcGen == q3::TcGen::Environment;
  look.tcMods = stage.tcMods;
  if (stage.hasBlend) look.blend = {glBlendFactor(stage.srcBlend), glBlendFactor(stage.dstBlend)};
  look.alphaTest = stage.alphaTest;
  look.vertexColor = stage.rgbGen == q3::RgbGen::Vertex || stage.rgbGen == q3::RgbGen::ExactVertex ||
                     stage.rgbGen == q3::RgbGen::LightingDiffuse;
  look.vertexAlpha = stage.alphaGen == q3::AlphaGen::Vertex;
  look.rgbGen = stage.rgbGen;
  look.constColor = stage.constColor;
  look.rgbWave = stage.rgbWave;
  look.alphaGen = stage.alphaGen;
  look.constAlpha = stage.constAlpha;
  look.alphaWave = stage.alphaWave;
}

/// True for the blends a shine stage may use: add, filter x2 (dst src + src dst) and
/// dst (1 + src) (gl_dst_color gl_dst_alpha over an opaque base, whose alpha is 1).
bool isShineBlend(const q3::ShaderStage& stage) {
  using F = q3::BlendFactor;
  if (!stage.hasBlend) return false;
  return (stage.srcBlend == F::One && stage.dstBlend == F::One) ||
         (stage.srcBlend == F::DstColor && stage.dstBlend == F::SrcColor) ||
         (stage.srcBlend == F::DstColor && stage.dstBlend == F::DstAlpha);
}

/// True for a stage that may be a shine: an image with a shine blend, environment-mapped, or
/// on the mesh uvs when it filters (gl_dst_color ...: OpenArena's weapons brighten their paint by
/// itself); added mesh-uv stages are left out (pulsing glows need the stage's time).
bool isShineStage(const q3::ShaderStage& stage, bool environment) {
  if (stage.source != q3::TextureSource::Image || stage.textures.empty() || !isShineBlend(stage)) return false;
  if (environment) return stage.tcGen == q3::TcGen::Environment;
  return stage.tcGen == q3::TcGen::Base && stage.srcBlend == q3::BlendFactor::DstColor;
}

/// The shine of an opaque base stage (index first): the first later environment-mapped image
/// stage with a shine blend, else the first mesh-uv filter stage.
std::optional<ShineLook> shineOf(const q3::ShaderDef& shader, size_t first) {
  const q3::ShaderStage& base = shader.stages[first];
  size_t s = first + 1;
  while (s < shader.stages.size() && !isShineStage(shader.stages[s], true)) ++s;
  if (s == shader.stages.size()) {
    s = first + 1;
    while (s < shader.stages.size() && !isShineStage(shader.stages[s], false)) ++s;
  }
  if (s == shader.stages.size()) return std::nullopt;
  const q3::ShaderStage& stage = shader.stages[s];
  ShineLook shine;
  shine.image = stage.textures.front();
  shine.clamp = stage.clamp;
  shine.reflectionUv = stage.tcGen == q3::TcGen::Environment;
  shine.tcMods = stage.tcMods;
  shine.blend = {glBlendFactor(stage.srcBlend), glBlendFactor(stage.dstBlend)};
  shine.rgbGen = stage.rgbGen;
  shine.constColor = stage.constColor;
  for (size_t r = s + 1; r < shader.stages.size(); ++r) {
    const q3::ShaderStage& redraw = shader.stages[r];
    shine.baseRedrawn = shine.baseRedrawn ||
                        (redraw.source == q3::TextureSource::Image && redraw.textures == base.textures &&
                         redraw.tcGen == base.tcGen && redraw.hasBlend &&
                         redraw.srcBlend == q3::BlendFactor::SrcAlpha &&
                         redraw.dstBlend == q3::BlendFactor::OneMinusSrcAlpha);
  }
  return shine;
}

}  // namespace

ShaderLook lookOfShader(const q3::ShaderDef& shader) {
  ShaderLook look;
  look.fromScript = !shader.implicit;
  look.stages = shader.stages;
  look.sky = shader.has(q3::SurfaceParm::Sky);
  look.nodraw = shader.has(q3::SurfaceParm::NoDraw);
  look.translucent = shader.has(q3::SurfaceParm::Trans);
  look.noPicmip = shader.noPicmip || shader.noMipmaps;
  look.polygonOffset = shader.polygonOffset;
  look.surfaceLight = shader.surfaceLight;
  for (const q3::Deform& deform : shader.deforms)
    look.autosprite = look.autosprite || deform.kind == q3::DeformKind::AutoSprite;
  size_t first = 0;
  while (first < shader.stages.size() && shader.stages[first].source == q3::TextureSource::Lightmap) ++first;
  if (first == shader.stages.size()) {
    if (shader.stages.empty() && !look.sky) look.nodraw = true;
    return look;
  }
  takeStage(shader.stages[first], look);
  // Later additive image stages (a second glow over the first): drawn as extra layers. Over a
  // first stage that scales what is behind by its alpha without being the plain alpha blend
  // (gl_one gl_src_alpha explosions), every later blended image stage is a layer too.
  const bool plainAlphaBlend = look.blend.src == GL_SRC_ALPHA && look.blend.dst == GL_ONE_MINUS_SRC_ALPHA;
  const bool firstIsLayer = look.blend.dst == GL_ONE || (!plainAlphaBlend && (look.blend.dst == GL_SRC_ALPHA ||
                                                                              look.blend.dst == GL_ONE_MINUS_SRC_ALPHA));
  if (firstIsLayer) {
    for (size_t s = first + 1; s < shader.stages.size(); ++s) {
      const q3::ShaderStage& stage = shader.stages[s];
      if (stage.source != q3::TextureSource::Image || stage.textures.empty() || !stage.blends()) continue;
      if (look.blend.dst == GL_ONE && stage.dstBlend != q3::BlendFactor::One) continue;
      ShaderLook layer;
      layer.fromScript = look.fromScript;
      takeStage(stage, layer);
      look.layers.push_back(std::move(layer));
    }
  }
  // An opaque painted base with an environment-mapped shine over it (chrome weapons, projectiles).
  const q3::ShaderStage& base = shader.stages[first];
  if (base.source == q3::TextureSource::Image && !look.blend.blends()) look.shine = shineOf(shader, first);
  return look;
}

bool ShaderScripts::addScript(std::string_view text, const std::string& file) {
  return library_->addScript(text, file);
}

void ShaderScripts::load(const Engine& engine) {
  auto library = std::make_shared<q3::ShaderLibrary>();
  library->addScriptsInEngineOrder(
      engine.listFiles("scripts", ".shader"),
      [&engine](const std::string& file) -> std::optional<std::vector<std::byte>> {
        const auto bytes = engine.readFile("scripts/" + file);
        if (!bytes) return std::nullopt;
        const auto* first = reinterpret_cast<const std::byte*>(bytes->data());
        return std::vector<std::byte>(first, first + bytes->size());
      });
  for (const std::string& error : library->errors()) engine.warn("shader script ignored: " + error);
  library_ = std::move(library);
}

std::optional<ShaderLook> ShaderScripts::find(std::string_view name) const {
  const q3::ShaderDef* shader = library_->find(name);
  if (!shader) return std::nullopt;
  return lookOfShader(*shader);
}

}  // namespace glue
