#include "renderer/scene/integrator/lightmap_compositor.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "renderer/scene/integrator/display_composite.h"
#include "renderer/scene/integrator/integrator.h"
#include "renderer/scene/integrator/trace_common.h"
#include "renderer/scene/lights/stock_dlights.h"
#include "renderer/scene/media/fog_volumes.h"

namespace pa {

namespace {

using trace::kInfinity;

/// The camera ray cone's footprint on a surface over the one pixel OpenGL measures a texture's
/// level of detail by (the larger of its x and y texel derivatives): 2^-0.25, fitted on the
/// frames of engine_fidelity_lightmap against opengl1 (mean PSNR with GL_LINEAR_MIPMAP_NEAREST:
/// 31.54 dB at 1, 31.68 at 2^-0.25, 31.67 at 2^-0.5; with trilinear levels 31.66, 31.79, 31.78).
constexpr float kRasterFootprintScale = 0.8408964f;

/// A fog layer to blend over what lies behind it on display values, as the stock renderer's
/// framebuffer does.
struct DisplayFog {
  glm::vec3 radianceInFront;
  float opacity;
  glm::vec3 color;
};

/// dot(a, b) as a chain of fused multiply-adds, x first: the rounding of the Direct/Path
/// integrator's dot products, so that both measure a hit's facing alike (and its footprint, but
/// for kRasterFootprintScale).
float fusedDot(const glm::vec3& a, const glm::vec3& b) { return std::fma(a.z, b.z, std::fma(a.y, b.y, a.x * b.x)); }

/// What the stock renderer's texture units read for a surface: the base texture and the baked
/// light (lightmap texture or vertex colour), both in display values.
struct StockTexels {
  glm::vec3 base{1.0f};   ///< Display values in [0, 1].
  float baseAlpha = 1.0f;
  glm::vec3 baked{1.0f};  ///< Display values in [0, 1].
  glm::vec3 albedo{1.0f}; ///< Linear base colour (AOV); filled when `albedoKnown`.
  bool albedoKnown = false;
};

/// The base texture and baked light of a hit in display values. An sRGB texture with no other
/// factor is read as stored (its bytes filtered, as a texture unit filters them); anything else
/// (base colour, vertex or entity tint, linear data, vertex light) is computed in linear values
/// and encoded, the two encodings in one pass. The base texture is filtered as `filter` says.
StockTexels stockTexels(const RenderScene& scene, const SurfaceHit& s, float footprint, TextureFilter filter) {
  const MaterialRecord& m = *s.material;
  StockTexels t;
  const glm::vec4 factor = scene.baseFactor(s);
  bool encodeBase = false, encodeBaked = false;
  if (m.base != nullptr && m.base->srgb() && glm::vec3(factor) == glm::vec3(1.0f)) {
    const glm::vec4 texel = m.base->sampleStored(s.uv, scene.baseLod(s, footprint), filter);
    t.base = glm::clamp(glm::vec3(texel), 0.0f, 1.0f);
    t.baseAlpha = texel.a * factor.a;
  } else {
    glm::vec4 c = factor;
    if (m.base != nullptr) c *= m.base->sample(s.uv, scene.baseLod(s, footprint), filter);
    t.albedo = glm::clamp(glm::vec3(c), 0.0f, 1.0f);
    t.albedoKnown = true;
    t.base = t.albedo;
    t.baseAlpha = c.a;
    encodeBase = true;
  }
  if (m.desc.stock.useVertexLight) {
    t.baked = glm::clamp(glm::vec3(s.vertexColor), 0.0f, 1.0f);   // display values already
  } else if (m.lightmap != nullptr && m.lightmap->srgb()) {
    t.baked = glm::clamp(glm::vec3(m.lightmap->sampleStored(s.lightmapUv, 0.0f)), 0.0f, 1.0f);
  } else if (m.lightmap != nullptr) {
    t.baked = glm::vec3(m.lightmap->sample(s.lightmapUv, 0.0f));
    encodeBaked = true;
  }
  if (encodeBase || encodeBaked) {
    const auto [base, baked] = encodeTwo(t.base, t.baked);
    if (encodeBase) t.base = base;
    if (encodeBaked) t.baked = baked;
  }
  if (m.cover != nullptr) {   // the cover stage blended over the base in display values
    const CoverTexel cover = scene.coverAt(s, footprint, filter, true);
    if (cover.weight > 0.0f) {
      t.base = glm::mix(t.base, cover.color, cover.weight);
      t.albedoKnown = false;   // litSurface decodes it from the display value
    }
  }
  return t;
}

/// Base colour x baked light of the surface a camera ray ends on (texture x lightmap in 8-bit
/// values, as stock multiplies them), with its shine stage, in display values as the stock
/// renderer multiplies and blends its stages; fills t.albedo. Without a shine stage `display`
/// is set to the display value it decoded (clamped to [0, 1]).
glm::vec3 litSurface(const RenderScene& scene, const SurfaceHit& s, StockTexels& t, float footprint,
                     TextureFilter filter, std::optional<glm::vec3>& display) {
  const MaterialRecord& m = *s.material;
  // texture x baked light in 8-bit values, as stock (x the display's overbright factor)
  const glm::vec3 productDisplay = t.base * t.baked * m.desc.stock.bakedLightScale;
  if (!t.albedoKnown) t.albedo = decodeColour(t.base);
  glm::vec3 lit = decodeColour(productDisplay);
  if (m.shine == nullptr) {
    display = glm::clamp(productDisplay, 0.0f, 1.0f);
  } else {   // the shine stage over the lit base, in display values too
    glm::vec4 shine = scene.shineColor(s, footprint, filter);
    if (m.desc.stock.shineVertexColor) {   // a vertex-lit surface's vertex colour is in display values
      const glm::vec3 vertex(s.vertexColor);
      shine = glm::vec4(m.desc.stock.useVertexLight ? displayProductWithDisplay(glm::vec3(shine), vertex)
                                                    : displayProduct(glm::vec3(shine), vertex),
                        shine.a);
    }
    const float redrawn = m.desc.stock.shineMaskedByBaseAlpha ? std::clamp(t.baseAlpha, 0.0f, 1.0f) : 0.0f;
    lit = composeShine(lit, shine, m.desc.stock.shineBlend, redrawn);
  }
  return lit;
}

/// The lit surface `lit` (linear; `display` its display value when known) after the stock
/// dynamic-light passes of the scene's lights at `s`, both updated.
glm::vec3 dynamicallyLit(const RenderScene& scene, const SurfaceHit& s, const glm::vec3& lit,
                         std::optional<glm::vec3>& display) {
  const glm::vec3 before = display ? *display : fastLinearToSrgb(lit);
  const glm::vec3 after = stockDlightsOver(scene.stockDlights, s.position, s.geometricNormal, before);
  if (after == before) return lit;
  display = after;
  return decodeColour(after);
}

}  // namespace

PixelSample composeLightmapSample(const RenderScene& scene, const CameraRays& camera, const RenderSettings& settings,
                                  float px, float py, const sampling::PixelSampler& sampler,
                                  const TracedCameraRay* traced, TriangleMemo* memo) {
  // The sample's AOVs (PixelSample's defaults until set), the sample built from them at the end
  // with every member given: GCC zero-fills a default PixelSample first with `rep stos`.
  glm::vec3 albedoAov(0.0f), normalAov(0.0f), position(0.0f);
  glm::vec2 bary(0.0f);
  float depthAov = kInfinity;
  bool overlay = false;
  InstanceId instance = kNoId;
  MaterialId material = kNoId;
  uint32_t prim = 0;
  Ray ray = traced ? traced->ray : camera.generate(px, py);
  glm::vec3 radiance(0.0f);
  // 1, unless more fog layers cross the path than displayFog holds: those dim what lies behind.
  glm::vec3 beta(1.0f);
  float coneWidth = 0.0f;
  const float coneSpread = camera.pixelSpreadAngle();
  const uint32_t maxDepth = settings.maxBounces + trace::kExtraDeltaBounces;   // portal crossings
  // The shading normal only for the normal AOV (the denoiser's, or one asked for).
  const SurfaceParts parts = settings.normalAov || settings.denoise ? SurfaceParts::All : SurfaceParts::NoShadingNormal;
  DisplayComposite layers;   // see-through layers, composed in display values at the end
  std::optional<glm::vec3> litDisplay;   // the display value of the lit surface (litSurface)
  std::array<DisplayFog, 8> displayFog;
  uint32_t displayFogCount = 0;

  // The path goes on only through portals: every segment is seen directly by the camera.
  for (uint32_t depth = 0;; ++depth) {
    trace::SegmentHit segment;
    segment.collected.displayValues = true;   // layers in display values (DisplayComposite)
    trace::traceSegment(scene, ray, depth, sampler.bits(kGroupsPerVertex * depth + kGroupRayBits), true, traced,
                        segment);
    const Hit& hit = segment.hit;
    const float tHit = segment.found ? hit.t : kInfinity;
    if (depth == 0) overlay = segment.found && segment.onOverlay;
    // glm::normalize(ray.dir) (which is ray.dir x (1 / length)) with the length kept for the fog.
    const float dirLength = glm::length(ray.dir);
    const glm::vec3 dir = ray.dir * (1.0f / dirLength);
    // Fog along this segment; a camera ray measures it by eye-space depth, as stock does.
    const float eyeDepthScale = depth == 0 ? glm::dot(dir, camera.forward()) : 1.0f;
    // No fog where the map has none, or where no volume holds the packet's hits (markFogFreeEnds).
    const bool fogFree = scene.fogs.empty() || (depth == 0 && traced != nullptr && traced->fogFreeEnd);
    const FogSegment fog =
        fogFree ? FogSegment() : FogSegment(scene.fogs, ray.origin, ray.dir, tHit, dirLength * eyeDepthScale, true);
    layers.appendBefore(*segment.additive, tHit);
    if (fog.transmittance() < 1.0f && displayFogCount < displayFog.size()) {
      displayFog[displayFogCount++] = {radiance, 1.0f - fog.transmittance(), fog.layerColor()};
    } else if (fog.transmittance() < 1.0f) {
      radiance += beta * fog.glow();
      beta *= fog.transmittance();
    }
    const SurfaceHit s = segment.found ? scene.surfaceAt(hit, segment.onOverlay, ray, parts, memo) : SurfaceHit{};
    if (!segment.found || s.material->desc.sky) {
      const glm::vec3 sky = scene.sky.radiance(dir);
      radiance += beta * sky;
      albedoAov = glm::min(sky, glm::vec3(1.0f));   // as trace::recordSkyAovs
      normalAov = glm::vec3(0.0f);
      depthAov = kInfinity;
      break;
    }
    if (const PortalDesc* portal = trace::portalEntered(scene, s, dir)) {
      if (depth >= maxDepth) break;
      ray = trace::throughPortal(*portal, s.position, dir);
      coneWidth += coneSpread * hit.t;
      continue;
    }
    const float facing = fusedDot(s.geometricNormal, -dir);
    const bool front = facing > 0.0f;
    const glm::vec3 ns = front ? s.shadingNormal : -s.shadingNormal;
    coneWidth += coneSpread * hit.t;
    const float footprint =
        kRasterFootprintScale * coneWidth / std::max(trace::kMinCosForFootprint, front ? facing : -facing);
    StockTexels texels = stockTexels(scene, s, footprint, settings.stockTextureFilter);
    glm::vec3 lit = litSurface(scene, s, texels, footprint, settings.stockTextureFilter, litDisplay);
    // Stock's dynamic-light pass follows the surface's stages, before its fog.
    if (s.material->desc.stock.takesDynamicLights && !scene.stockDlights.empty())
      lit = dynamicallyLit(scene, s, lit, litDisplay);
    albedoAov = texels.albedo;   // as trace::recordSurfaceAovs
    normalAov = ns;
    depthAov = hit.t;
    if (depth == 0) {   // reprojection ids only when no portal lies between the hit and the camera
      instance = s.instance != nullptr ? s.instance->id : kNoId;
      material = trace::materialIdOf(scene, s);
      position = s.position;
      prim = s.prim;
      bary = s.bary;
    }
    const glm::vec3 le = scene.emission(s, front);
    if (le != glm::vec3(0.0f)) layers.append({le, glm::vec3(1.0f)});   // a glow stage adds in display values
    if (radiance != glm::vec3(0.0f) || beta != glm::vec3(1.0f)) litDisplay.reset();   // not the radiance alone
    radiance += beta * lit;
    break;
  }
  for (uint32_t i = displayFogCount; i-- > 0;) {
    const DisplayFog& f = displayFog[i];
    radiance = f.radianceInFront + blendInDisplaySpace(radiance - f.radianceInFront, f.opacity, f.color);
  }
  // See-through layers over the fogged surface; over the surface's display value where that is
  // the whole of the radiance (no decode and encode again).
  const glm::vec3 composed =
      layers.size() != 0 && litDisplay && displayFogCount == 0 ? layers.overDisplay(*litDisplay) : layers.over(radiance);
  return PixelSample{.radiance = composed,
                     .emission = composed,   // no Monte Carlo noise at all
                     .albedo = albedoAov,
                     .normal = normalAov,
                     .depth = depthAov,
                     .overlay = overlay,
                     .instance = instance,
                     .material = material,
                     .position = position,
                     .prim = prim,
                     .bary = bary};
}

}  // namespace pa
