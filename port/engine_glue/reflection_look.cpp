#include "port/engine_glue/reflection_look.h"

#include <algorithm>

#include <GL/gl.h>

#include "port/engine_glue/stock_look.h"          // byteToLinear
#include "port/q3formats/shader/material.h"   // uvTransformAt

namespace glue {
namespace {

/// UvAffine (s' = a s + b t + tx, t' = c s + d t + ty) as the renderer's mat3x2 (columns are the
/// images of s, t, 1), tcMods frozen at time 0.
glm::mat3x2 uvTransformOf(const std::vector<q3::TcMod>& tcMods) {
  const q3::UvAffine uv = q3::uvTransformAt(tcMods, 0.0);
  return glm::mat3x2(glm::vec2(uv.a, uv.c), glm::vec2(uv.b, uv.d), glm::vec2(uv.tx, uv.ty));
}

}  // namespace

void applyReflectionLook(const ShaderLook& look, pa::MaterialDesc& desc) {
  if (!look.reflectionUv) return;
  desc.baseTexCoords = pa::TexCoordSource::ReflectionSphere;
  desc.uvTransform = uvTransformOf(look.tcMods);
  if (desc.alphaMode == pa::AlphaMode::Opaque || desc.alphaMode == pa::AlphaMode::Mask) {
    desc.specular = kReflectionSpecular;
  }
}

void applyShineLook(const ShaderLook& look, pa::TextureId shineTexture, pa::MaterialDesc& desc) {
  if (!look.shine || shineTexture == pa::kNoId) return;
  if (desc.alphaMode != pa::AlphaMode::Opaque && desc.alphaMode != pa::AlphaMode::Mask) return;
  const ShineLook& shine = *look.shine;
  desc.stock.shineTexture = shineTexture;
  desc.stock.shineTexCoords = shine.reflectionUv ? pa::TexCoordSource::ReflectionSphere : pa::TexCoordSource::Mesh;
  desc.stock.shineUvTransform = uvTransformOf(shine.tcMods);
  desc.stock.shineMaskedByBaseAlpha = shine.baseRedrawn;
  switch (shine.rgbGen) {
    case q3::RgbGen::LightingDiffuse:
    case q3::RgbGen::Vertex:
    case q3::RgbGen::ExactVertex: desc.stock.shineVertexColor = true; break;
    case q3::RgbGen::Const:
      desc.stock.shineColor = glm::vec3(byteToLinear(shine.constColor[0] * 255.0f), byteToLinear(shine.constColor[1] * 255.0f),
                                  byteToLinear(shine.constColor[2] * 255.0f));
      break;
    default: break;   // identity / identityLighting (1 without overbright); others drawn white
  }
  if (shine.blend.src == GL_DST_COLOR && shine.blend.dst == GL_SRC_COLOR) {
    desc.stock.shineBlend = pa::LayerBlend::Modulate2x;
  } else if (shine.blend.src == GL_DST_COLOR && shine.blend.dst == GL_DST_ALPHA) {
    desc.stock.shineBlend = pa::LayerBlend::MultiplyAdd;   // dst src + dst x 1 (an opaque base's alpha)
  } else {
    desc.stock.shineBlend = pa::LayerBlend::Add;
  }
  if (shine.reflectionUv) {
    desc.specular = std::max(desc.specular, kReflectionSpecular);
    // A shine that multiplies what is under it (Modulate2x, MultiplyAdd) reflects in its colour.
    desc.specularTinted = desc.stock.shineBlend != pa::LayerBlend::Add;
  }
}

}  // namespace glue
