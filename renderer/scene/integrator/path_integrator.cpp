#include "renderer/scene/integrator/path_integrator.h"

#include <algorithm>
#include <cmath>
#include <span>

#include <glm/geometric.hpp>

#include "renderer/bvh/ray_offset.h"
#include "renderer/scene/integrator/baked_light.h"
#include "renderer/scene/integrator/display_composite.h"
#include "renderer/scene/integrator/trace_common.h"
#include "renderer/scene/materials/bsdf.h"
#include "renderer/scene/media/fog_volumes.h"
#include "renderer/scene/restir/restir.h"
#include "renderer/scene/sampling/warp.h"

namespace pa {

namespace {

using trace::clampContribution;
using trace::kInfinity;
using trace::maxComponent;

// Sampler dimension groups within one path vertex.
constexpr uint32_t kGroupLight = 1;     // light choice, light point (2), sky cell
constexpr uint32_t kGroupBsdf = 2;      // direction (2), lobe choice, roulette
constexpr uint32_t kGroupRays = kGroupRayBits;   // random bits for stochastic transparency

/// State carried from one path vertex to the next for MIS.
struct PreviousVertex {
  bool delta = true;          // camera or mirror: emitters hit next get full weight
  float bsdfPdf = 0.0f;
  glm::vec3 position{0.0f};
  glm::vec3 normal{0.0f};
  bool resampled = false;     // its direct light came from reservoir resampling (no MIS: see tracePathSample)
};

/// Next-event estimation at a surface point; returns the MIS-weighted contribution / beta.
glm::vec3 sampleDirectLight(const RenderScene& scene, const SurfaceHit& s, const Bsdf& bsdf, const glm::vec3& wo,
                            const glm::vec3& ng, const glm::vec3& ns, const glm::vec4& u, uint32_t bits) {
  LightSample ls;
  // A sky sample's radiance is looked up only once its shadow ray passed (the same value).
  if (!scene.lights.sample(s.position, ns, u, ls, false)) return glm::vec3(0.0f);
  const glm::vec3 f = bsdf.evalCos(wo, ls.wi);
  if (f == glm::vec3(0.0f)) return glm::vec3(0.0f);
  Ray shadow;
  shadow.origin = offsetRayOrigin(s.position, glm::dot(ls.wi, ng) > 0.0f ? ng : -ng);
  if (ls.environment) {
    shadow.dir = ls.wi;
    shadow.tmax = kInfinity;
  } else if (ls.lightNormal != glm::vec3(0.0f)) {
    // Area light: end just off the light's surface so it does not shadow itself.
    const glm::vec3 end = offsetRayOrigin(ls.lightPoint, ls.lightNormal);
    shadow.dir = end - shadow.origin;
    shadow.tmax = 1.0f;
  } else {
    shadow.dir = ls.lightPoint - shadow.origin;
    shadow.tmax = 1.0f;
  }
  TraceRequest request;
  request.kind = RayKind::Shadow;
  request.randomBits = bits;
  request.towardEnvironment = ls.environment;
  if (scene.occluded(shadow, request)) return glm::vec3(0.0f);
  float throughFog = 1.0f;
  if (!scene.fogs.empty()) {
    throughFog = FogSegment(scene.fogs, shadow.origin, shadow.dir, shadow.tmax, glm::length(shadow.dir)).transmittance();
    if (!(throughFog > 0.0f)) return glm::vec3(0.0f);
  }
  if (ls.light.kind == LightPoint::Kind::Sky) ls.radiance = scene.lights.skyRadiance(ls.wi);
  const float weight = ls.delta ? 1.0f : sampling::powerHeuristic(ls.pdf, bsdf.pdf(wo, ls.wi));
  return f * ls.radiance * (weight * throughFog / ls.pdf);
}

/// The direct light a reservoir's sample brings to a surface point (its visibility is known).
glm::vec3 resampledDirectLight(const RenderScene& scene, const SurfaceHit& s, const Bsdf& bsdf, const glm::vec3& wo,
                               const glm::vec3& ng, const glm::vec3& ns, const ResampledLight& resampled) {
  LightSample ls;
  if (!(resampled.weight > 0.0f) || !scene.lights.evaluate(resampled.light, s.position, ns, ls)) return glm::vec3(0.0f);
  const glm::vec3 f = bsdf.evalCos(wo, ls.wi);
  if (f == glm::vec3(0.0f)) return glm::vec3(0.0f);
  float throughFog = 1.0f;
  if (!scene.fogs.empty()) {
    const Ray shadow = restir::shadowRayTo(s.position, ng, ls);
    throughFog = FogSegment(scene.fogs, shadow.origin, shadow.dir, shadow.tmax, glm::length(shadow.dir)).transmittance();
  }
  return f * ls.radiance * (ls.jacobian * resampled.weight * throughFog);
}

/// Radiance arriving from the environment along dir, MIS-weighted against sky sampling. Seen
/// (camera and mirror chains) until the path has scattered, lighting radiance after that.
glm::vec3 environmentRadiance(const RenderScene& scene, const glm::vec3& dir, const PreviousVertex& prev,
                              bool scattered) {
  const glm::vec3 le = scattered ? scene.sky.lightingRadiance(dir) : scene.sky.radiance(dir);
  if (prev.delta) return le;
  if (prev.resampled) return scene.lights.skyPdf(prev.position, prev.normal, dir) > 0.0f ? glm::vec3(0.0f) : le;
  return le * sampling::powerHeuristic(prev.bsdfPdf, scene.lights.skyPdf(prev.position, prev.normal, dir));
}

/// Calls f(colour) for each additive surface in front of tHit, its colour dimmed by the fog
/// between it and the ray origin.
template <class F>
void forEachAdditiveThroughFog(const AdditiveHits& additive, float tHit, const FogSegment& fog, F&& f) {
  for (uint32_t i = 0; i < additive.count; ++i) {
    const AdditiveHits::Entry& e = additive.entries[i];
    if (e.t < tHit) f(fog.empty() ? e.color : e.color * fog.transmittanceTo(e.t));
  }
}

/// Additive surfaces in front of tHit, each dimmed by the fog between it and the ray origin.
glm::vec3 additiveThroughFog(const AdditiveHits& additive, float tHit, const FogSegment& fog) {
  if (fog.empty()) return additive.sumBefore(tHit);
  glm::vec3 sum(0.0f);
  forEachAdditiveThroughFog(additive, tHit, fog, [&](const glm::vec3& c) { sum += c; });
  return sum;
}

/// The linear multiplier of what lies behind the see-through layers in front of tHit: their
/// `transmit` product is a multiplier of display values (a team decal's dst x (1 + src)), taken
/// to linear radiance through the display's 2.2 power; 1 where no layer keeps a share of it.
glm::vec3 layersTransmittance(const AdditiveHits& additive, float tHit) {
  const glm::vec3 display = additive.transmitBefore(tHit);
  if (display == glm::vec3(1.0f)) return display;
  const glm::vec3 d = glm::max(display, glm::vec3(0.0f));
  return {std::pow(d.x, 2.2f), std::pow(d.y, 2.2f), std::pow(d.z, 2.2f)};
}

}  // namespace

PixelSample tracePathSample(const RenderScene& scene, const CameraRays& camera, const RenderSettings& settings,
                            float px, float py, const sampling::PixelSampler& sampler, const TracedCameraRay* traced,
                            const ResampledLight* resampled, TriangleMemo* memo) {
  PixelSample out;
  Ray ray = traced ? traced->ray : camera.generate(px, py);
  glm::vec3 radiance(0.0f);
  glm::vec3 seen(0.0f);   // the part of radiance gathered before the first scattering
  // With the stock look each part of it is a stage the stock framebuffer adds in display values:
  // their display values are summed (seenDisplay) and the sum shown (LightingLook::DisplaySpace).
  // A part alone needs no sum (it is shown as is): the curve is taken from the second part on.
  const bool displaySums = settings.lightingLook == LightingLook::DisplaySpace;
  glm::vec3 seenDisplay(0.0f);
  uint32_t seenParts = 0;
  glm::vec3 beta(1.0f);
  PreviousVertex prev;
  float coneWidth = 0.0f;
  float coneSpread = camera.pixelSpreadAngle();
  const uint32_t maxScatter = settings.integrator == Integrator::Direct ? std::min(1u, settings.maxBounces)
                                                                         : settings.maxBounces;
  uint32_t scatterCount = 0;
  // Adds light that reaches the camera from what it hit (emitters, sky, glows, fog), not light
  // reflected there: until the path first scatters it is exact per sample (PixelSample::emission).
  // Counts parts the camera sees (nonzero, 3 floats each, before `seen` adds them) into
  // seenDisplay, from the second part on; a ray's layers go through the curve together.
  const auto sumSeenDisplay = [&](std::span<float> parts) {
    const uint32_t n = static_cast<uint32_t>(parts.size() / 3);
    if (seenParts + n > 1) {
      if (seenParts == 1) seenDisplay = fastLinearToSrgb(seen);   // the first part
      fastLinearToSrgb(parts);
      for (uint32_t k = 0; k < n; ++k) seenDisplay += glm::vec3(parts[3 * k], parts[3 * k + 1], parts[3 * k + 2]);
    }
    seenParts += n;
  };
  const auto gather = [&](const glm::vec3& c) {
    radiance += c;
    if (scatterCount == 0) {
      if (displaySums && c != glm::vec3(0.0f)) {
        float part[3] = {c.x, c.y, c.z};
        sumSeenDisplay(part);
      }
      seen += c;
    }
  };
  uint32_t portalsCrossed = 0;   // what the camera sees through a portal counts as seen directly

  for (uint32_t depth = 0;; ++depth) {
    const uint32_t viewDepth = depth - portalsCrossed;
    const uint32_t group = kGroupsPerVertex * depth;
    trace::SegmentHit segment;
    trace::traceSegment(scene, ray, depth, sampler.bits(group + kGroupRays), prev.delta, traced, segment);
    const Hit& hit = segment.hit;
    const float tHit = segment.found ? hit.t : kInfinity;
    if (depth == 0) out.overlay = segment.found && segment.onOverlay;
    const glm::vec3 dir = glm::normalize(ray.dir);
    const FogSegment fog(scene.fogs, ray.origin, ray.dir, tHit, glm::length(ray.dir), false);
    if (displaySums && scatterCount == 0 && segment.additive->count > 1) {
      // Each layer a stage of its own, added in display values (fog dims each as in additiveThroughFog).
      float parts[3 * AdditiveHits::kCapacity];
      uint32_t n = 0;
      glm::vec3 sum(0.0f);
      forEachAdditiveThroughFog(*segment.additive, tHit, fog, [&](const glm::vec3& layer) {
        const glm::vec3 c = clampContribution(beta * layer, viewDepth, settings.radianceClamp);
        if (c == glm::vec3(0.0f)) return;
        parts[3 * n] = c.x, parts[3 * n + 1] = c.y, parts[3 * n + 2] = c.z;
        ++n;
        sum += c;
      });
      sumSeenDisplay(std::span(parts, 3 * n));
      radiance += sum;
      seen += sum;
    } else {
      gather(clampContribution(beta * additiveThroughFog(*segment.additive, tHit, fog), viewDepth,
                               settings.radianceClamp));
    }
    if (segment.additive->count != 0) beta *= layersTransmittance(*segment.additive, tHit);
    if (fog.transmittance() < 1.0f) {
      // The glow is the look of lit haze: seen along camera and mirror chains, never a light
      // source after a scattering (the map's lights already lit it; counting it would light twice).
      if (scatterCount == 0) gather(beta * fog.glow());
      beta *= fog.transmittance();
    }
    // Camera rays of neighbouring pixels mostly end on a few triangles; later vertices seldom share one.
    const SurfaceHit s = segment.found ? scene.surfaceAt(hit, segment.onOverlay, ray, SurfaceParts::All,
                                                         depth == 0 ? memo : nullptr)
                                       : SurfaceHit{};
    if (!segment.found || s.material->desc.sky) {
      const glm::vec3 le = environmentRadiance(scene, dir, prev, scatterCount > 0);
      gather(clampContribution(beta * le, viewDepth, settings.radianceClamp));
      if (viewDepth == 0) trace::recordSkyAovs(scene, dir, out);
      break;
    }

    const MaterialRecord& m = *s.material;
    if (const PortalDesc* portal = trace::portalEntered(scene, s, dir)) {
      if (depth >= maxScatter + trace::kExtraDeltaBounces) break;
      ray = trace::throughPortal(*portal, s.position, dir);
      prev.delta = true;   // nothing samples lights through a portal: what it reaches counts fully
      coneWidth += coneSpread * hit.t;
      ++portalsCrossed;
      continue;
    }
    const glm::vec3 wo = -dir;
    const bool front = glm::dot(s.geometricNormal, wo) > 0.0f;
    const glm::vec3 ng = front ? s.geometricNormal : -s.geometricNormal;
    const glm::vec3 ns = trace::viewerFacingShadingNormal(front ? s.shadingNormal : -s.shadingNormal, wo);
    coneWidth += coneSpread * hit.t;
    const float footprint = coneWidth / std::max(trace::kMinCosForFootprint, glm::dot(ng, wo));
    // After a scattering the colour only weighs light the path carries on: one bilinear lookup
    // in the nearest mip level instead of two blended (the ray cone is wide there already).
    const glm::vec4 baseRgba =
        scene.baseColor(s, footprint, scatterCount == 0 ? TextureFilter{} : TextureFilter{MipFilter::Nearest});
    const glm::vec3 albedo = glm::clamp(glm::vec3(baseRgba), 0.0f, 1.0f);
    if (viewDepth == 0) trace::recordSurfaceAovs(scene, s, hit.t, albedo, ns, portalsCrossed > 0, out);

    // Until the first scattering every earlier vertex was the camera, a mirror or a portal, so
    // the MIS weight below is 1 and the look may differ from the light (seenEmission).
    const glm::vec3 le = scatterCount == 0 ? scene.seenEmission(s, front) : scene.emission(s, front);
    if (le != glm::vec3(0.0f)) {
      float weight = 1.0f;
      if (!prev.delta) {
        const uint32_t index = scene.emissiveIndex(s);
        const float lightPdf =
            index == kNoId ? 0.0f : scene.lights.emissivePdf(index, prev.position, prev.normal, s.position);
        // After a resampled vertex the reservoir carries every light the sampler can pick there.
        weight = prev.resampled ? (lightPdf > 0.0f ? 0.0f : 1.0f) : sampling::powerHeuristic(prev.bsdfPdf, lightPdf);
      }
      gather(clampContribution(beta * le * weight, viewDepth, settings.radianceClamp));
    }
    if (scatterCount >= maxScatter || depth >= maxScatter + trace::kExtraDeltaBounces) {
      glm::vec3 baked;
      if (settings.bakedLightAtPathEnd && scatterCount > 0 && scatterCount >= maxScatter && !m.desc.mirror &&
          bakedLightAt(s, baked)) {
        const glm::vec3 diffuse = albedo * (1.0f - std::clamp(m.desc.specular, 0.0f, 1.0f));
        radiance += clampContribution(beta * diffuse * baked, depth, settings.radianceClamp);
      }
      break;
    }

    const Bsdf bsdf(albedo, m.desc.specular, m.desc.roughness, m.desc.mirror, ns, ng, m.desc.specularTinted);
    const glm::vec4 uLight = sampler.get4(group + kGroupLight);
    const bool useResampled = resampled != nullptr && depth == 0 && !bsdf.isDelta();
    if (!bsdf.isDelta()) {
      glm::vec3 direct = useResampled ? resampledDirectLight(scene, s, bsdf, wo, ng, ns, *resampled)
                                      : sampleDirectLight(scene, s, bsdf, wo, ng, ns, uLight,
                                                          sampler.bits(group + kGroupRays + 1000));
      const AmbientLight& ambient = scene.sky.ambient();   // the author's unshadowed ambient and floor
      if (ambient.active()) direct = ambient.apply(direct, albedo * (1.0f - std::clamp(m.desc.specular, 0.0f, 1.0f)));
      radiance += clampContribution(beta * direct, depth + 1, settings.radianceClamp);   // never exempt
    }

    const glm::vec4 uBsdf = sampler.get4(group + kGroupBsdf);
    // Russian roulette before the direction is drawn, so that a path it ends samples none: the
    // bounce survives with the probability of the throughput times the surface's reflectance
    // (for a diffuse surface what the sample's weight multiplies it by), and dark surfaces, most
    // of a Quake III map, seldom trace one. A mirror is never ended (it does not scatter).
    float survive = 1.0f;
    if (!bsdf.isDelta() && scatterCount + 1 >= std::max(1u, settings.rouletteStart)) {
      survive = std::min(1.0f, std::max(0.05f, maxComponent(beta * bsdf.reflectance())));
      if (uBsdf.w >= survive) break;
    }
    BsdfSample bs;
    if (!bsdf.sample(wo, glm::vec3(uBsdf.x, uBsdf.y, uBsdf.z), bs)) break;
    beta *= bs.weight;
    beta /= survive;
    // Member by member: a braced temporary was copied back in 16-byte loads over the narrower
    // stores that built it (a store-forwarding stall every scattering).
    prev.delta = bs.delta;
    prev.bsdfPdf = bs.pdf;
    prev.position = s.position;
    prev.normal = ns;
    prev.resampled = useResampled;
    if (!bs.delta) {
      ++scatterCount;
      coneSpread = std::max(coneSpread, bs.glossy ? 0.1f : 0.5f);
    }
    if (!(maxComponent(beta) > 0.0f)) break;
    ray = Ray{};
    ray.origin = offsetRayOrigin(s.position, glm::dot(bs.wi, ng) > 0.0f ? ng : -ng);
    ray.dir = bs.wi;
  }
  out.radiance = radiance;
  out.emission = seen;
  if (seenParts > 1) {
    // The seen part as the linear value of its display sum, clamped as 8 bits are: what
    // lightingLook adds in display values to the lit part.
    out.emission = fastSrgbToLinear(glm::min(seenDisplay, glm::vec3(1.0f)));
    out.radiance = radiance - seen + out.emission;
  }
  return out;
}

}  // namespace pa
