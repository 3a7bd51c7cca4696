// WorldScene -> binary glTF 2.0.
#include "assets_converter/gltf_export.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <optional>
#include <utility>

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/mat3x3.hpp>

#include "assets_converter/glb_builder.h"
#include "port/q3formats/bsp/bsp_file.h"
#include "port/q3formats/shader/material.h"
#include "port/q3formats/shader/shader_time.h"
#include "port/q3formats/world/world_lights.h"
#include "renderer/core/srgb.h"

namespace pa::converter {
namespace {

/// The script words of a wave.
const char* waveName(q3::WaveFunc func) {
  switch (func) {
    case q3::WaveFunc::Sin: return "sin";
    case q3::WaveFunc::Triangle: return "triangle";
    case q3::WaveFunc::Square: return "square";
    case q3::WaveFunc::Sawtooth: return "sawtooth";
    case q3::WaveFunc::InverseSawtooth: return "inversesawtooth";
    case q3::WaveFunc::Noise: return "noise";
  }
  return "sin";
}

nlohmann::json waveJson(const q3::WaveForm& w) {
  return {{"func", waveName(w.func)}, {"base", w.base}, {"amplitude", w.amplitude}, {"phase", w.phase},
          {"frequency", w.frequency}};
}

/// A stage's tcMods in script order, as extras (what a viewer needs to animate them).
nlohmann::json tcModsJson(const std::vector<q3::TcMod>& mods) {
  nlohmann::json out = nlohmann::json::array();
  for (const q3::TcMod& m : mods) {
    switch (m.kind) {
      case q3::TcModKind::Scroll: out.push_back({{"tcMod", "scroll"}, {"speed", {m.scroll[0], m.scroll[1]}}}); break;
      case q3::TcModKind::Scale: out.push_back({{"tcMod", "scale"}, {"scale", {m.scroll[0], m.scroll[1]}}}); break;
      case q3::TcModKind::Rotate: out.push_back({{"tcMod", "rotate"}, {"degreesPerSecond", m.degreesPerSecond}}); break;
      case q3::TcModKind::Stretch: out.push_back({{"tcMod", "stretch"}, {"wave", waveJson(m.wave)}}); break;
      case q3::TcModKind::Turb: out.push_back({{"tcMod", "turb"}, {"wave", waveJson(m.wave)}}); break;
      case q3::TcModKind::Transform:
        out.push_back({{"tcMod", "transform"},
                       {"matrix", {m.matrix[0], m.matrix[1], m.matrix[2], m.matrix[3]}},
                       {"translate", {m.translate[0], m.translate[1]}}});
        break;
      case q3::TcModKind::EntityTranslate: out.push_back({{"tcMod", "entityTranslate"}}); break;
    }
  }
  return out;
}

/// KHR_texture_transform of an affine uv map (uv' = T R S uv; rotation r gives u' = cos r sx u +
/// sin r sy v, v' = -sin r sx u + cos r sy v); nullopt when it is the identity or has a shear no
/// offset / rotation / scale can express.
std::optional<nlohmann::json> textureTransformJson(const q3::UvAffine& m) {
  const float sx = std::hypot(m.a, m.c);
  if (!(sx > 1e-6f)) return std::nullopt;
  const float rotation = std::atan2(-m.c, m.a);
  const float sy = m.b * std::sin(rotation) + m.d * std::cos(rotation);
  const float tolerance = 1e-5f * std::max({1.0f, std::fabs(m.a), std::fabs(m.b), std::fabs(m.c), std::fabs(m.d)});
  // Columns (a, c) and (b, d) of a rotation x scale are orthogonal and rebuild the map.
  if (std::fabs(m.a * m.b + m.c * m.d) > tolerance * std::max(1.0f, sx * std::fabs(sy))) return std::nullopt;
  if (std::fabs(std::sin(rotation) * sy - m.b) > tolerance || std::fabs(std::cos(rotation) * sy - m.d) > tolerance)
    return std::nullopt;
  nlohmann::json out = nlohmann::json::object();
  if (m.tx != 0.0f || m.ty != 0.0f) out["offset"] = {m.tx, m.ty};
  if (std::fabs(rotation) > 1e-7f) out["rotation"] = rotation;
  if (std::fabs(sx - 1.0f) > 1e-7f || std::fabs(sy - 1.0f) > 1e-7f) out["scale"] = {sx, sy};
  if (out.empty()) return std::nullopt;
  return out;
}

using nlohmann::json;

/// How a texture's alpha channel is rewritten for a glTF alpha mode.
enum class AlphaVariant : uint8_t {
  AsIs,            ///< Unchanged.
  Inverted,        ///< 255 - alpha: Quake's alphaFunc LT128 as a glTF MASK.
  FromBrightness,  ///< alpha = max(r, g, b): additive blending approximated with BLEND.
};

constexpr uint32_t kSamplerRepeat = 0;
constexpr uint32_t kSamplerClamp = 1;
constexpr float kQuakeFovY = 73.74f;   // cg_fov 90 at 4:3
// Environment-mapped base stages become a smooth metal tinted by the image: fully metallic so
// the tint colours the reflection, roughness 0.25 because Quake's sphere maps are soft blurs
// of a room, not mirror images (the same roughness, metallic 0, with a texture added over them).
constexpr float kReflectiveMetallic = 1.0f;
constexpr float kReflectiveRoughness = 0.25f;

json vec3Json(const glm::vec3& v) { return json::array({v.x, v.y, v.z}); }

json quatJson(const glm::mat3& basis) {
  glm::quat q = glm::normalize(glm::quat_cast(basis));
  return json::array({q.x, q.y, q.z, q.w});
}

/// Rotation whose local -Z points along `dir` (glTF lights and cameras look down -Z).
glm::mat3 basisLookingAlong(const glm::vec3& dir, const glm::vec3& upHint) {
  glm::vec3 back = -glm::normalize(dir);
  glm::vec3 up = upHint - back * glm::dot(upHint, back);
  if (glm::length(up) < 1e-4f) up = std::abs(back.y) < 0.9f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0);
  up = glm::normalize(up - back * glm::dot(up, back));
  glm::vec3 right = glm::cross(up, back);
  return glm::mat3(right, up, back);
}

/// Mean colour of an RGBA8 sRGB image in linear RGB (every texel weighs the same).
glm::vec3 averageLinearColor(const q3::WorldImage& image) {
  const size_t texels = size_t(image.width) * image.height;
  if (texels == 0 || image.rgba8.size() != texels * 4) return glm::vec3(1.0f);
  auto linear = [](uint8_t value) { return pa::srgbToLinear(value / 255.0); };
  double sum[3] = {0.0, 0.0, 0.0};
  for (size_t i = 0; i < texels; ++i)
    for (int c = 0; c < 3; ++c) sum[c] += linear(image.rgba8[i * 4 + size_t(c)]);
  return glm::vec3(float(sum[0] / double(texels)), float(sum[1] / double(texels)), float(sum[2] / double(texels)));
}

glm::vec3 unitOrFallback(glm::vec3 v, const glm::vec3& fallback) {
  float len = glm::length(v);
  return (std::isfinite(len) && len > 1e-6f) ? v / len : fallback;
}

class Exporter {
 public:
  Exporter(const q3::WorldScene& scene, const ExportOptions& options)
      : scene_(scene), options_(options), glb_(options.generator) {}

  std::vector<std::byte> run(ExportStats* stats) {
    glb_.append("samplers", {{"magFilter", 9729}, {"minFilter", 9987}, {"wrapS", 10497}, {"wrapT", 10497}});
    glb_.append("samplers", {{"magFilter", 9729}, {"minFilter", 9729}, {"wrapS", 33071}, {"wrapT", 33071}});

    json rootChildren = json::array();
    for (size_t m = 0; m < scene_.models.size(); ++m)
      if (auto node = modelNode(m)) rootChildren.push_back(*node);
    if (options_.lights)
      if (auto node = lightsNode()) rootChildren.push_back(*node);
    if (options_.cameras)
      if (auto node = camerasNode()) rootChildren.push_back(*node);

    json root = {{"name", scene_.mapName.empty() ? std::string("map") : scene_.mapName},
                 {"children", rootChildren},
                 {"extras", sceneExtras()}};
    if (rootChildren.empty()) root.erase("children");
    uint32_t rootIndex = glb_.append("nodes", std::move(root));
    glb_.append("scenes", {{"name", scene_.mapName}, {"nodes", json::array({rootIndex})}});
    glb_.json()["scene"] = 0;

    if (glb_.json().contains("textures") == false) glb_.json().erase("samplers");
    std::vector<std::byte> bytes = glb_.finish();
    stats_.nodes = uint32_t(glb_.json()["nodes"].size());
    stats_.bytes = bytes.size();
    if (stats) *stats = stats_;
    return bytes;
  }

 private:
  uint32_t texture(int32_t worldTexture, AlphaVariant variant) {
    auto key = std::make_pair(worldTexture, variant);
    if (auto it = textures_.find(key); it != textures_.end()) return it->second;
    const q3::WorldTexture& tex = scene_.textures.at(size_t(worldTexture));
    std::vector<uint8_t> pixels = tex.image.rgba8;
    std::string name = tex.resolvedPath.empty() ? tex.requestedPath : tex.resolvedPath;
    if (variant == AlphaVariant::Inverted) {
      for (size_t i = 3; i < pixels.size(); i += 4) pixels[i] = uint8_t(255 - pixels[i]);
      name += "#alpha-inverted";
    } else if (variant == AlphaVariant::FromBrightness) {
      for (size_t i = 0; i + 3 < pixels.size(); i += 4) pixels[i + 3] = std::max({pixels[i], pixels[i + 1], pixels[i + 2]});
      name += "#alpha-from-brightness";
    }
    uint32_t image = glb_.addPngImage(tex.image.width, tex.image.height, pixels, name);
    ++stats_.images;
    uint32_t index = glb_.append("textures", {{"source", image}, {"sampler", tex.clamp ? kSamplerClamp : kSamplerRepeat}, {"name", name}});
    textures_.emplace(key, index);
    return index;
  }

  bool textureUsable(int32_t worldTexture) const {
    if (worldTexture < 0 || size_t(worldTexture) >= scene_.textures.size()) return false;
    const auto& image = scene_.textures[size_t(worldTexture)].image;
    return image.width > 0 && image.height > 0 && image.rgba8.size() == size_t(image.width) * image.height * 4;
  }

  std::optional<uint32_t> lightmapTexture(int32_t lightmap) {
    if (!options_.lightmaps || q3::lightmapPageOf(lightmap, scene_.lightmaps.size()) < 0) return std::nullopt;
    if (auto it = lightmaps_.find(lightmap); it != lightmaps_.end()) return it->second;
    const q3::WorldImage& image = scene_.lightmaps[size_t(lightmap)];
    if (image.width == 0 || image.rgba8.size() != size_t(image.width) * image.height * 4) return std::nullopt;
    std::string name = "lightmap " + std::to_string(lightmap);
    uint32_t source = glb_.addPngImage(image.width, image.height, image.rgba8, name);
    ++stats_.images;
    uint32_t index = glb_.append("textures", {{"source", source}, {"sampler", kSamplerClamp}, {"name", name}});
    lightmaps_.emplace(lightmap, index);
    return index;
  }

  /// Whether a material's surfaces are written at all.
  bool exported(const q3::WorldMaterial& m) const {
    if (!m.visible) return false;   // fog-only surfaces are invisible; lava with fogParms is drawn
    if (m.sky && !options_.skySurfaces) return false;
    return true;
  }

  uint32_t material(uint32_t index) {
    if (auto it = materials_.find(index); it != materials_.end()) return it->second;
    const q3::WorldMaterial& m = scene_.materials.at(index);
    json pbr = {{"metallicFactor", 0.0}, {"roughnessFactor", m.specular > 0.0f ? 0.35 : 1.0}};
    glm::vec4 base = m.baseColor;
    json out = {{"name", m.shaderName}, {"doubleSided", m.twoSided}};
    // A base stage that is an environment map (tcGen environment: chrome, glass sheen) is a
    // reflection image read at the mirrored view direction; laid on the mesh UVs it would show
    // as a stretched photograph. Where the shader adds the surface's own texture over the
    // reflection (shiny floors and trims), that texture is the base of a smooth dielectric;
    // otherwise the surface becomes a reflective tint: the image's mean colour x the stage
    // colour on a smooth metal. Any viewer's environment lighting supplies the reflection.
    // A texture blended over the reflection by its alpha (the cover: painted metal over chrome)
    // is what the surface shows too.
    const bool reflective = m.baseReflects;
    const int32_t overlay = textureUsable(m.reflectionOverlayTexture) ? m.reflectionOverlayTexture : m.coverTexture;
    const bool overlaid = reflective && textureUsable(overlay);
    int32_t shownTexture = m.baseTexture;
    if (overlaid) {
      shownTexture = overlay;
      pbr["roughnessFactor"] = kReflectiveRoughness;
    } else if (reflective) {
      if (textureUsable(m.baseTexture) && !scene_.textures[size_t(m.baseTexture)].isFallback)
        base *= glm::vec4(averageLinearColor(scene_.textures[size_t(m.baseTexture)].image), 1.0f);
      pbr["metallicFactor"] = kReflectiveMetallic;
      pbr["roughnessFactor"] = kReflectiveRoughness;
    }
    const bool hasTexture = (!reflective || overlaid) && textureUsable(shownTexture);

    AlphaVariant variant = AlphaVariant::AsIs;
    switch (m.alphaMode) {
      case q3::WorldAlphaMode::Opaque:
        break;
      case q3::WorldAlphaMode::Mask:
        out["alphaMode"] = "MASK";
        out["alphaCutoff"] = m.alphaInvert ? 1.0f - m.alphaCutoff : m.alphaCutoff;
        if (m.alphaInvert) variant = AlphaVariant::Inverted;
        break;
      case q3::WorldAlphaMode::Blend:
      case q3::WorldAlphaMode::Filter:   // glTF has no multiplying mode: blended by its alpha
        out["alphaMode"] = "BLEND";
        base.a *= m.opacity;
        break;
      case q3::WorldAlphaMode::Additive:
        // glTF has no additive mode: emit the texture and let its brightness be its opacity.
        out["alphaMode"] = "BLEND";
        variant = AlphaVariant::FromBrightness;
        if (hasTexture) out["emissiveTexture"] = {{"index", texture(shownTexture, variant)}};
        out["emissiveFactor"] = vec3Json(glm::clamp(glm::vec3(base), 0.0f, 1.0f));
        base = glm::vec4(0.0f, 0.0f, 0.0f, base.a);
        break;
    }
    if (hasTexture) pbr["baseColorTexture"] = {{"index", texture(shownTexture, variant)}};
    // tcMods: the look at time 0 as KHR_texture_transform (static scale / rotate / transform, a
    // stretch's first size); animated ones also go to extras.quake.tcMods. A reflective base's
    // tcMods move its sphere map, not the texture shown (the overlay has its own stage).
    std::optional<json> uvTransform;
    if (hasTexture && !reflective && !m.tcMods.empty()) uvTransform = textureTransformJson(q3::uvTransformAt(m.tcMods, 0.0));
    if (uvTransform) {
      glb_.useExtension("KHR_texture_transform");
      pbr["baseColorTexture"]["extensions"]["KHR_texture_transform"] = *uvTransform;
      if (out.contains("emissiveTexture")) out["emissiveTexture"]["extensions"]["KHR_texture_transform"] = *uvTransform;
    }
    base = glm::clamp(base, 0.0f, 1.0f);
    pbr["baseColorFactor"] = json::array({base.r, base.g, base.b, base.a});
    out["pbrMetallicRoughness"] = std::move(pbr);

    if (m.surfaceLight > 0.0f && glm::length(m.emission) > 0.0f) {
      glm::vec3 color = glm::clamp(m.emission, 0.0f, 1.0f);
      float peak = std::max({color.r, color.g, color.b});
      if (peak > 0.0f) color /= peak;
      out["emissiveFactor"] = vec3Json(color);
      if (textureUsable(m.emissiveTexture))
        out["emissiveTexture"] = {{"index", texture(m.emissiveTexture, AlphaVariant::AsIs)}};
      float strength = q3::surfaceLightRadiance(m.surfaceLight);
      if (strength != 1.0f) {
        out["extensions"]["KHR_materials_emissive_strength"] = {{"emissiveStrength", strength}};
        glb_.useExtension("KHR_materials_emissive_strength");
      }
    }

    json quake = {{"shader", m.shaderName},
                  {"surfaceFlags", m.surfaceFlags},
                  {"contentFlags", m.contentFlags},
                  {"implicitShader", !m.fromScript}};
    if (m.alphaMode == q3::WorldAlphaMode::Additive) quake["blend"] = "add";
    if (m.alphaMode == q3::WorldAlphaMode::Filter) quake["blend"] = "filter";
    if (m.surfaceLight > 0.0f) quake["surfaceLight"] = m.surfaceLight;
    if (m.sky) quake["sky"] = true;
    // A lightmap stage that doubles what it multiplies (GL_DST_COLOR GL_SRC_COLOR).
    if (m.lightmapScale != 1.0f) quake["lightmapStageScale"] = m.lightmapScale;
    if (m.mirror) quake["mirror"] = true;
    if (m.uvScrollPerSecond != glm::vec2(0.0f)) quake["uvScrollPerSecond"] = {m.uvScrollPerSecond.x, m.uvScrollPerSecond.y};
    if (!reflective && q3::tcModsAnimate(m.tcMods)) quake["tcMods"] = tcModsJson(m.tcMods);
    if (hasTexture) quake["texture"] = scene_.textures[size_t(shownTexture)].resolvedPath;
    if (reflective && textureUsable(m.baseTexture))
      quake["environmentMap"] = scene_.textures[size_t(m.baseTexture)].resolvedPath;
    out["extras"] = {{"quake", std::move(quake)}};

    uint32_t gltfIndex = glb_.append("materials", std::move(out));
    ++stats_.materials;
    materials_.emplace(index, gltfIndex);
    return gltfIndex;
  }

  std::optional<json> primitive(const q3::WorldMesh& mesh) {
    const size_t n = mesh.positions.size();
    if (n == 0 || mesh.indices.size() < 3 || mesh.material >= scene_.materials.size()) return std::nullopt;
    if (!exported(scene_.materials[mesh.material])) return std::nullopt;

    // Keep only whole, in-range triangles.
    std::vector<uint32_t> indices;
    indices.reserve(mesh.indices.size());
    for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
      uint32_t a = mesh.indices[t], b = mesh.indices[t + 1], c = mesh.indices[t + 2];
      if (a >= n || b >= n || c >= n || a == b || b == c || a == c) continue;
      indices.insert(indices.end(), {a, b, c});
    }
    if (indices.empty()) return std::nullopt;

    std::vector<glm::vec3> positions(n), normals(n);
    for (size_t i = 0; i < n; ++i) {
      const glm::vec3& p = mesh.positions[i];
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) return std::nullopt;
      positions[i] = toGltfPosition(p, options_.metresPerUnit);
      glm::vec3 normal = i < mesh.normals.size() ? mesh.normals[i] : glm::vec3(0.0f, 0.0f, 1.0f);
      normals[i] = unitOrFallback(toGltfDirection(normal), glm::vec3(0.0f, 1.0f, 0.0f));
    }
    json attributes = {{"POSITION", glb_.addVec3(positions)}, {"NORMAL", glb_.addVec3(normals)}};
    auto finiteUvs = [](std::vector<glm::vec2> uvs) {
      for (auto& uv : uvs)
        if (!std::isfinite(uv.x) || !std::isfinite(uv.y)) uv = glm::vec2(0.0f);
      return uvs;
    };
    if (mesh.uvs.size() == n) attributes["TEXCOORD_0"] = glb_.addVec2(finiteUvs(mesh.uvs));
    json prim = {{"attributes", json::object()}, {"material", material(mesh.material)}};
    std::optional<uint32_t> lightmap;
    if (mesh.lightmapUvs.size() == n) lightmap = lightmapTexture(mesh.lightmap);
    if (lightmap) {
      uint32_t lightmapUvs = glb_.addVec2(finiteUvs(mesh.lightmapUvs));
      if (!attributes.contains("TEXCOORD_0")) attributes["TEXCOORD_0"] = lightmapUvs;
      attributes["TEXCOORD_1"] = lightmapUvs;
      prim["extras"] = {{"lightmapTexture", *lightmap}, {"lightmapTexCoord", 1}};
    }
    prim["attributes"] = std::move(attributes);
    prim["indices"] = glb_.addIndices(indices);
    stats_.triangles += indices.size() / 3;
    ++stats_.primitives;
    return prim;
  }

  std::optional<uint32_t> modelNode(size_t modelIndex) {
    const q3::WorldModel& model = scene_.models[modelIndex];
    json primitives = json::array();
    for (const auto& mesh : model.meshes)
      if (auto prim = primitive(mesh)) primitives.push_back(std::move(*prim));
    if (primitives.empty()) return std::nullopt;
    std::string name = "world";
    if (modelIndex != 0) name = std::string(1, '*').append(std::to_string(modelIndex));
    uint32_t mesh = glb_.append("meshes", {{"name", name}, {"primitives", std::move(primitives)}});
    json node = {{"name", name}, {"mesh", mesh}};
    if (!model.bounds.empty())
      node["extras"] = {{"quake", {{"model", modelIndex},
                                   {"mins", vec3Json(model.bounds.mins)},
                                   {"maxs", vec3Json(model.bounds.maxs)}}}};
    return glb_.append("nodes", std::move(node));
  }

  std::optional<uint32_t> lightsNode() {
    json children = json::array();
    const float area = options_.metresPerUnit * options_.metresPerUnit;
    for (const q3::WorldLight& light : scene_.lights) {
      if (!(light.intensity > 0.0f) || !std::isfinite(light.intensity)) continue;
      json desc = {{"name", light.source}, {"color", vec3Json(glm::clamp(light.color, 0.0f, 1.0f))}};
      json node = {{"name", light.source}};
      glm::vec3 dir = unitOrFallback(toGltfDirection(light.direction), glm::vec3(0.0f, -1.0f, 0.0f));
      switch (light.type) {
        case q3::WorldLightType::Point:
        case q3::WorldLightType::Spot:
          // W/sr per Quake unit^2 -> per metre^2: intensity scales with length^2.
          desc["intensity"] = light.intensity * area;
          if (light.range > 0.0f) desc["range"] = light.range * options_.metresPerUnit;
          node["translation"] = vec3Json(toGltfPosition(light.position, options_.metresPerUnit));
          if (light.type == q3::WorldLightType::Point) {
            desc["type"] = "point";
          } else {
            desc["type"] = "spot";
            float outer = std::clamp(std::acos(std::clamp(light.cosOuterAngle, -1.0f, 1.0f)), 1e-3f,
                                     std::numbers::pi_v<float> / 2.0f);
            float inner = std::clamp(std::acos(std::clamp(light.cosInnerAngle, -1.0f, 1.0f)), 0.0f, outer * 0.999f);
            desc["spot"] = {{"innerConeAngle", inner}, {"outerConeAngle", outer}};
            node["rotation"] = quatJson(basisLookingAlong(dir, glm::vec3(0, 1, 0)));
          }
          break;
        case q3::WorldLightType::Sun:
          desc["type"] = "directional";
          desc["intensity"] = light.intensity;   // irradiance: independent of the length unit
          node["rotation"] = quatJson(basisLookingAlong(dir, glm::vec3(0, 1, 0)));
          break;
      }
      desc["extras"] = {{"quake", {{"light", light.quakeIntensity}, {"linear", light.linearFalloff}}}};
      auto& list = glb_.json()["extensions"]["KHR_lights_punctual"]["lights"];
      if (list.is_null()) list = json::array();
      list.push_back(std::move(desc));
      node["extensions"] = {{"KHR_lights_punctual", {{"light", list.size() - 1}}}};
      children.push_back(glb_.append("nodes", std::move(node)));
      ++stats_.lights;
    }
    if (children.empty()) return std::nullopt;
    glb_.useExtension("KHR_lights_punctual");
    return glb_.append("nodes", {{"name", "lights"}, {"children", std::move(children)}});
  }

  std::optional<uint32_t> camerasNode() {
    json children = json::array();
    for (const q3::WorldCamera& cam : scene_.cameras) {
      glm::vec3 forward = unitOrFallback(toGltfDirection(cam.forward), glm::vec3(0, 0, -1));
      glm::vec3 up = unitOrFallback(toGltfDirection(cam.up), glm::vec3(0, 1, 0));
      float fovX = std::clamp(cam.fovX, 1.0f, 170.0f);
      // Quake's fov_x is for a 4:3 screen; glTF wants the vertical angle.
      float yfov = 2.0f * std::atan(std::tan(glm::radians(fovX) / 2.0f) * 0.75f);
      if (cam.fovX == 90.0f) yfov = glm::radians(kQuakeFovY);
      uint32_t camera = glb_.append("cameras", {{"name", cam.name},
                                                {"type", "perspective"},
                                                {"perspective", {{"yfov", yfov}, {"znear", 4.0f * options_.metresPerUnit}}}});
      children.push_back(glb_.append("nodes", {{"name", cam.name},
                                               {"camera", camera},
                                               {"translation", vec3Json(toGltfPosition(cam.eye, options_.metresPerUnit))},
                                               {"rotation", quatJson(basisLookingAlong(forward, up))}}));
      ++stats_.cameras;
    }
    if (children.empty()) return std::nullopt;
    return glb_.append("nodes", {{"name", "cameras"}, {"children", std::move(children)}});
  }

  json sceneExtras() const {
    json sky = {{"shader", scene_.sky.shaderName}, {"color", vec3Json(scene_.sky.color)}};
    json faces = json::array();
    for (int32_t face : scene_.sky.faces)
      faces.push_back(face >= 0 && size_t(face) < scene_.textures.size() ? json(scene_.textures[size_t(face)].resolvedPath) : json(nullptr));
    sky["faces+X-X+Y-Y+Z-Z"] = std::move(faces);
    json fogs = json::array();
    for (const q3::WorldFog& fog : scene_.fogs) {
      json planes = json::array();   // the fog brush: [nx, ny, nz, d], inside where n . p <= d
      for (const glm::vec4& p : fog.planes) planes.push_back(json::array({p.x, p.y, p.z, p.w}));
      fogs.push_back({{"shader", fog.shaderName},
                      {"mins", vec3Json(fog.bounds.mins)},
                      {"maxs", vec3Json(fog.bounds.maxs)},
                      {"planes", std::move(planes)},
                      {"color", vec3Json(fog.color)},
                      {"depthForOpaque", fog.depthForOpaque}});
    }
    return {{"quake", {{"map", scene_.mapName},
                       {"metresPerUnit", options_.metresPerUnit},
                       {"axes", "(x, y, z) quake -> (x, z, -y) glTF"},
                       {"lightmapOverbrightScale", q3::kLightmapOverbrightScale},
                       {"sky", std::move(sky)},
                       {"fogs", std::move(fogs)},
                       {"ambientLight", vec3Json(scene_.ambientLight)},    // worldspawn _ambient x _color
                       {"minimumLight", vec3Json(scene_.minimumLight)},    // worldspawn _minlight x _color
                       {"warnings", scene_.warnings.size()}}}};
  }

  const q3::WorldScene& scene_;
  const ExportOptions& options_;
  GlbBuilder glb_;
  ExportStats stats_;
  std::map<std::pair<int32_t, AlphaVariant>, uint32_t> textures_;
  std::map<int32_t, uint32_t> lightmaps_;
  std::map<uint32_t, uint32_t> materials_;
};

}  // namespace

std::vector<std::byte> exportGlb(const q3::WorldScene& scene, const ExportOptions& options, ExportStats* stats) {
  return Exporter(scene, options).run(stats);
}

}  // namespace pa::converter
