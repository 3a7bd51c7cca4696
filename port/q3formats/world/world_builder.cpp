// assembleWorldScene: materials, textures, meshes, sky, sun, fogs from a SourceWorld.
#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <map>
#include <string>
#include <numbers>
#include <tuple>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "port/q3formats/bsp/bsp_file.h"
#include "port/q3formats/shader/material.h"
#include "port/q3formats/shader/shader_library.h"
#include "port/q3formats/world/world_external_lightmaps.h"
#include "port/q3formats/world/world_lights.h"
#include "port/q3formats/world/world_source.h"
#include "port/q3formats/world/world_textures.h"

namespace q3 {
namespace {

/// One RGBA8 texel holding the mean of each channel of RGBA8 `texels` (empty when there are none).
std::vector<uint8_t> meanTexel(const std::vector<uint8_t>& texels) {
  const size_t count = texels.size() / 4;
  if (count == 0) return {};
  std::array<double, 4> sum{};
  for (size_t i = 0; i < count * 4; ++i) sum[i % 4] += texels[i];
  std::vector<uint8_t> mean(4);
  for (size_t c = 0; c < 4; ++c) mean[c] = static_cast<uint8_t>(std::lround(sum[c] / double(count)));
  return mean;
}

bool finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

glm::vec3 normalisedColor(glm::vec3 c) {
  float peak = std::max({c.r, c.g, c.b});
  return peak > 0.0f ? c / peak : glm::vec3(1.0f);
}

WorldAlphaMode alphaModeOf(AlphaMode mode) {
  switch (mode) {
    case AlphaMode::Opaque: return WorldAlphaMode::Opaque;
    case AlphaMode::Mask: return WorldAlphaMode::Mask;
    case AlphaMode::Blend: return WorldAlphaMode::Blend;
    case AlphaMode::Additive: return WorldAlphaMode::Additive;
    case AlphaMode::Multiply: return WorldAlphaMode::Filter;
  }
  return WorldAlphaMode::Opaque;
}

class SceneAssembler {
 public:
  SceneAssembler(const SourceWorld& source, const ShaderLibrary& shaders, const FileLoader& loadFile,
                 const WorldBuildOptions& options)
      : source_(source), shaders_(shaders), options_(options),
        textures_(loadFile, options.loadTextures, scene_.textures, scene_.warnings),
        externalLightmaps_(textures_, scene_.lightmaps, scene_.warnings) {}

  WorldScene run() {
    scene_.mapName = source_.mapName;
    scene_.lightGrid = source_.lightGrid;
    for (const auto& rgb : source_.lightmaps) {
      WorldImage image{128, 128, std::vector<uint8_t>(128 * 128 * 4)};
      for (size_t i = 0; i < 128 * 128; ++i) {
        image.rgba8[i * 4 + 0] = rgb[i * 3 + 0];
        image.rgba8[i * 4 + 1] = rgb[i * 3 + 1];
        image.rgba8[i * 4 + 2] = rgb[i * 3 + 2];
        image.rgba8[i * 4 + 3] = 255;
      }
      scene_.lightmaps.push_back(std::move(image));
    }
    // q3map2 -external: an empty lump, the lightmap numbers count lm_NNNN images beside the map.
    const bool numbered = std::any_of(source_.surfaces.begin(), source_.surfaces.end(),
                                      [](const SourceSurface& s) { return s.lightmap >= 0; });
    if (scene_.lightmaps.empty() && numbered && !source_.externalLightmapFolder.empty())
      externalLightmaps_.addNumbered(source_.externalLightmapFolder);
    numberedLightmaps_ = scene_.lightmaps.size();
    scene_.models.resize(std::max<size_t>(1, source_.modelBounds.size()));
    for (size_t m = 0; m < source_.modelBounds.size(); ++m) scene_.models[m].bounds = source_.modelBounds[m];

    for (const SourceSurface& surface : source_.surfaces) addSurface(surface);
    for (auto& model : scene_.models)
      std::stable_sort(model.meshes.begin(), model.meshes.end(),
                       [](const WorldMesh& a, const WorldMesh& b) { return std::tie(a.material, a.lightmap) < std::tie(b.material, b.lightmap); });

    addEntityLightsAndCameras(source_.entities, scene_);
    addFogs();
    if (skyMaterial_) addSky(*skyMaterial_);
    return std::move(scene_);
  }

 private:
  /// Material index of a BSP shader (created on first use).
  uint32_t material(uint32_t shaderIndex, bool hasLightmap) {
    auto key = std::make_pair(shaderIndex, hasLightmap);
    if (auto it = materials_.find(key); it != materials_.end()) return it->second;
    const SourceShader& lump = source_.shaders.at(shaderIndex);
    WorldMaterial m;
    m.shaderName = lump.name;
    m.surfaceFlags = lump.surfaceFlags;
    m.contentFlags = lump.contentFlags;

    auto exists = [this](const std::string& path) { return textures_.exists(path); };
    std::optional<ShaderDef> def =
        shaders_.resolve(lump.name, hasLightmap ? ImplicitLighting::Lightmap : ImplicitLighting::Vertex, exists);
    if (!def) {
      scene_.warnings.push_back("shader '" + lump.name + "': no script and no image, using the fallback texture");
      m.baseTexture = textures_.get(lump.name, false, /*warnIfMissing=*/false);
      m.vertexLit = !hasLightmap;
      m.visible = (lump.surfaceFlags & (kSurfNodraw | kSurfHint | kSurfSkip)) == 0;
      m.sky = (lump.surfaceFlags & kSurfSky) != 0;
      m.twoSided = false;
    } else {
      fillFromShader(*def, hasLightmap, m);
    }
    uint32_t index = uint32_t(scene_.materials.size());
    scene_.materials.push_back(std::move(m));
    materials_.emplace(key, index);
    return index;
  }

  void fillFromShader(const ShaderDef& def, bool hasLightmap, WorldMaterial& m) {
    const MaterialInfo info = deriveMaterial(def);
    m.fromScript = !def.implicit;
    std::string base = info.baseTexture.empty() && !info.animFrames.empty() ? info.animFrames.front() : info.baseTexture;
    if (!base.empty() && base[0] != '$' && base[0] != '*') m.baseTexture = textures_.get(base, info.clampUv);
    if (m.baseTexture >= 0 && !info.baseModulations.empty() && info.animFrames.empty())
      m.baseTexture = modulatedBase(def.name, m.baseTexture, info.baseModulations);
    m.baseColor = glm::vec4(info.constColor[0], info.constColor[1], info.constColor[2], 1.0f);
    m.alphaMode = alphaModeOf(info.alphaMode);
    m.alphaCutoff = info.alphaCutoff;
    m.alphaInvert = info.alphaInvert;
    m.additiveSource = info.additiveSource;
    m.additiveAlphaTest = info.additiveAlphaTest;
    m.filterBlend = info.filterBlend;
    m.twoSided = info.twoSided;
    m.decal = info.polygonOffset;
    m.sky = info.sky || (m.surfaceFlags & kSurfSky) != 0;
    m.fog = info.fogVolume;
    m.mirror = info.portal;
    // A fog shader whose first stage is solid (lava with fogParms) draws its surface like any
    // other; the cloud layers some fog shaders filter or blend onto the fog's surface are left
    // out (the fog volume itself gives the look), as are fog-only shaders (no stages).
    const bool solidStage = info.alphaMode == AlphaMode::Opaque || info.alphaMode == AlphaMode::Mask;
    m.visible = !info.invisible && (!m.fog || solidStage) &&
                (m.surfaceFlags & (kSurfNodraw | kSurfHint | kSurfSkip)) == 0;
    m.lightmapScale = info.lightmapScale;
    if (!info.lightmapImage.empty()) m.lightmap = externalLightmaps_.get(info.lightmapImage);
    if (m.lightmap >= 0) {   // drawn by its shader stage as an image
      scene_.lightmapNamedByShader.resize(scene_.lightmaps.size(), false);
      scene_.lightmapNamedByShader[size_t(m.lightmap)] = true;
    }
    const bool lightmapped = hasLightmap || m.lightmap >= 0;
    m.vertexLit = info.lighting == LightingMode::Vertex || (!lightmapped && info.lighting == LightingMode::Lightmap) ||
                  (m.surfaceFlags & kSurfNolightmap) != 0;
    m.castsShadows = !m.sky && !seeThroughLayer(m.alphaMode) && m.visible;
    m.specular = info.environmentMapped ? 0.5f : 0.0f;
    m.baseReflects = info.baseReflects;
    if (m.baseReflects && !info.reflectionOverlay.empty() && textures_.exists(info.reflectionOverlay))
      m.reflectionOverlayTexture = textures_.get(info.reflectionOverlay, false);
    m.tcMods = info.uvAnimation;
    for (const TcMod& mod : info.uvAnimation) {
      if (mod.kind == TcModKind::Scroll) m.uvScrollPerSecond += glm::vec2(mod.scroll[0], mod.scroll[1]);
      if (mod.kind == TcModKind::Scale) m.uvScale *= glm::vec2(mod.scroll[0], mod.scroll[1]);
    }
    if (!info.glowTextures.empty()) {
      // A missing glow image would glow as the fallback checker: leave the glow out instead.
      const std::string& glow = info.glowTextures.front();
      if (textures_.exists(glow))
        m.emissiveTexture = textures_.get(glow, info.glowClampUv);
      else
        scene_.warnings.push_back("shader '" + def.name + "': glow texture '" + glow + "' not found, glow left out");
    }
    if (!info.coverTexture.empty() && m.baseTexture >= 0) {
      // A missing cover image would cover the base with the fallback checker: left out instead.
      if (textures_.exists(info.coverTexture)) {
        m.coverTexture = textures_.get(info.coverTexture, info.coverClampUv);
        m.coverTcMods = info.coverTcMods;
        m.coverVertexAlpha = info.coverVertexAlpha;
        m.coverAlphaCutoff = info.coverAlphaCutoff;
      } else {
        scene_.warnings.push_back("shader '" + def.name + "': cover image '" + info.coverTexture +
                                  "' not found, left out");
      }
    }
    if (info.surfaceLight > 0.0f) {
      m.surfaceLight = info.surfaceLight;
      glm::vec3 color(1.0f);
      if (info.hasLightColor) {
        color = glm::vec3(info.lightColor[0], info.lightColor[1], info.lightColor[2]);
      } else {
        // The first light image that loads (q3map2's order); none: white, never the fallback checker.
        for (const std::string& image : info.lightImageCandidates)
          if (textures_.exists(image)) {
            color = textures_.averageColor(textures_.get(image, false));
            break;
          }
      }
      m.emission = normalisedColor(glm::max(color, glm::vec3(0.0f)));
      if (!m.visible) m.castsShadows = false;
    } else if (m.emissiveTexture >= 0) {
      m.emission = glm::vec3(1.0f);
    }
    if (m.sky && !skyMaterial_) skyMaterial_ = std::make_pair(def, info);
    if (def.sun && !sunShaderSeen_) {
      sunShaderSeen_ = true;
      addSun(def);
    }
  }

  void addSun(const ShaderDef& def) {
    const SunParms& sun = *def.sun;
    if (!(sun.intensity > 0.0f)) return;
    WorldLight light;
    light.type = WorldLightType::Sun;
    float azimuth = glm::radians(sun.degrees), elevation = glm::radians(sun.elevation);
    glm::vec3 towardSun(std::cos(azimuth) * std::cos(elevation), std::sin(azimuth) * std::cos(elevation), std::sin(elevation));
    light.direction = -towardSun;
    light.color = normalisedColor(glm::vec3(sun.color[0], sun.color[1], sun.color[2]));
    light.quakeIntensity = sun.intensity;
    light.intensity = sunIrradiance(sun.intensity);
    light.angularRadius = glm::radians(std::max(0.0f, sun.deviation));
    light.source = "q3map_sun in " + def.name;
    scene_.lights.push_back(light);
  }

  /// The base texture multiplied by the shader's later filter stages (MaterialInfo::
  /// baseModulations), as a texture of its own shared by equal requests; `base` when none applies.
  int32_t modulatedBase(const std::string& shader, int32_t base, const std::vector<BaseModulation>& modulations) {
    std::string key = std::to_string(base);
    for (const BaseModulation& mod : modulations)
      key += " x" + std::to_string(mod.scale) + (mod.meanOnly ? " mean " : " ") + mod.texture;
    if (const auto found = modulatedTextures_.find(key); found != modulatedTextures_.end()) return found->second;
    WorldTexture out = scene_.textures.at(size_t(base));
    bool applied = false;
    if (out.isFallback) return base;
    for (const BaseModulation& mod : modulations) {
      if (!textures_.exists(mod.texture)) {
        scene_.warnings.push_back("shader '" + shader + "': filter stage image '" + mod.texture + "' not found, left out");
        continue;
      }
      const WorldImage& by = scene_.textures.at(size_t(textures_.get(mod.texture, false))).image;
      if (mod.meanOnly) {
        // One texel of the image's mean colour (its own uvs: the pattern does not line up).
        const std::vector<uint8_t> mean = meanTexel(by.rgba8);
        if (mean.empty()) continue;
        if (modulateBase(out.image.rgba8, out.image.width, out.image.height, mean, 1, 1, mod.scale)) {
          out.requestedPath += " x mean of " + mod.texture;
          applied = true;
        }
      } else if (modulateBase(out.image.rgba8, out.image.width, out.image.height, by.rgba8, by.width, by.height,
                              mod.scale)) {
        out.requestedPath += " x " + mod.texture;
        applied = true;
      }
    }
    int32_t index = base;
    if (applied) {
      scene_.textures.push_back(std::move(out));
      index = int32_t(scene_.textures.size() - 1);
    }
    modulatedTextures_.emplace(key, index);
    return index;
  }

  /// A new texture holding texture `index` turned by 180 degrees (texel order reversed).
  int32_t turnedCopy(int32_t index) {
    WorldTexture turned = scene_.textures.at(size_t(index));
    std::vector<uint8_t>& texels = turned.image.rgba8;
    const size_t count = texels.size() / 4;
    for (size_t i = 0; i < count / 2; ++i)
      std::swap_ranges(texels.begin() + std::ptrdiff_t(4 * i), texels.begin() + std::ptrdiff_t(4 * i + 4),
                       texels.begin() + std::ptrdiff_t(4 * (count - 1 - i)));
    turned.requestedPath += " (turned 180)";
    scene_.textures.push_back(std::move(turned));
    return int32_t(scene_.textures.size() - 1);
  }

  void addSky(const std::pair<ShaderDef, MaterialInfo>& sky) {
    const auto& [def, info] = sky;
    scene_.sky.shaderName = def.name;
    scene_.sky.cloudHeight = info.skyBox.cloudHeight;
    glm::vec3 sum(0.0f);
    int count = 0;
    // Faces in cube order +X, -X, +Y, -Y, +Z, -Z as the stock renderer shows them (MaterialInfo
    // SkyBox: _rt _lf _bk _ft _up _dn, the _up image turned by 180 degrees).
    // A missing far box ("skyParms full 512 -" is a common idiom) is skipped by the engine,
    // which then draws only the cloud layers: no warning, no fallback faces.
    for (size_t f = 0; f < 6; ++f) {
      const std::string& face = info.skyBox.farFaces[f];
      if (face.empty() || !textures_.exists(face)) continue;
      scene_.sky.faces[f] = textures_.get(face, true);
      if (info.skyBox.turned180[f]) scene_.sky.faces[f] = turnedCopy(scene_.sky.faces[f]);
      sum += textures_.averageColor(scene_.sky.faces[f]);
      ++count;
    }
    if (count == 0) {
      // Cloud layers only: the average of the base texture stands in for the sky colour.
      for (const WorldMaterial& m : scene_.materials)
        if (m.sky && m.shaderName == def.name && m.baseTexture >= 0) {
          sum = textures_.averageColor(m.baseTexture);
          count = 1;
          break;
        }
    }
    scene_.sky.color = count > 0 ? sum / float(count) : glm::vec3(0.0f);
    scene_.sky.surfaceLight = info.surfaceLight;
    scene_.sky.sunLit = def.sun.has_value();
    for (const CompilerDirective& d : def.compilerDirectives) {
      if (d.keyword != "q3map_skylight") continue;
      float value = 0.0f;
      int iterations = 0;
      if (d.args.size() < 2 || std::from_chars(d.args[0].data(), d.args[0].data() + d.args[0].size(), value).ec != std::errc() ||
          std::from_chars(d.args[1].data(), d.args[1].data() + d.args[1].size(), iterations).ec != std::errc() ||
          !std::isfinite(value) || value < 0.0f) {
        scene_.warnings.push_back("sky shader '" + def.name + "': malformed q3map_skylight, ignored");
        continue;
      }
      scene_.sky.skyLight = value;
      scene_.sky.skyLightIterations = std::clamp(iterations, 0, 1024);
    }
  }

  void addFogs() {
    for (const SourceFog& fog : source_.fogs) {
      WorldFog out;
      out.shaderName = fog.shaderName;
      out.bounds = fog.bounds;
      for (const glm::vec4& plane : fog.planes) {
        const float length = glm::length(glm::vec3(plane));
        if (std::isfinite(length) && std::isfinite(plane.w) && length > 1e-6f) out.planes.push_back(plane / length);
      }
      if (out.planes.size() != fog.planes.size())
        scene_.warnings.push_back("fog '" + fog.shaderName + "': " + std::to_string(fog.planes.size() - out.planes.size()) +
                                  " invalid brush planes dropped");
      if (out.planes.empty()) scene_.warnings.push_back("fog '" + fog.shaderName + "': brush has no planes, fog not drawn");
      if (const ShaderDef* def = shaders_.find(fog.shaderName); def && def->fog) {
        out.color = glm::vec3(def->fog->color[0], def->fog->color[1], def->fog->color[2]);
        out.depthForOpaque = def->fog->depthForOpaque;
      } else {
        scene_.warnings.push_back("fog shader '" + fog.shaderName + "': no fogParms, default grey");
      }
      scene_.fogs.push_back(std::move(out));
    }
  }

  void addSurface(const SourceSurface& s) {
    const size_t n = s.positions.size();
    if (n == 0 || s.indices.size() < 3) return;
    if (s.shader >= source_.shaders.size() || s.normals.size() != n || s.uvs.size() != n || s.lightmapUvs.size() != n ||
        s.colors.size() != n) {
      scene_.warnings.push_back("surface with inconsistent arrays skipped (shader " + std::to_string(s.shader) + ")");
      return;
    }
    for (const glm::vec3& p : s.positions)
      if (!finite(p)) {
        scene_.warnings.push_back("surface with non-finite vertex skipped (shader '" + source_.shaders[s.shader].name + "')");
        return;
      }
    // Lightmap: the image the shader names, else the one the surface's number selects (one
    // rule: lightmapPageOf), else vertex light as the engine does, with one warning per map.
    const int32_t page = lightmapPageOf(s.lightmap, numberedLightmaps_);
    uint32_t mat = material(s.shader, page >= 0);
    const WorldMaterial& m = scene_.materials[mat];
    const bool engineNumber = s.lightmap < 0 && s.lightmap >= kLightmap2D;
    if (page < 0 && m.lightmap < 0 && !engineNumber && !lightmapNumberWarned_) {
      lightmapNumberWarned_ = true;
      scene_.warnings.push_back("lightmap number " + std::to_string(s.lightmap) + " selects none of the " +
                                std::to_string(numberedLightmaps_) +
                                " lightmaps (external lightmaps missing?): such surfaces drawn vertex-lit");
    }
    if (!m.visible && m.surfaceLight <= 0.0f && !options_.keepInvisible) return;
    const int32_t lightmap = m.vertexLit ? -1 : m.lightmap >= 0 ? m.lightmap : page;

    // Whole, in-range, non-degenerate triangles.
    std::vector<uint32_t> triangles;
    triangles.reserve(s.indices.size());
    for (size_t t = 0; t + 2 < s.indices.size(); t += 3) {
      uint32_t a = s.indices[t], b = s.indices[t + 1], c = s.indices[t + 2];
      if (a >= n || b >= n || c >= n || a == b || b == c || a == c) continue;
      triangles.insert(triangles.end(), {a, b, c});
    }
    if (triangles.empty()) return;

    uint32_t modelIndex = s.model < scene_.models.size() ? s.model : 0;
    WorldModel& model = scene_.models[modelIndex];
    auto key = std::make_tuple(modelIndex, mat, lightmap);
    auto it = meshes_.find(key);
    if (it == meshes_.end()) {
      it = meshes_.emplace(key, model.meshes.size()).first;
      WorldMesh mesh;
      mesh.material = mat;
      mesh.lightmap = lightmap;
      model.meshes.push_back(std::move(mesh));
    }
    WorldMesh& mesh = model.meshes[it->second];
    const uint32_t base = uint32_t(mesh.positions.size());
    for (uint32_t index : triangles) mesh.indices.push_back(base + index);
    for (size_t v = 0; v < n; ++v) {
      mesh.positions.push_back(s.positions[v]);
      glm::vec3 normal = s.normals[v];
      float len = glm::length(normal);
      mesh.normals.push_back(std::isfinite(len) && len > 1e-6f ? normal / len : glm::vec3(0.0f, 0.0f, 1.0f));
      glm::vec2 uv = s.uvs[v], lm = s.lightmapUvs[v];
      mesh.uvs.push_back(std::isfinite(uv.x) && std::isfinite(uv.y) ? uv : glm::vec2(0.0f));
      mesh.lightmapUvs.push_back(std::isfinite(lm.x) && std::isfinite(lm.y) ? lm : glm::vec2(0.0f));
      mesh.colors.push_back(s.colors[v]);
      mesh.bounds.extend(s.positions[v]);
    }
    ++mesh.sourceSurfaces;
  }

  const SourceWorld& source_;
  const ShaderLibrary& shaders_;
  const WorldBuildOptions& options_;
  WorldScene scene_;
  TextureCache textures_;
  ExternalLightmaps externalLightmaps_;
  size_t numberedLightmaps_ = 0;   ///< lightmaps lightmap numbers select (internal, else lm_NNNN)
  std::map<std::pair<uint32_t, bool>, uint32_t> materials_;
  std::map<std::tuple<uint32_t, uint32_t, int32_t>, size_t> meshes_;
  std::optional<std::pair<ShaderDef, MaterialInfo>> skyMaterial_;
  std::map<std::string, int32_t> modulatedTextures_;   ///< modulatedBase() results by request
  bool sunShaderSeen_ = false;
  bool lightmapNumberWarned_ = false;
};

}  // namespace

WorldScene assembleWorldScene(const SourceWorld& source, const ShaderLibrary& shaders, const FileLoader& loadFile,
                              const WorldBuildOptions& options) {
  return SceneAssembler(source, shaders, loadFile, options).run();
}

}  // namespace q3
