#include "port/engine_glue/reflection_look.h"

#include "port/q3formats/shader/material.h"   // uvTransformAt

namespace glue {

void applyReflectionLook(const ShaderLook& look, pa::MaterialDesc& desc) {
  if (!look.reflectionUv) return;
  desc.baseTexCoords = pa::TexCoordSource::ReflectionSphere;
  const q3::UvAffine uv = q3::uvTransformAt(look.tcMods, 0.0);
  // UvAffine: s' = a s + b t + tx, t' = c s + d t + ty; mat3x2 columns are the images of s, t, 1.
  desc.uvTransform = glm::mat3x2(glm::vec2(uv.a, uv.c), glm::vec2(uv.b, uv.d), glm::vec2(uv.tx, uv.ty));
  if (desc.alphaMode == pa::AlphaMode::Opaque || desc.alphaMode == pa::AlphaMode::Mask) {
    desc.specular = kReflectionSpecular;
  }
}

}  // namespace glue
