// uploadWorld: WorldScene -> pa::Renderer.
#include "port/scene_bridge/scene_bridge.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "port/q3formats/bsp/bsp_file.h"
#include "port/q3formats/shader/material.h"
#include "port/q3formats/world/world_lights.h"
#include "renderer/core/srgb.h"

namespace pa::bridge {
namespace {

/// Mean linear colour of an RGBA8 sRGB image (1 when empty).
glm::vec3 meanLinearColor(const q3::WorldImage& image) {
  if (image.rgba8.empty()) return glm::vec3(1.0f);
  glm::dvec3 sum(0.0);
  for (size_t i = 0; i + 3 < image.rgba8.size(); i += 4)
    sum += glm::dvec3(srgbToLinear(image.rgba8[i] / 255.0f), srgbToLinear(image.rgba8[i + 1] / 255.0f),
                      srgbToLinear(image.rgba8[i + 2] / 255.0f));
  return glm::vec3(sum / double(image.rgba8.size() / 4));
}

bool validImage(const q3::WorldImage& image) {
  return image.width > 0 && image.height > 0 && image.rgba8.size() == size_t(image.width) * image.height * 4;
}

AlphaMode alphaModeOf(q3::WorldAlphaMode mode) {
  switch (mode) {
    case q3::WorldAlphaMode::Opaque: return AlphaMode::Opaque;
    case q3::WorldAlphaMode::Mask: return AlphaMode::Mask;
    case q3::WorldAlphaMode::Blend: return AlphaMode::Blend;
    case q3::WorldAlphaMode::Additive:
    case q3::WorldAlphaMode::Filter: return AlphaMode::Additive;   // a see-through layer (StockLook::layerBlend)
  }
  return AlphaMode::Opaque;
}

/// q3map_surfacelight: constant radiance of the light's colour; shown through its texture
/// (glow stage, else base) scaled per channel so that the texture's mean emits the light's
/// colour (q3map2 lights with the light image's mean colour, uniform: the texture must not tint
/// it a second time). Camera rays see
/// that texture at its own brightness, as the stock renderer draws the stage
/// (MaterialDesc::seenEmission): the light a shader claims is no guide to its look, and light
/// recovery may scale it far down (a jump pad) or leave it far above white (lava).
void setSurfaceLightEmission(const q3::WorldScene& scene, const WorldHandles& handles, const q3::WorldMaterial& m,
                             float lightScale, MaterialDesc& desc) {
  int32_t shown = m.emissiveTexture >= 0 ? m.emissiveTexture : m.baseTexture;
  glm::vec3 radiance = m.emission * q3::surfaceLightRadiance(m.surfaceLight) * lightScale;
  if (shown >= 0 && size_t(shown) < scene.textures.size() && size_t(shown) < handles.textures.size() &&
      validImage(scene.textures[size_t(shown)].image)) {
    glm::vec3 mean = meanLinearColor(scene.textures[size_t(shown)].image);
    float luminance = 0.2126f * mean.r + 0.7152f * mean.g + 0.0722f * mean.b;
    if (luminance > 1e-3f && handles.textures[size_t(shown)] != kNoId) {
      desc.emissiveTexture = handles.textures[size_t(shown)];
      desc.seenEmission = glm::vec3(1.0f);
      radiance /= glm::max(mean, glm::vec3(1e-3f * luminance));
    }
  }
  desc.emission = radiance;
}

/// One model's vertex and index arrays, gathered from its meshes.
struct ModelArrays {
  std::vector<glm::vec3> positions, normals;
  std::vector<glm::vec2> uvs, lightmapUvs;
  std::vector<glm::vec4> colors;
  std::vector<uint32_t> indices;
};

}  // namespace

std::vector<uint8_t> colorShiftLightmap(const std::vector<uint8_t>& rgba8, int shift) {
  std::vector<uint8_t> out(rgba8.size());
  for (size_t i = 0; i + 3 < rgba8.size(); i += 4) {
    int r = rgba8[i] << shift, g = rgba8[i + 1] << shift, b = rgba8[i + 2] << shift;
    int peak = std::max({r, g, b});
    if (peak > 255) {
      r = r * 255 / peak;
      g = g * 255 / peak;
      b = b * 255 / peak;
    }
    out[i] = uint8_t(r);
    out[i + 1] = uint8_t(g);
    out[i + 2] = uint8_t(b);
    out[i + 3] = rgba8[i + 3];
  }
  return out;
}

MaterialDesc materialDesc(const q3::WorldScene& scene, const WorldHandles& handles, uint32_t material, int32_t lightmap,
                          float lightScale) {
  const q3::WorldMaterial& m = scene.materials.at(material);
  auto texture = [&](int32_t index) {
    return index >= 0 && size_t(index) < handles.textures.size() ? handles.textures[size_t(index)] : kNoId;
  };
  MaterialDesc desc;
  desc.baseTexture = texture(m.baseTexture);
  desc.baseColor = glm::clamp(m.baseColor, 0.0f, 1.0f);
  desc.alphaMode = alphaModeOf(m.alphaMode);
  desc.alphaCutoff = m.alphaCutoff;
  desc.alphaInvert = m.alphaInvert;
  desc.opacity = m.opacity;
  if (m.alphaMode == q3::WorldAlphaMode::Additive) {
    // The stage's source factor, as the framebuffer blends it (destination GL_ONE).
    switch (m.additiveSource) {
      case q3::BlendFactor::SrcAlpha:   // flames: the texture x its own alpha
        desc.stock.layerBlend = LayerBlend::Factors;
        desc.stock.layerSrcFactor = BlendFactor::SrcAlpha;
        desc.stock.layerDstFactor = BlendFactor::One;
        break;
      case q3::BlendFactor::DstColor:   // team decals: what is behind x (1 + the texture)
        desc.stock.layerBlend = LayerBlend::MultiplyAdd;
        break;
      default: break;   // One (and rarer factors): the texture added
    }
    desc.layerAlphaTest = m.additiveAlphaTest;
  } else if (m.alphaMode == q3::WorldAlphaMode::Filter) {   // multiplies what is behind (tinted glass)
    switch (m.filterBlend) {
      case q3::FilterBlend::Multiply: desc.stock.layerBlend = LayerBlend::Multiply; break;
      case q3::FilterBlend::MultiplyInverse: desc.stock.layerBlend = LayerBlend::MultiplyInverse; break;
      case q3::FilterBlend::Modulate2x: desc.stock.layerBlend = LayerBlend::Modulate2x; break;
    }
  }
  desc.stock.lightmapTexture =
      q3::lightmapPageOf(lightmap, handles.lightmaps.size()) >= 0 ? handles.lightmaps[size_t(lightmap)] : kNoId;
  desc.stock.useVertexLight = m.vertexLit || desc.stock.lightmapTexture == kNoId;
  if (m.vertexLit || desc.stock.lightmapTexture != kNoId) desc.stock.bakedLightScale = handles.bakedLightScale;
  // A lightmap stage that doubles what it multiplies (GL_DST_COLOR GL_SRC_COLOR).
  if (!desc.stock.useVertexLight) {
    desc.stock.lightmapStageScale = m.lightmapScale;
    desc.stock.bakedLightScale *= m.lightmapScale;
  }
  // Stock draws its dynamic-light pass on opaque (alpha-tested too) surfaces but sky and nodlight ones.
  const bool opaque = m.alphaMode == q3::WorldAlphaMode::Opaque || m.alphaMode == q3::WorldAlphaMode::Mask;
  desc.stock.takesDynamicLights =
      opaque && m.visible && !m.sky && !m.fog && !m.mirror && (m.surfaceFlags & q3::kSurfNoDlight) == 0;
  desc.mirror = m.mirror;
  desc.specular = m.specular;
  desc.twoSided = m.twoSided;
  desc.castsShadows = m.castsShadows;
  desc.visible = m.visible;
  desc.sky = m.sky;
  // uv animation at time 0 is the static scale; scrolling is applied per frame by the glue.
  desc.uvTransform = glm::mat3x2(glm::vec2(m.uvScale.x, 0.0f), glm::vec2(0.0f, m.uvScale.y), glm::vec2(0.0f));
  // tcGen environment base: the renderer reads it at the mirrored view direction (stock look in the
  // lightmap preset; the albedo under the glossy lobe `specular` in the traced presets).
  // A reflection under the surface's own texture added and lit with it (shiny trims: texture,
  // chrome, the texture again added, the lightmap): that texture on the mesh uvs is the base,
  // the chrome the glossy lobe's (`specular`); the Lightmap preset leaves the chrome's sheen out.
  if (m.baseReflects && m.reflectionOverlayTexture >= 0 && texture(m.reflectionOverlayTexture) != kNoId) {
    desc.baseTexture = texture(m.reflectionOverlayTexture);
    desc.uvTransform = glm::mat3x2(1.0f);   // the chrome's tcMods are not the texture's
  } else if (m.baseReflects) {
    desc.baseTexCoords = TexCoordSource::ReflectionSphere;
  }
  // The cover stage on the mesh uvs through its tcMods at time 0 (no installed map's cover moves;
  // one that did would hold its place).
  desc.coverTexture = texture(m.coverTexture);
  if (desc.coverTexture != kNoId) {
    const q3::UvAffine uv = q3::uvTransformAt(m.coverTcMods, 0.0);
    desc.coverUvTransform = glm::mat3x2(glm::vec2(uv.a, uv.c), glm::vec2(uv.b, uv.d), glm::vec2(uv.tx, uv.ty));
    desc.coverVertexAlpha = m.coverVertexAlpha;
    desc.coverAlphaCutoff = m.coverAlphaCutoff;
  }

  // Additive surface lights are drawn as additive surfaces: the renderer does not sample
  // additive surfaces as lights, so their light goes to surfaceLightProxy(). Those that add
  // their stages plainly (blendFunc add: teleporter rings, force fields) show their glow stage
  // as any additive surface does; flames (their own alpha) and water (a multiply-add) keep
  // their base alone, as the glow stage of either would not add as its blend does.
  const bool plainAdditive = m.alphaMode == q3::WorldAlphaMode::Additive && m.additiveSource == q3::BlendFactor::One;
  const bool layer = q3::seeThroughLayer(m.alphaMode);
  if (m.surfaceLight > 0.0f && !layer) {
    setSurfaceLightEmission(scene, handles, m, lightScale, desc);
  } else if ((m.surfaceLight <= 0.0f || plainAdditive) && m.emissiveTexture >= 0) {
    // Glow stages: the texture at its own brightness.
    desc.emissiveTexture = texture(m.emissiveTexture);
    desc.emission = glm::vec3(1.0f);
  }
  return desc;
}

std::optional<MaterialDesc> surfaceLightProxy(const q3::WorldScene& scene, const WorldHandles& handles,
                                              uint32_t material, float lightScale) {
  const q3::WorldMaterial& m = scene.materials.at(material);
  const bool layer = q3::seeThroughLayer(m.alphaMode);
  if (!(m.surfaceLight > 0.0f) || !layer || m.sky) return std::nullopt;
  MaterialDesc desc;
  desc.visible = false;        // never hit: sampled as a light only (NEE at full weight)
  desc.castsShadows = false;
  desc.twoSided = m.twoSided;
  desc.baseColor = glm::vec4(0.0f, 0.0f, 0.0f, 1.0f);
  setSurfaceLightEmission(scene, handles, m, lightScale, desc);
  return desc;
}

LightDesc lightDesc(const q3::WorldLight& light, float lightScale) {
  LightDesc desc;
  desc.position = light.position;
  desc.direction = light.direction;
  desc.color = light.color;
  desc.intensity = light.intensity * lightScale;
  switch (light.type) {
    case q3::WorldLightType::Point: desc.type = LightType::Point; break;
    case q3::WorldLightType::Spot:
      desc.type = LightType::Spot;
      desc.cosInnerAngle = light.cosInnerAngle;
      desc.cosOuterAngle = light.cosOuterAngle;
      break;
    case q3::WorldLightType::Sun:
      desc.type = LightType::Directional;
      desc.angularRadius = light.angularRadius;
      break;
  }
  if (light.linearFalloff) {
    desc.falloff = Falloff::Linear;
    desc.range = light.range;
  }
  return desc;
}

WorldHandles uploadWorld(const q3::WorldScene& scene, Renderer& renderer, const UploadOptions& options) {
  WorldHandles handles;
  handles.bakedLightScale = options.bakedLightScale;
  for (const q3::WorldTexture& t : scene.textures) {
    if (!validImage(t.image)) {
      handles.textures.push_back(kNoId);
      continue;
    }
    TextureDesc desc;
    desc.width = t.image.width;
    desc.height = t.image.height;
    desc.rgba8 = t.image.rgba8;
    desc.wrap = t.clamp ? TextureWrap::Clamp : TextureWrap::Repeat;
    handles.textures.push_back(renderer.addTexture(desc));
  }
  for (const q3::WorldImage& lm : scene.lightmaps) {
    if (!validImage(lm)) {
      handles.lightmaps.push_back(kNoId);
      continue;
    }
    // Images a shader stage names are drawn unbrightened, as the stock renderer draws them.
    const size_t index = handles.lightmaps.size();
    const bool asImage = index < scene.lightmapNamedByShader.size() && scene.lightmapNamedByShader[index];
    std::vector<uint8_t> shifted = colorShiftLightmap(lm.rgba8, asImage ? 0 : options.lightmapShift);
    TextureDesc desc;
    desc.width = lm.width;
    desc.height = lm.height;
    desc.rgba8 = shifted;
    desc.srgb = true;   // gamma-space multiply, see the header
    desc.wrap = TextureWrap::Clamp;
    desc.mipmaps = false;
    handles.lightmaps.push_back(renderer.addTexture(desc));
  }

  for (size_t modelIndex = 0; modelIndex < scene.models.size(); ++modelIndex) {
    const q3::WorldModel& model = scene.models[modelIndex];
    ModelArrays arrays;
    auto& [positions, normals, uvs, lightmapUvs, colors, indices] = arrays;
    std::vector<MaterialId> triangleMaterials;
    for (const q3::WorldMesh& mesh : model.meshes) {
      const size_t n = mesh.positions.size();
      if (n == 0 || mesh.normals.size() != n || mesh.uvs.size() != n || mesh.lightmapUvs.size() != n ||
          mesh.colors.size() != n || mesh.material >= scene.materials.size())
        continue;
      auto key = std::make_pair(mesh.material, mesh.lightmap);
      auto it = handles.materials.find(key);
      if (it == handles.materials.end())
        it = handles.materials
                 .emplace(key, renderer.addMaterial(materialDesc(scene, handles, mesh.material, mesh.lightmap, options.lightScale)))
                 .first;
      const bool vertexLight = scene.materials[mesh.material].vertexLit || mesh.lightmap < 0;
      const uint32_t base = uint32_t(positions.size());
      positions.insert(positions.end(), mesh.positions.begin(), mesh.positions.end());
      normals.insert(normals.end(), mesh.normals.begin(), mesh.normals.end());
      if (scene.materials[mesh.material].decal) {   // off the wall it lies on, towards its front
        for (size_t i = base; i < positions.size(); ++i) {
          const float length = glm::length(normals[i]);
          if (length > 0.0f && std::isfinite(length)) positions[i] += normals[i] * (kWorldDecalLift / length);
        }
      }
      uvs.insert(uvs.end(), mesh.uvs.begin(), mesh.uvs.end());
      lightmapUvs.insert(lightmapUvs.end(), mesh.lightmapUvs.begin(), mesh.lightmapUvs.end());
      for (const glm::vec4& c : mesh.colors) {
        // Vertex colours are baked light (gamma space) on vertex-lit surfaces; elsewhere white.
        colors.push_back(vertexLight ? glm::vec4(srgbToLinear(c.r), srgbToLinear(c.g), srgbToLinear(c.b), c.a)
                                     : glm::vec4(1.0f, 1.0f, 1.0f, c.a));
      }
      MaterialId proxy = kNoId;
      if (auto found = handles.lightProxies.find(mesh.material); found != handles.lightProxies.end()) {
        proxy = found->second;
      } else if (auto desc = surfaceLightProxy(scene, handles, mesh.material, options.lightScale)) {
        proxy = handles.lightProxies.emplace(mesh.material, renderer.addMaterial(*desc)).first->second;
      }
      for (size_t i = 0; i + 2 < mesh.indices.size(); i += 3) {
        uint32_t a = mesh.indices[i], b = mesh.indices[i + 1], c = mesh.indices[i + 2];
        if (a >= n || b >= n || c >= n) continue;
        indices.insert(indices.end(), {base + a, base + b, base + c});
        triangleMaterials.push_back(it->second);
        ++handles.triangles;
        if (proxy != kNoId) {   // the same triangle again, as the invisible emitter
          indices.insert(indices.end(), {base + a, base + b, base + c});
          triangleMaterials.push_back(proxy);
        }
      }
    }
    if (indices.empty()) {
      handles.modelMeshes.push_back(kNoId);
      handles.modelInstances.push_back(kNoId);
      continue;
    }
    MeshId id = renderer.addMesh(meshDescOf(arrays, triangleMaterials));
    handles.modelMeshes.push_back(id);
    InstanceDesc instance;
    instance.mesh = id;
    handles.modelInstances.push_back(renderer.addInstance(instance));
  }

  if (options.lights)
    for (const q3::WorldLight& light : scene.lights)
      if (light.intensity > 0.0f && std::isfinite(light.intensity))
        handles.lights.push_back(renderer.addLight(lightDesc(light, options.lightScale)));

  handles.sky = skyDesc(scene, handles, options);
  handles.fog = fogVolumes(scene, options.lightScale);
  return handles;
}

void showSkyAndFog(const WorldHandles& handles, Renderer& renderer) {
  renderer.setSky(handles.sky);
  renderer.setFogVolumes(handles.fog.volumes);
}

FogVolumes fogVolumes(const q3::WorldScene& scene, float lightScale) {
  constexpr float kMinDepthForOpaque = 1.0f;   // R_LoadFogs clamps the distance to 1
  FogVolumes out;
  for (const q3::WorldFog& fog : scene.fogs) {
    if (fog.planes.empty()) continue;
    out.planes.push_back(fog.planes);
  }
  size_t next = 0;
  for (const q3::WorldFog& fog : scene.fogs) {
    if (fog.planes.empty()) continue;
    FogVolumeDesc desc;
    desc.planes = out.planes[next++];
    const glm::vec3 display = glm::clamp(fog.color, 0.0f, 1.0f);
    desc.color = glm::vec3(srgbToLinear(display.r), srgbToLinear(display.g), srgbToLinear(display.b)) * lightScale;
    desc.depthForOpaque = std::isfinite(fog.depthForOpaque) ? std::max(fog.depthForOpaque, kMinDepthForOpaque)
                                                            : kMinDepthForOpaque;
    out.volumes.push_back(desc);
  }
  return out;
}

SkyDesc skyDesc(const q3::WorldScene& scene, const WorldHandles& handles, const UploadOptions& options) {
  SkyDesc sky;
  sky.color = scene.sky.color;
  sky.intensity = options.skyIntensity;
  // The worldspawn's ambient light and floor, on every surface whatever the lights (not the sky's
  // light: they do not scale with skyIntensity).
  sky.ambientRadiance = scene.ambientLight * (q3::ambientLightRadiance(1.0f) * options.lightScale);
  sky.minimumRadiance = scene.minimumLight * (q3::ambientLightRadiance(1.0f) * options.lightScale);
  bool allFaces = true;
  glm::vec3 faceMean(0.0f);
  for (size_t f = 0; f < 6; ++f) {
    const int32_t t = scene.sky.faces[f];
    const bool valid = t >= 0 && size_t(t) < handles.textures.size() && handles.textures[size_t(t)] != kNoId;
    sky.faces[f] = valid ? handles.textures[size_t(t)] : kNoId;
    allFaces = allFaces && valid;
    if (valid) faceMean += meanLinearColor(scene.textures[size_t(t)].image) / 6.0f;
  }
  // What q3map2 lit the map with through the sky: its dome of sky-light suns as a uniform
  // radiance; a sky shader with only q3map_sun lit it by the sun alone (an analytic light).
  const float skyLight = q3::skyLightRadiance(scene.sky.skyLight, scene.sky.skyLightIterations);
  const float compiled = q3::surfaceLightRadiance(scene.sky.surfaceLight) + skyLight;
  if (allFaces) {
    sky.color = glm::vec3(1.0f);   // the box shows as drawn...
    const float shown = 0.2126f * faceMean.r + 0.7152f * faceMean.g + 0.0722f * faceMean.b;
    if (skyLight > 0.0f) {         // ...and lights as compiled, however dark it looks
      sky.lightingScale = skyLight * options.lightScale / std::max(shown, 1e-4f);
    } else if (scene.sky.sunLit && !(scene.sky.surfaceLight > 0.0f)) {
      sky.lightingScale = 0.0f;
    }
    // A box with q3map_surfacelight keeps its look as its light: on oa_dm6 (space box,
    // q3map_surfacelight 100) the q3map2 surface-light radiance is ~40x brighter than the
    // baked lightmaps, the box as drawn within 4x.
    return sky;
  }
  sky.faces.fill(kNoId);
  if (compiled > 0.0f) {
    // q3map2 lit the map through the sky surfaces as area lights of this radiance.
    glm::vec3 hue = scene.sky.color;
    const float peak = std::max({hue.r, hue.g, hue.b});
    hue = peak > 0.0f ? hue / peak : glm::vec3(1.0f);
    sky.color = hue * compiled * options.lightScale;
  } else if (scene.sky.sunLit) {
    sky.lightingScale = 0.0f;
  }
  return sky;
}

glm::vec3 skyLightingRadiance(const q3::WorldScene& scene, const UploadOptions& options) {
  WorldHandles faces;   // stand-in ids: skyDesc only asks which textures exist
  for (const q3::WorldTexture& t : scene.textures) faces.textures.push_back(validImage(t.image) ? TextureId(0) : kNoId);
  const SkyDesc sky = skyDesc(scene, faces, options);
  glm::vec3 shown = sky.color;
  if (std::none_of(sky.faces.begin(), sky.faces.end(), [](TextureId id) { return id == kNoId; })) {
    shown = glm::vec3(0.0f);
    for (int32_t t : scene.sky.faces) shown += meanLinearColor(scene.textures[size_t(t)].image) / 6.0f * sky.color;
  }
  return shown * sky.intensity * sky.lightingScale;
}

Camera cameraFromSpawn(const q3::WorldCamera& spawn, float aspect, float fovX) {
  Camera camera;
  camera.origin = spawn.eye;
  camera.forward = spawn.forward;
  camera.left = spawn.left;
  camera.up = spawn.up;
  camera.fovX = std::clamp(fovX, 1.0f, 170.0f);
  float safeAspect = aspect > 1e-3f && std::isfinite(aspect) ? aspect : 4.0f / 3.0f;
  camera.fovY = glm::degrees(2.0f * std::atan(std::tan(glm::radians(camera.fovX) / 2.0f) / safeAspect));
  return camera;
}

}  // namespace pa::bridge
