// glTF data -> MaterialDesc / LightDesc / SkyDesc / Camera (see the mapping in gltf_mapping.h).
#include "renderer/gltf_io/gltf_mapping.h"

#include <cmath>
#include <cstdlib>
#include <sstream>

#include <glm/trigonometric.hpp>

namespace pa::gltf {
namespace {

/// Dielectric reflectance at normal incidence (IOR 1.5).
constexpr float kDielectricSpecular = 0.04f;

bool flagSet(const Extras& extras, const char* key) {
  const auto it = extras.find(key);
  if (it == extras.end()) return false;
  return it->second == "true" || it->second == "1" || it->second == "yes";
}

/// Parses "[r, g, b]" (JSON array text) into `out`; false if the text is not three finite numbers.
bool parseVec3(const std::string& text, glm::vec3& out) {
  std::string cleaned = text;
  for (char& c : cleaned)
    if (c == '[' || c == ']' || c == ',') c = ' ';
  std::istringstream in(cleaned);
  glm::vec3 value;
  if (!(in >> value.x >> value.y >> value.z)) return false;
  if (!std::isfinite(value.x) || !std::isfinite(value.y) || !std::isfinite(value.z)) return false;
  out = value;
  return true;
}

TextureId rendererTexture(uint32_t gltfTexture, const std::vector<TextureId>& textures) {
  return gltfTexture < textures.size() ? textures[gltfTexture] : kNoId;
}

}  // namespace

MaterialDesc toMaterialDesc(const GltfMaterial& material, const std::vector<TextureId>& textures) {
  MaterialDesc desc;
  desc.baseTexture = rendererTexture(material.baseColorTexture, textures);
  desc.baseColor = material.baseColorFactor;
  desc.uvTransform = material.baseColorUvTransform;
  switch (material.alphaMode) {
    case AlphaMode::Opaque: desc.alphaMode = pa::AlphaMode::Opaque; break;
    case AlphaMode::Mask: desc.alphaMode = pa::AlphaMode::Mask; break;
    case AlphaMode::Blend: desc.alphaMode = pa::AlphaMode::Blend; break;
  }
  desc.alphaCutoff = material.alphaCutoff;
  desc.emissiveTexture = rendererTexture(material.emissiveTexture, textures);
  desc.emission = material.emissive;
  desc.specular = kDielectricSpecular + (1.0f - kDielectricSpecular) * material.metallic;
  desc.roughness = material.roughness;
  desc.twoSided = material.doubleSided;
  desc.sky = flagSet(material.extras, "sky");
  desc.mirror = flagSet(material.extras, "mirror");
  desc.visible = !flagSet(material.extras, "nodraw");
  desc.castsShadows = !flagSet(material.extras, "noshadows");
  if (flagSet(material.extras, "additive")) desc.alphaMode = pa::AlphaMode::Additive;
  desc.alphaInvert = flagSet(material.extras, "alphaInvert");
  return desc;
}

LightDesc toLightDesc(const GltfLight& light) {
  LightDesc desc;
  switch (light.type) {
    case LightType::Point: desc.type = pa::LightType::Point; break;
    case LightType::Spot: desc.type = pa::LightType::Spot; break;
    case LightType::Directional: desc.type = pa::LightType::Directional; break;
  }
  desc.position = light.position;
  desc.direction = light.direction;
  desc.color = light.color;
  desc.intensity = light.intensity;
  desc.falloff = Falloff::InverseSquare;
  desc.range = light.range;
  desc.cosInnerAngle = std::cos(light.innerConeAngle);
  desc.cosOuterAngle = std::cos(light.outerConeAngle);
  return desc;
}

SkyDesc toSkyDesc(const Extras& sceneExtras) {
  SkyDesc sky;
  if (const auto it = sceneExtras.find("sky_color"); it != sceneExtras.end()) parseVec3(it->second, sky.color);
  if (const auto it = sceneExtras.find("sky_intensity"); it != sceneExtras.end()) {
    char* end = nullptr;
    const float intensity = std::strtof(it->second.c_str(), &end);
    if (end != it->second.c_str() && std::isfinite(intensity) && intensity >= 0.0f) sky.intensity = intensity;
  }
  return sky;
}

Camera toCamera(const GltfCamera& camera, float imageAspect) {
  Camera out;
  out.origin = camera.origin;
  out.forward = camera.forward;
  out.left = camera.left;
  out.up = camera.up;
  out.fovY = glm::degrees(camera.yfov);
  out.fovX = glm::degrees(2.0f * std::atan(std::tan(0.5f * camera.yfov) * imageAspect));
  return out;
}

}  // namespace pa::gltf
