#include "port/engine_glue/stock_look.h"

#include <algorithm>
#include <array>
#include <cmath>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>

#include "port/q3formats/shader/material.h"
#include "port/q3formats/shader/shader_library.h"
#include "renderer/core/srgb.h"

namespace glue {
namespace {

/// Where the stock renderer takes a model surface's colour from (its stage's rgbGen).
enum class ModelColorSource : uint8_t { EntityLight, White, Entity, OneMinusEntity };

ModelColorSource modelColorSource(const ShaderEntry& entry) {
  const ShaderLook& look = entry.look;
  if (!look.fromScript) return ModelColorSource::EntityLight;   // implicit model shader: lightingDiffuse
  switch (look.rgbGen) {
    case q3::RgbGen::LightingDiffuse: return ModelColorSource::EntityLight;
    case q3::RgbGen::Entity: return ModelColorSource::Entity;
    case q3::RgbGen::OneMinusEntity: return ModelColorSource::OneMinusEntity;
    default: return ModelColorSource::White;   // identity / identityLighting (1 without overbright);
                                               // const colours are the material's base colour
  }
}

}  // namespace

/// True for the stock alpha blend (GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA).
bool isAlphaBlend(const BlendFunc& blend) {
  return blend.src == 0x0302 /*GL_SRC_ALPHA*/ && blend.dst == 0x0303 /*GL_ONE_MINUS_SRC_ALPHA*/;
}

std::optional<std::pair<pa::BlendFactor, pa::BlendFactor>> layerFactors(const BlendFunc& blend) {
  const auto factor = [](unsigned gl) -> std::optional<pa::BlendFactor> {
    switch (gl) {
      case 0: return pa::BlendFactor::Zero;
      case 1: return pa::BlendFactor::One;
      case 0x0300: return pa::BlendFactor::SrcColor;
      case 0x0301: return pa::BlendFactor::OneMinusSrcColor;
      case 0x0302: return pa::BlendFactor::SrcAlpha;
      case 0x0303: return pa::BlendFactor::OneMinusSrcAlpha;
      default: return std::nullopt;
    }
  };
  const auto src = factor(blend.src), dst = factor(blend.dst);
  if (!src || !dst) return std::nullopt;
  return std::make_pair(*src, *dst);
}

/// RGBA with the colour multiplied by alpha (alpha kept).
Darkening filterAsDarkening(const BlendFunc& blend) {
  constexpr unsigned kZero = 0, kSrcColor = 0x0300, kOneMinusSrcColor = 0x0301, kDstColor = 0x0306;
  // dst * src: (DST_COLOR, ZERO) or (ZERO, SRC_COLOR); dst * (1 - src): (ZERO, ONE_MINUS_SRC_COLOR).
  if ((blend.src == kDstColor && blend.dst == kZero) || (blend.src == kZero && blend.dst == kSrcColor))
    return Darkening::BySourceColor;
  if (blend.src == kZero && blend.dst == kOneMinusSrcColor) return Darkening::ByInverseSourceColor;
  return Darkening::None;
}

/// Black RGBA whose alpha is how much `image` darkens what is behind it.
std::shared_ptr<const Image> darkeningImage(const std::shared_ptr<const Image>& image, Darkening mode) {
  if (!image) return nullptr;
  auto out = std::make_shared<Image>();
  out->width = image->width;
  out->height = image->height;
  out->rgba.assign(image->rgba.size(), 0);
  for (size_t i = 0; i + 3 < image->rgba.size(); i += 4) {
    const int luminance = (image->rgba[i] * 54 + image->rgba[i + 1] * 183 + image->rgba[i + 2] * 19) >> 8;
    out->rgba[i + 3] = static_cast<uint8_t>(mode == Darkening::BySourceColor ? 255 - luminance : luminance);
  }
  return out;
}

std::shared_ptr<const Image> premultipliedImage(const std::shared_ptr<const Image>& image) {
  if (!image) return nullptr;
  auto out = std::make_shared<Image>(*image);
  for (size_t i = 0; i + 3 < out->rgba.size(); i += 4)
    for (size_t c = 0; c < 3; ++c) out->rgba[i + c] = static_cast<uint8_t>((out->rgba[i + c] * out->rgba[i + 3] + 127) / 255);
  return out;
}

/// Vertex colours of alpha-blended effect triangles premultiplied by their alpha (linearised, as
/// the layer is composed in display values), to go with MaterialUse::StockEffect and Effect.
void premultiplyBlendedEffects(ShaderRegistry& shaders, GeometryBatch& batch) {
  std::vector<uint8_t>& done = batch.scratch.doneFlags(batch.colors.size());
  for (size_t t = 0; t < batch.triangleShaders.size(); ++t) {
    const ShaderLook& look = shaders.resolve(batch.triangleShaders[t]).look;
    if (!look.fromScript || !isAlphaBlend(look.blend)) continue;
    for (size_t corner = 0; corner < 3; ++corner) {
      const uint32_t v = batch.indices[t * 3 + corner];
      if (v >= batch.colors.size() || done[v]) continue;
      done[v] = 1;
      // The layer is encoded before it is added (display values): encode(lin(c) * lin(a)) ~ c * a.
      glm::vec4& c = batch.colors[v];
      c = glm::vec4(glm::vec3(c) * byteToLinear(c.a * 255.0f), c.a);
    }
  }
}

float byteToLinear(float byte) {
  // Whole bytes (grid light, entity and shader colours: three per model vertex per frame in the
  // lightmap preset) from a table of the same values, without powf; 0 and fractions computed.
  static const std::array<float, 256> kWholeBytes = [] {
    std::array<float, 256> t{};
    for (int i = 0; i < 256; ++i) t[size_t(i)] = pa::srgbToLinearClamped(static_cast<float>(i) / 255.0f);
    return t;
  }();
  if (byte >= 1.0f && byte <= 255.0f) {
    const int whole = static_cast<int>(byte);
    if (static_cast<float>(whole) == byte) return kWholeBytes[size_t(whole)];
  }
  return pa::srgbToLinearClamped(byte / 255.0f);
}

/// Lightmap preset: each vertex of an MD3 batch gets the colour the stock renderer gives it
/// (grid light per vertex normal, entity colour or white). Stock multiplies texture
/// and colour bytes in gamma space; the tracer multiplies linear values, so the bytes are
/// linearised (lin(a) * lin(b) ~ lin(a * b)).
void lightModelLikeStock(const q3abi::refEntity_t& e, const glm::mat4x3& toWorld,
                         const EntityLight& light, ShaderRegistry& shaders, GeometryBatch& batch) {
  const glm::mat3 axes(toWorld);
  std::vector<uint8_t>& done = batch.scratch.doneFlags(batch.positions.size());
  for (size_t t = 0; t < batch.triangleShaders.size(); ++t) {
    const ModelColorSource source = modelColorSource(shaders.resolve(batch.triangleShaders[t]));
    for (size_t corner = 0; corner < 3; ++corner) {
      const uint32_t v = batch.indices[t * 3 + corner];
      if (v >= batch.positions.size() || done[v]) continue;
      done[v] = 1;
      glm::vec3 bytes(255.0f);
      switch (source) {
        case ModelColorSource::EntityLight: {
          glm::vec3 normal = axes * batch.normals[v];
          const float length = glm::length(normal);
          normal = length > 1e-12f ? normal / length : glm::vec3(0.0f, 0.0f, 1.0f);
          bytes = diffuseVertexLight(light, normal);
          break;
        }
        case ModelColorSource::Entity:
          bytes = glm::vec3(e.shaderRGBA[0], e.shaderRGBA[1], e.shaderRGBA[2]);
          break;
        case ModelColorSource::OneMinusEntity:
          bytes = glm::vec3(255 - e.shaderRGBA[0], 255 - e.shaderRGBA[1], 255 - e.shaderRGBA[2]);
          break;
        case ModelColorSource::White:
          break;
      }
      batch.colors[v] = glm::vec4(byteToLinear(bytes.r), byteToLinear(bytes.g), byteToLinear(bytes.b),
                                  batch.colors[v].a);
    }
  }
}

/// World surfaces whose shader has no lightmap stage and no vertex-colour stage are drawn by
/// opengl1 at full texture brightness (rgbGen identityLighting), whatever q3map2 baked into
/// their vertex colours: whiten those colours (the lightmap preset multiplies them in; the
/// traced presets ignore vertex colours of vertex-lit surfaces). Also records the colour of each
/// material's glow stage (rgbGen const of the first additive stage), which the stock look adds.
void stockWorldLook(q3::WorldScene& scene, const q3::ShaderLibrary& library,
                    std::unordered_map<uint32_t, glm::vec3>& glowColors, int lightShift) {
  std::vector<bool> unlit(scene.materials.size(), false);
  for (size_t i = 0; i < scene.materials.size(); ++i) {
    const q3::WorldMaterial& m = scene.materials[i];
    const q3::ShaderDef* def = m.fromScript ? library.find(m.shaderName) : nullptr;
    if (def == nullptr) continue;
    unlit[i] = q3::deriveMaterial(*def).lighting == q3::LightingMode::Unlit;
    for (size_t s = 1; s < def->stages.size(); ++s) {
      const q3::ShaderStage& stage = def->stages[s];
      if (stage.source != q3::TextureSource::Image || !stage.blends() || stage.dstBlend != q3::BlendFactor::One ||
          stage.tcGen == q3::TcGen::Environment)
        continue;
      if (stage.rgbGen == q3::RgbGen::Const)
        glowColors[uint32_t(i)] = glm::vec3(byteToLinear(stage.constColor[0] * 255.0f),
                                            byteToLinear(stage.constColor[1] * 255.0f),
                                            byteToLinear(stage.constColor[2] * 255.0f));
      break;
    }
  }
  for (q3::WorldModel& model : scene.models) {
    for (q3::WorldMesh& mesh : model.meshes) {
      if (mesh.material >= unlit.size()) continue;
      if (unlit[mesh.material]) {
        for (glm::vec4& color : mesh.colors) color = glm::vec4(1.0f, 1.0f, 1.0f, color.a);
      } else if (scene.materials[mesh.material].vertexLit || mesh.lightmap < 0) {
        // Baked vertex light is brightened at load like lightmaps (tr_bsp.c shifts every
        // draw vertex colour by r_mapOverBrightBits - overbrightBits).
        for (glm::vec4& color : mesh.colors) {
          const glm::vec3 shifted = colorShiftLight(glm::round(glm::vec3(color) * 255.0f), lightShift);
          color = glm::vec4(shifted / 255.0f, color.a);
        }
      }
    }
  }
}

/// Repeats the triangles of shaders that have extra additive layers once per layer
/// (batch.triangleLayers tells which layer each triangle draws).
void addShaderLayers(ShaderRegistry& shaders, GeometryBatch& batch) {
  const size_t count = batch.triangles();
  batch.triangleLayers.assign(count, 0);
  const bool timed = !batch.triangleShaderTimes.empty();
  if (timed) batch.triangleShaderTimes.resize(count, 0.0f);
  for (size_t t = 0; t < count; ++t) {
    const size_t layers = shaders.resolve(batch.triangleShaders[t]).look.layers.size();
    for (size_t layer = 1; layer <= layers; ++layer) {
      batch.indices.insert(batch.indices.end(), {batch.indices[t * 3], batch.indices[t * 3 + 1], batch.indices[t * 3 + 2]});
      batch.triangleShaders.push_back(batch.triangleShaders[t]);
      batch.triangleLayers.push_back(static_cast<uint32_t>(layer));
      if (timed) batch.triangleShaderTimes.push_back(batch.triangleShaderTimes[t]);
    }
  }
}

uint8_t stockSpecularAlpha(const glm::vec3& position, const glm::vec3& normal, const glm::vec3& viewer) {
  const glm::vec3 kLight(-960.0f, 1980.0f, 96.0f);   // stock's fixed specular light, model space
  const float normalLength = glm::length(normal);
  const glm::vec3 n = normalLength > 0.0f ? normal / normalLength : glm::vec3(0.0f, 0.0f, 1.0f);
  const glm::vec3 toLight = kLight - position;
  const float lightLength = glm::length(toLight);
  const glm::vec3 l = lightLength > 0.0f ? toLight / lightLength : glm::vec3(0.0f);
  const glm::vec3 reflected = 2.0f * glm::dot(n, l) * n - l;
  const glm::vec3 toViewer = viewer - position;
  const float viewerLength = glm::length(toViewer);
  if (!(viewerLength > 0.0f)) return 0;
  float d = glm::dot(reflected, toViewer) / viewerLength;
  if (!(d >= 0.0f)) return 0;
  d = d * d;
  d = d * d;
  return static_cast<uint8_t>(std::min(255, static_cast<int>(d * 255.0f)));
}

void specularAlphaLikeStock(const std::function<bool(q3abi::qhandle_t, uint32_t)>& specular, const glm::vec3& viewer,
                            GeometryBatch& batch) {
  const size_t vertices =
      std::min({batch.positions.size(), batch.normals.size(), batch.uvs.size(), batch.colors.size()});
  std::vector<uint32_t>& copies = batch.scratch.vertices;
  copies.assign(vertices, UINT32_MAX);
  for (size_t t = 0; t < batch.triangles(); ++t) {
    const uint32_t layer = t < batch.triangleLayers.size() ? batch.triangleLayers[t] : 0u;
    if (!specular(batch.triangleShaders[t], layer)) continue;
    for (size_t corner = 0; corner < 3; ++corner) {
      uint32_t& index = batch.indices[t * 3 + corner];
      if (index >= vertices) continue;
      if (copies[index] == UINT32_MAX) {
        copies[index] = static_cast<uint32_t>(batch.positions.size());
        const glm::vec3 position = batch.positions[index], normal = batch.normals[index];
        const glm::vec4 color = batch.colors[index];
        batch.positions.push_back(position);
        batch.normals.push_back(normal);
        batch.uvs.push_back(batch.uvs[index]);
        batch.colors.push_back(glm::vec4(glm::vec3(color), stockSpecularAlpha(position, normal, viewer) / 255.0f));
      }
      index = copies[index];
    }
  }
}

void applyPictureToWorld(q3::WorldScene& scene, const q3::ShaderLibrary& library, const PictureSettings& picture) {
  if (picture.picmip == 0 && !(picture.intensity > 1.0f)) return;
  std::vector<bool> keepSize(scene.textures.size(), false);
  auto keep = [&](int32_t index) {
    if (index >= 0 && size_t(index) < keepSize.size()) keepSize[size_t(index)] = true;
  };
  for (const q3::WorldMaterial& m : scene.materials) {
    const q3::ShaderDef* shader = m.fromScript ? library.find(m.shaderName) : nullptr;
    if (!m.sky && (shader == nullptr || !(shader->noPicmip || shader->noMipmaps))) continue;
    keep(m.baseTexture);
    keep(m.emissiveTexture);
    keep(m.reflectionOverlayTexture);
    keep(m.coverTexture);
  }
  for (int32_t face : scene.sky.faces) keep(face);
  for (size_t t = 0; t < scene.textures.size(); ++t) {
    q3::WorldImage& image = scene.textures[t].image;
    if (image.width == 0 || image.height == 0) continue;
    if (!keepSize[t] && picture.picmip > 0) {
      int width = int(image.width), height = int(image.height);
      image.rgba8 = picmipImage(image.rgba8, width, height, picture.picmip);
      image.width = uint32_t(width);
      image.height = uint32_t(height);
    }
    applyIntensity(image.rgba8, picture.intensity);
  }
}

}  // namespace glue
