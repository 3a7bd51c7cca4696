#include "renderer/scene/integrator/lightmap_compositor.h"

#include <algorithm>
#include <array>
#include <cmath>

#include <glm/geometric.hpp>

#include "renderer/scene/integrator/display_composite.h"
#include "renderer/scene/integrator/integrator.h"
#include "renderer/scene/integrator/trace_common.h"
#include "renderer/scene/media/fog_volumes.h"

namespace pa {

namespace {

using trace::kInfinity;

/// A fog layer to blend over what lies behind it on display values, as the stock renderer's
/// framebuffer does.
struct DisplayFog {
  glm::vec3 radianceInFront;
  float opacity;
  glm::vec3 color;
};

/// dot(a, b) as a chain of fused multiply-adds, x first: the rounding of the Direct/Path
/// integrator's dot products, so that both measure a hit's texture footprint alike.
float fusedDot(const glm::vec3& a, const glm::vec3& b) { return std::fma(a.z, b.z, std::fma(a.y, b.y, a.x * b.x)); }

/// Base colour x baked light of the surface a camera ray ends on, with its shine stage, in
/// display values as the stock renderer multiplies and blends its stages.
glm::vec3 litSurface(const RenderScene& scene, const SurfaceHit& s, const glm::vec4& baseRgba, const glm::vec3& albedo,
                     float footprint) {
  const MaterialRecord& m = *s.material;
  glm::vec3 baked(1.0f);
  if (m.desc.stock.useVertexLight) {
    baked = glm::vec3(s.vertexColor);
  } else if (m.lightmap != nullptr) {
    baked = glm::vec3(m.lightmap->sample(s.lightmapUv, 0.0f));
  }
  glm::vec3 lit = displayProduct(albedo, baked);   // texture x lightmap in 8-bit values, as stock
  if (m.shine != nullptr) {   // the shine stage over the lit base, in display values too
    glm::vec4 shine = scene.shineColor(s, footprint);
    if (m.desc.stock.shineVertexColor) shine = glm::vec4(displayProduct(glm::vec3(shine), glm::vec3(s.vertexColor)), shine.a);
    const float redrawn = m.desc.stock.shineMaskedByBaseAlpha ? std::clamp(baseRgba.a, 0.0f, 1.0f) : 0.0f;
    lit = composeShine(lit, shine, m.desc.stock.shineBlend, redrawn);
  }
  return lit;
}

}  // namespace

PixelSample composeLightmapSample(const RenderScene& scene, const CameraRays& camera, const RenderSettings& settings,
                                  float px, float py, const sampling::PixelSampler& sampler,
                                  const TracedCameraRay* traced) {
  PixelSample out;
  Ray ray = traced ? traced->ray : camera.generate(px, py);
  glm::vec3 radiance(0.0f);
  // 1, unless more fog layers cross the path than displayFog holds: those dim what lies behind.
  glm::vec3 beta(1.0f);
  float coneWidth = 0.0f;
  const float coneSpread = camera.pixelSpreadAngle();
  const uint32_t maxDepth = settings.maxBounces + trace::kExtraDeltaBounces;   // portal crossings
  DisplayComposite layers;   // see-through layers, composed in display values at the end
  std::array<DisplayFog, 8> displayFog;
  uint32_t displayFogCount = 0;

  // The path goes on only through portals: every segment is seen directly by the camera.
  for (uint32_t depth = 0;; ++depth) {
    trace::SegmentHit segment;
    trace::traceSegment(scene, ray, depth, sampler.bits(kGroupsPerVertex * depth + kGroupRayBits), true, traced,
                        segment);
    const Hit& hit = segment.hit;
    const float tHit = segment.found ? hit.t : kInfinity;
    if (depth == 0) out.overlay = segment.found && segment.onOverlay;
    const glm::vec3 dir = glm::normalize(ray.dir);
    // Fog along this segment; a camera ray measures it by eye-space depth, as stock does.
    const float eyeDepthScale = depth == 0 ? glm::dot(dir, camera.forward()) : 1.0f;
    const FogSegment fog(scene.fogs, ray.origin, ray.dir, tHit, glm::length(ray.dir) * eyeDepthScale, true);
    layers.appendBefore(*segment.additive, tHit);
    if (fog.transmittance() < 1.0f && displayFogCount < displayFog.size()) {
      displayFog[displayFogCount++] = {radiance, 1.0f - fog.transmittance(), fog.layerColor()};
    } else if (fog.transmittance() < 1.0f) {
      radiance += beta * fog.glow();
      beta *= fog.transmittance();
    }
    const SurfaceHit s = segment.found ? scene.surfaceAt(hit, segment.onOverlay, ray) : SurfaceHit{};
    if (!segment.found || s.material->desc.sky) {
      radiance += beta * scene.sky.radiance(dir);
      trace::recordSkyAovs(scene, dir, out);
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
    const float footprint = coneWidth / std::max(trace::kMinCosForFootprint, front ? facing : -facing);
    const glm::vec4 baseRgba = scene.baseColor(s, footprint);
    const glm::vec3 albedo = glm::clamp(glm::vec3(baseRgba), 0.0f, 1.0f);
    trace::recordSurfaceAovs(scene, s, hit.t, albedo, ns, depth > 0, out);
    const glm::vec3 le = scene.emission(s, front);
    if (le != glm::vec3(0.0f)) layers.append({le, glm::vec3(1.0f)});   // a glow stage adds in display values
    radiance += beta * litSurface(scene, s, baseRgba, albedo, footprint);
    break;
  }
  for (uint32_t i = displayFogCount; i-- > 0;) {
    const DisplayFog& f = displayFog[i];
    radiance = f.radianceInFront + blendInDisplaySpace(radiance - f.radianceInFront, f.opacity, f.color);
  }
  out.radiance = layers.over(radiance);   // see-through layers over the fogged surface
  out.emission = out.radiance;            // no Monte Carlo noise at all
  return out;
}

}  // namespace pa
