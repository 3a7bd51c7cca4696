// glTF images/samplers/textures/materials -> GltfImage/GltfTexture/GltfMaterial.
#include "renderer/gltf_io/gltf_materials.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace pa::gltf::detail {
namespace {

[[noreturn]] void fail(const std::string& message) { throw std::runtime_error(message); }

/// Minimal JSON text of a tinygltf value (for non-string extras).
void writeJson(const tinygltf::Value& value, std::ostringstream& out, int depth) {
  if (depth > 64) {
    out << "null";
    return;
  }
  if (value.IsString()) {
    out << '"';
    for (char c : value.Get<std::string>()) {
      if (c == '"' || c == '\\') out << '\\' << c;
      else if (static_cast<unsigned char>(c) < 0x20) out << ' ';
      else out << c;
    }
    out << '"';
  } else if (value.IsBool()) {
    out << (value.Get<bool>() ? "true" : "false");
  } else if (value.IsInt()) {
    out << value.Get<int>();
  } else if (value.IsNumber()) {
    out << value.GetNumberAsDouble();
  } else if (value.IsArray()) {
    out << '[';
    for (size_t i = 0; i < value.ArrayLen(); ++i) {
      if (i) out << ',';
      writeJson(value.Get(static_cast<int>(i)), out, depth + 1);
    }
    out << ']';
  } else if (value.IsObject()) {
    out << '{';
    bool first = true;
    for (const std::string& key : value.Keys()) {
      if (!first) out << ',';
      first = false;
      out << '"' << key << "\":";
      writeJson(value.Get(key), out, depth + 1);
    }
    out << '}';
  } else {
    out << "null";
  }
}

float finiteOr(double value, float fallback) {
  return std::isfinite(value) ? static_cast<float>(value) : fallback;
}

/// Index of a texture reference, checked against the texture count.
uint32_t textureIndex(int index, size_t textureCount, const std::string& what) {
  if (index < 0) return kNone;
  if (static_cast<size_t>(index) >= textureCount)
    fail(what + ".index " + std::to_string(index) + " out of range (file has " + std::to_string(textureCount) +
         " textures)");
  return static_cast<uint32_t>(index);
}

/// KHR_texture_transform as uv' = M * (u, v, 1) (translation * rotation * scale).
glm::mat3x2 textureTransform(const tinygltf::ExtensionMap& extensions) {
  const auto it = extensions.find("KHR_texture_transform");
  if (it == extensions.end() || !it->second.IsObject()) return glm::mat3x2(1.0f);
  auto pair = [&](const char* key, glm::vec2 fallback) {
    const tinygltf::Value& v = it->second.Get(key);
    if (!v.IsArray() || v.ArrayLen() != 2 || !v.Get(0).IsNumber() || !v.Get(1).IsNumber()) return fallback;
    return glm::vec2(finiteOr(v.Get(0).GetNumberAsDouble(), fallback.x), finiteOr(v.Get(1).GetNumberAsDouble(), fallback.y));
  };
  const glm::vec2 offset = pair("offset", glm::vec2(0.0f));
  const glm::vec2 scale = pair("scale", glm::vec2(1.0f));
  const tinygltf::Value& rotationValue = it->second.Get("rotation");
  const float rotation = rotationValue.IsNumber() ? finiteOr(rotationValue.GetNumberAsDouble(), 0.0f) : 0.0f;
  const float c = std::cos(rotation), s = std::sin(rotation);
  return glm::mat3x2(glm::vec2(c * scale.x, -s * scale.x), glm::vec2(s * scale.y, c * scale.y), offset);
}

void convertImages(const tinygltf::Model& model, GltfScene& scene) {
  for (size_t i = 0; i < model.images.size(); ++i) {
    const tinygltf::Image& source = model.images[i];
    GltfImage image;
    image.name = !source.name.empty() ? source.name : source.uri;
    const uint64_t expected = static_cast<uint64_t>(std::max(source.width, 0)) * std::max(source.height, 0) * 4;
    if (source.width > 0 && source.height > 0 && source.bits == 8 && source.component == 4 &&
        source.image.size() == expected) {
      image.width = static_cast<uint32_t>(source.width);
      image.height = static_cast<uint32_t>(source.height);
      image.rgba8 = source.image;
    }
    scene.images.push_back(std::move(image));
  }
}

void convertTextures(const tinygltf::Model& model, GltfScene& scene) {
  for (size_t i = 0; i < model.textures.size(); ++i) {
    const tinygltf::Texture& source = model.textures[i];
    const std::string what = "textures[" + std::to_string(i) + "]";
    GltfTexture texture;
    if (source.source >= static_cast<int>(model.images.size()))
      fail(what + ".source " + std::to_string(source.source) + " out of range (file has " +
           std::to_string(model.images.size()) + " images)");
    if (source.source >= 0 && scene.images[static_cast<size_t>(source.source)].width > 0)
      texture.image = static_cast<uint32_t>(source.source);
    if (source.sampler >= static_cast<int>(model.samplers.size()))
      fail(what + ".sampler " + std::to_string(source.sampler) + " out of range (file has " +
           std::to_string(model.samplers.size()) + " samplers)");
    if (source.sampler >= 0) {
      const tinygltf::Sampler& sampler = model.samplers[static_cast<size_t>(source.sampler)];
      if (sampler.wrapS == TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE && sampler.wrapT == TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE)
        texture.wrap = Wrap::Clamp;
      else if (sampler.wrapS == TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT ||
               sampler.wrapT == TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT)
        scene.warnings.push_back(what + ": MIRRORED_REPEAT approximated by REPEAT");
    }
    scene.textures.push_back(texture);
  }
}

}  // namespace

namespace {

/// Adds `value` under `key`; objects are flattened into "key.member" entries.
void flattenExtras(const tinygltf::Value& value, const std::string& key, int depth, Extras& out) {
  if (value.IsObject() && depth < 16) {
    for (const std::string& member : value.Keys())
      flattenExtras(value.Get(member), key.empty() ? member : key + "." + member, depth + 1, out);
  } else if (value.IsString()) {
    out[key] = value.Get<std::string>();
  } else {
    std::ostringstream text;
    writeJson(value, text, 0);
    out[key] = text.str();
  }
}

}  // namespace

Extras convertExtras(const tinygltf::Value& extras) {
  Extras out;
  if (extras.IsObject()) flattenExtras(extras, "", 0, out);
  return out;
}

void convertMaterials(const tinygltf::Model& model, const LoadOptions& options, GltfScene& scene) {
  convertImages(model, scene);
  convertTextures(model, scene);
  for (size_t i = 0; i < model.materials.size(); ++i) {
    const tinygltf::Material& source = model.materials[i];
    const std::string what = "materials[" + std::to_string(i) + "]";
    GltfMaterial material;
    material.name = source.name;
    const auto& pbr = source.pbrMetallicRoughness;
    if (pbr.baseColorFactor.size() != 4) fail(what + ".baseColorFactor needs 4 values");
    for (int c = 0; c < 4; ++c) material.baseColorFactor[c] = finiteOr(pbr.baseColorFactor[static_cast<size_t>(c)], 1.0f);
    material.baseColorTexture = textureIndex(pbr.baseColorTexture.index, scene.textures.size(),
                                             what + ".baseColorTexture");
    if (material.baseColorTexture != kNone) {
      if (pbr.baseColorTexture.texCoord != 0)
        scene.warnings.push_back(what + ": baseColorTexture uses TEXCOORD_" +
                                 std::to_string(pbr.baseColorTexture.texCoord) + ", TEXCOORD_0 used instead");
      material.baseColorUvTransform = textureTransform(pbr.baseColorTexture.extensions);
      if (scene.textures[material.baseColorTexture].image == kNone) material.baseColorTexture = kNone;
    }
    material.metallic = std::clamp(finiteOr(pbr.metallicFactor, 1.0f), 0.0f, 1.0f);
    material.roughness = std::clamp(finiteOr(pbr.roughnessFactor, 1.0f), 0.0f, 1.0f);
    if (source.alphaMode == "MASK") material.alphaMode = AlphaMode::Mask;
    else if (source.alphaMode == "BLEND") material.alphaMode = AlphaMode::Blend;
    else if (source.alphaMode != "OPAQUE" && !source.alphaMode.empty())
      scene.warnings.push_back(what + ": unknown alphaMode \"" + source.alphaMode + "\", OPAQUE used");
    material.alphaCutoff = std::max(finiteOr(source.alphaCutoff, 0.5f), 0.0f);
    material.doubleSided = source.doubleSided;

    float emissiveStrength = 1.0f;
    const auto strength = source.extensions.find("KHR_materials_emissive_strength");
    if (strength != source.extensions.end()) {
      const tinygltf::Value& value = strength->second.Get("emissiveStrength");
      if (value.IsNumber()) emissiveStrength = std::max(finiteOr(value.GetNumberAsDouble(), 1.0f), 0.0f);
    }
    if (source.emissiveFactor.size() == 3)
      for (int c = 0; c < 3; ++c)
        material.emissive[c] = std::max(finiteOr(source.emissiveFactor[static_cast<size_t>(c)], 0.0f), 0.0f) *
                               emissiveStrength * options.lightUnitScale;
    material.emissiveTexture = textureIndex(source.emissiveTexture.index, scene.textures.size(),
                                            what + ".emissiveTexture");
    if (material.emissiveTexture != kNone && scene.textures[material.emissiveTexture].image == kNone)
      material.emissiveTexture = kNone;
    material.extras = convertExtras(source.extras);
    scene.materials.push_back(std::move(material));
  }
}

}  // namespace pa::gltf::detail
