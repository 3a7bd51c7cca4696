// glTF data -> MaterialDesc / LightDesc / SkyDesc / Camera (see the mapping in gltf_mapping.h).
#include "renderer/gltf_io/gltf_mapping.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include <glm/trigonometric.hpp>

namespace pa::gltf {
namespace {

/// Dielectric reflectance at normal incidence (IOR 1.5).
constexpr float kDielectricSpecular = 0.04f;

/// True when `key` (or assets_converter's "quake.<key>") is set to true/1/yes.
bool flagSet(const Extras& extras, const std::string& key) {
  for (const std::string& name : {key, "quake." + key}) {
    const auto it = extras.find(name);
    if (it != extras.end() && (it->second == "true" || it->second == "1" || it->second == "yes")) return true;
  }
  return false;
}

/// The value of the first of `keys` present, or nullptr.
const std::string* findExtra(const Extras& extras, std::initializer_list<const char*> keys) {
  for (const char* key : keys)
    if (const auto it = extras.find(key); it != extras.end()) return &it->second;
  return nullptr;
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
  const std::string* blend = findExtra(material.extras, {"quake.blend"});
  if (flagSet(material.extras, "additive") || (blend && *blend == "add")) desc.alphaMode = pa::AlphaMode::Additive;
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
  if (const std::string* color = findExtra(sceneExtras, {"sky_color", "quake.sky.color"})) parseVec3(*color, sky.color);
  if (const auto it = sceneExtras.find("sky_intensity"); it != sceneExtras.end()) {
    char* end = nullptr;
    const float intensity = std::strtof(it->second.c_str(), &end);
    if (end != it->second.c_str() && std::isfinite(intensity) && intensity >= 0.0f) sky.intensity = intensity;
  }
  return sky;
}

float lightmapStageScale(const GltfMaterial& material) {
  const std::string* text = findExtra(material.extras, {"quake.lightmapStageScale"});
  if (!text) return 1.0f;
  char* end = nullptr;
  const float scale = std::strtof(text->c_str(), &end);
  return end != text->c_str() && std::isfinite(scale) && scale > 0.0f && scale <= 4.0f ? scale : 1.0f;
}

float lightmapBrightness(const Extras& sceneExtras) {
  const std::string* text = findExtra(sceneExtras, {"lightmap_scale", "quake.lightmapOverbrightScale"});
  if (!text) return 1.0f;
  char* end = nullptr;
  const float scale = std::strtof(text->c_str(), &end);
  return end != text->c_str() && std::isfinite(scale) && scale > 0.0f && scale <= 64.0f ? scale : 1.0f;
}

std::vector<uint8_t> brightenLightmap(std::span<const uint8_t> rgba8, float scale) {
  std::vector<uint8_t> out(rgba8.size());
  for (size_t i = 0; i + 3 < rgba8.size(); i += 4) {
    float r = rgba8[i] * scale, g = rgba8[i + 1] * scale, b = rgba8[i + 2] * scale;
    const float peak = std::max({r, g, b});
    if (peak > 255.0f) {
      const float fit = 255.0f / peak;
      r *= fit, g *= fit, b *= fit;
    }
    out[i] = static_cast<uint8_t>(std::lround(r));
    out[i + 1] = static_cast<uint8_t>(std::lround(g));
    out[i + 2] = static_cast<uint8_t>(std::lround(b));
    out[i + 3] = 255;
  }
  return out;
}

Camera toCamera(const GltfCamera& camera, float imageAspect) {
  Camera out;
  out.origin = camera.origin;
  out.forward = camera.forward;
  out.left = camera.left;
  out.up = camera.up;
  out.fovY = glm::degrees(camera.yfov);
  out.fovX = glm::degrees(fovAcross(camera.yfov, imageAspect));
  return out;
}

}  // namespace pa::gltf
