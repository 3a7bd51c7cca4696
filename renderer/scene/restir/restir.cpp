#include "renderer/scene/restir/restir.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include <tbb/blocked_range.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

#include <glm/geometric.hpp>

#include "renderer/bvh/ray_offset.h"
#include "renderer/scene/integrator/integrator.h"
#include "renderer/scene/integrator/trace_common.h"
#include "renderer/scene/materials/bsdf.h"
#include "renderer/scene/sampling/sobol_sampler.h"
#include "renderer/scene/sampling/warp.h"

namespace pa::restir {

namespace {

constexpr float kInfinity = std::numeric_limits<float>::infinity();
// Sampler dimension groups of the resampling (far above the integrator's per-vertex groups).
constexpr uint32_t kGroupCandidates = 0x40000;   // + candidate index: light choice and point
constexpr uint32_t kGroupPicks = 0x41000;        // random bits: reservoir choices, shadow rays


bool visible(const RenderScene& scene, const ShadingPoint& point, const LightSample& sample, uint32_t bits) {
  TraceRequest request;
  request.kind = RayKind::Shadow;
  request.randomBits = bits;
  request.towardEnvironment = sample.environment;
  return !scene.occluded(shadowRayTo(point.position, point.ng, sample), request);
}

}  // namespace

Ray shadowRayTo(const glm::vec3& position, const glm::vec3& ng, const LightSample& sample) {
  Ray shadow;
  shadow.origin = offsetRayOrigin(position, glm::dot(sample.wi, ng) > 0.0f ? ng : -ng);
  if (sample.environment) {
    shadow.dir = sample.wi;
    shadow.tmax = kInfinity;
  } else if (sample.lightNormal != glm::vec3(0.0f)) {
    // Area light: end just off the light's surface so it does not shadow itself.
    shadow.dir = offsetRayOrigin(sample.lightPoint, sample.lightNormal) - shadow.origin;
    shadow.tmax = 1.0f;
  } else {
    shadow.dir = sample.lightPoint - shadow.origin;
    shadow.tmax = 1.0f;
  }
  return shadow;
}

ShadingPoint primaryShadingPoint(const RenderScene& scene, const CameraRays& camera, const Ray& cameraRay,
                                 uint32_t bits, PixelSample* aovs) {
  // The integrator's first vertex (traceClosest at depth 0, then its surface set-up).
  ShadingPoint point;
  Ray ray = cameraRay;
  Hit hit;
  TraceRequest request;
  request.kind = RayKind::Camera;
  request.randomBits = bits;
  bool onOverlay = false;
  bool found = false;
  if (!scene.overlay.empty()) {
    Ray overlayRay = ray;
    request.overlay = true;
    if (scene.intersect(overlayRay, hit, request)) {
      ray = overlayRay;
      onOverlay = found = true;
    }
    request.overlay = false;
  }
  if (!found) found = scene.intersect(ray, hit, request);
  if (aovs != nullptr) *aovs = PixelSample{};
  if (!found) return point;
  const SurfaceHit s = scene.surfaceAt(hit, onOverlay, ray);
  const MaterialRecord& m = *s.material;
  if (m.desc.sky || m.desc.mirror) return point;
  const glm::vec3 dir = glm::normalize(ray.dir);
  point.wo = -dir;
  const bool front = glm::dot(s.geometricNormal, point.wo) > 0.0f;
  point.ng = front ? s.geometricNormal : -s.geometricNormal;
  point.ns = trace::viewerFacingShadingNormal(front ? s.shadingNormal : -s.shadingNormal, point.wo);   // as the integrator
  const float footprint = camera.pixelSpreadAngle() * hit.t / std::max(trace::kMinCosForFootprint, glm::dot(point.ng, point.wo));
  point.albedo = glm::clamp(glm::vec3(scene.baseColor(s, footprint)), 0.0f, 1.0f);
  point.specular = m.desc.specular;
  point.roughness = m.desc.roughness;
  point.specularTinted = m.desc.specularTinted;
  point.position = s.position;
  point.depth = hit.t;
  point.instance = s.instance != nullptr ? s.instance->id : kNoId;
  point.material = s.material == &scene.defaultMaterial ? kNoId : static_cast<MaterialId>(s.material - scene.materials.data());
  point.valid = true;   // mirrors (the only delta surfaces) returned above
  if (aovs != nullptr) {
    aovs->overlay = onOverlay;
    aovs->instance = point.instance;
    aovs->material = point.material;
    aovs->position = point.position;
    aovs->normal = point.ns;
    aovs->depth = point.depth;
  }
  return point;
}

/// The surface's scattering at a shading point (never a mirror: those are not valid points).
Bsdf bsdfAt(const ShadingPoint& point) {
  return Bsdf(point.albedo, point.specular, point.roughness, false, point.ns, point.ng, point.specularTinted);
}

float target(const LightSampler& lights, const ShadingPoint& point, const LightPoint& light, LightSample& sample) {
  if (!lights.evaluate(light, point.position, point.ns, sample)) return 0.0f;
  const Bsdf bsdf = bsdfAt(point);
  const float t = sampling::luminance(bsdf.evalCos(point.wo, sample.wi) * sample.radiance) * sample.jacobian;
  return std::isfinite(t) && t > 0.0f ? t : 0.0f;
}

Resampler::Resampler(const Config& config) : config_(config) {}

void Resampler::reset() { haveHistory_ = false; }

bool Resampler::similar(const ShadingPoint& a, const ShadingPoint& b) const {
  return a.valid && b.valid && std::abs(a.depth - b.depth) <= config_.depthTolerance * a.depth &&
         glm::dot(a.ns, b.ns) >= config_.normalCosine;
}

void Resampler::combine(const RenderScene& scene, const ShadingPoint& at, const Input* inputs, uint32_t count,
                        uint32_t bits, Reservoir& out, uint64_t& rays) const {
  // Reservoir resampling of the inputs' samples by target at `at` x W x M, then W = sum / (Z x
  // target), Z = the summed M of the inputs that could have produced the sample kept.
  out = {};
  float sum = 0.0f;
  int chosen = -1;
  LightSample kept;
  float keptTarget = 0.0f;
  for (uint32_t i = 0; i < count; ++i) {
    const Reservoir& r = *inputs[i].reservoir;
    out.count += r.count;
    if (!(r.weight > 0.0f)) continue;
    LightSample sample;
    const float t = target(scene.lights, at, r.light, sample);
    const float w = t * r.weight * r.count;
    if (!(w > 0.0f) || !std::isfinite(w)) continue;
    sum += w;
    if (sampling::toUnitFloat(sampling::hashCombine(bits, i)) * sum < w) {
      chosen = static_cast<int>(i);
      kept = sample;
      keptTarget = t;
    }
  }
  if (chosen < 0) return;
  out.light = kept.light;
  // The pixel's own visibility first: an occluded sample contributes nothing, whatever Z is.
  if (!(chosen == 0 && inputs[0].knownVisible)) {
    ++rays;
    if (!visible(scene, at, kept, sampling::hashCombine(bits, 0x5000u))) return;
  }
  float z = inputs[0].reservoir->count;
  for (uint32_t i = 1; i < count; ++i) {
    const Input& input = inputs[i];
    if (static_cast<int>(i) == chosen && input.knownVisible) {
      z += input.reservoir->count;
      continue;
    }
    LightSample there;
    if (!(target(scene.lights, *input.point, kept.light, there) > 0.0f)) continue;
    ++rays;
    if (visible(scene, *input.point, there, sampling::hashCombine(bits, 0x5000u + i))) z += input.reservoir->count;
  }
  out.weight = sum / (z * keptTarget);
  if (!std::isfinite(out.weight)) out.weight = 0.0f;
}

void Resampler::run(const RenderScene& scene, const CameraRays& camera, uint32_t width, uint32_t height,
                    uint32_t pixelSeedBase, uint32_t sampleIndex, const temporal::InstanceMotion& motions,
                    const CameraRays* previousCamera) {
  const size_t n = size_t{width} * height;
  if (width != width_ || height != height_) {
    width_ = width;
    height_ = height;
    haveHistory_ = false;
    for (auto* v : {&initial_, &temporal_, &final_, &previous_}) v->assign(n, Reservoir{});
    points_.assign(n, ShadingPoint{});
    previousPoints_.assign(n, ShadingPoint{});
    gbuffer_.resize(width, height);
  }
  std::swap(previous_, final_);
  std::swap(previousPoints_, points_);
  const bool useHistory = haveHistory_ && previousCamera != nullptr;
  tbb::combinable<uint64_t> rayCount([] { return uint64_t{0}; });
  const auto forRows = [&](auto&& body) {
    tbb::parallel_for(tbb::blocked_range<uint32_t>(0, height, 4), [&](const tbb::blocked_range<uint32_t>& r) {
      uint64_t& rays = rayCount.local();
      for (uint32_t y = r.begin(); y != r.end(); ++y)
        for (uint32_t x = 0; x < width; ++x) body(x, y, size_t{y} * width + x, rays);
    });
  };
  const auto samplerAt = [&](size_t i) {
    return sampling::PixelSampler(sampling::hashCombine(pixelSeedBase, static_cast<uint32_t>(i)), sampleIndex);
  };

  // 1. Candidates: RIS over the light sampler's samples, then the kept one's visibility.
  forRows([&](uint32_t x, uint32_t y, size_t i, uint64_t& rays) {
    const sampling::PixelSampler sampler = samplerAt(i);
    const glm::vec2 jitter(sampler.get4(0));
    const float px = static_cast<float>(x) + jitter.x, py = static_cast<float>(y) + jitter.y;
    PixelSample aovs;
    ShadingPoint& point = points_[i];
    point = primaryShadingPoint(scene, camera, camera.generate(px, py), cameraRayBits(sampler), &aovs);
    gbuffer_.write(i, aovs, px, py, motions, previousCamera);
    Reservoir& r = initial_[i];
    r = {};
    if (!point.valid || scene.lights.empty()) return;
    const Bsdf bsdf = bsdfAt(point);
    float sum = 0.0f;
    LightSample kept;
    float keptTarget = 0.0f;
    const uint32_t picks = sampler.bits(kGroupPicks);
    for (uint32_t k = 0; k < config_.candidates; ++k) {
      LightSample sample;
      if (!scene.lights.sample(point.position, point.ns, sampler.get4(kGroupCandidates + k), sample)) continue;
      const float t = sampling::luminance(bsdf.evalCos(point.wo, sample.wi) * sample.radiance) * sample.jacobian;
      const float w = t / (sample.pdf * sample.jacobian);
      if (!(w > 0.0f) || !std::isfinite(w)) continue;
      sum += w;
      if (sampling::toUnitFloat(sampling::hashCombine(picks, k)) * sum < w) {
        kept = sample;
        keptTarget = t;
      }
    }
    r.count = static_cast<float>(config_.candidates);
    if (!(sum > 0.0f)) return;
    r.light = kept.light;
    ++rays;
    if (!visible(scene, point, kept, sampling::hashCombine(picks, 0x4000u))) return;
    r.weight = sum / (r.count * keptTarget);
  });

  // 2. Temporal: last frame's final reservoir where this pixel's hit was then.
  const float historyCap = config_.historyCap * static_cast<float>(config_.candidates);
  forRows([&](uint32_t x, uint32_t y, size_t i, uint64_t& rays) {
    temporal_[i] = initial_[i];
    const ShadingPoint& point = points_[i];
    if (!useHistory || !point.valid) return;
    const glm::vec2 motion = gbuffer_.motion[i];
    if (!std::isfinite(motion.x) || !std::isfinite(motion.y)) return;
    const glm::vec2 jitter(samplerAt(i).get4(0));
    const float qx = std::floor(static_cast<float>(x) + jitter.x + motion.x);
    const float qy = std::floor(static_cast<float>(y) + jitter.y + motion.y);
    if (!(qx >= 0.0f && qy >= 0.0f && qx < static_cast<float>(width) && qy < static_cast<float>(height))) return;
    const size_t j = static_cast<size_t>(qy) * width + static_cast<size_t>(qx);
    const ShadingPoint& then = previousPoints_[j];
    if (!then.valid || then.instance != point.instance || then.material != point.material) return;
    const float depthThen = gbuffer_.previousDepth[i];
    if (!(std::abs(then.depth - depthThen) <= config_.depthTolerance * depthThen)) return;
    if (!(glm::dot(then.ns, gbuffer_.previousNormal[i]) >= config_.normalCosine)) return;
    Reservoir history = previous_[j];
    history.count = std::min(history.count, historyCap);
    const Input inputs[2] = {{&initial_[i], &point, true}, {&history, &then, false}};
    combine(scene, point, inputs, 2, samplerAt(i).bits(kGroupPicks + 1), temporal_[i], rays);
  });

  // 3. Spatial: a few neighbours' temporal reservoirs on similar surfaces.
  forRows([&](uint32_t x, uint32_t y, size_t i, uint64_t& rays) {
    final_[i] = temporal_[i];
    const ShadingPoint& point = points_[i];
    if (!point.valid || config_.spatialNeighbours == 0) return;
    const sampling::PixelSampler sampler = samplerAt(i);
    constexpr uint32_t kMaxNeighbours = 8;
    Input inputs[kMaxNeighbours + 1];
    inputs[0] = {&temporal_[i], &point, true};
    uint32_t count = 1;
    for (uint32_t k = 0; k < std::min(config_.spatialNeighbours, kMaxNeighbours); ++k) {
      const glm::vec4 u = sampler.get4(kGroupCandidates + config_.candidates + k);
      const glm::vec2 d = config_.spatialRadius * sampling::concentricDisk(glm::vec2(u));
      const int nx = static_cast<int>(std::lround(static_cast<float>(x) + d.x));
      const int ny = static_cast<int>(std::lround(static_cast<float>(y) + d.y));
      if (nx < 0 || ny < 0 || nx >= static_cast<int>(width) || ny >= static_cast<int>(height)) continue;
      const size_t j = static_cast<size_t>(ny) * width + static_cast<size_t>(nx);
      if (j == i || !similar(point, points_[j])) continue;
      inputs[count++] = {&temporal_[j], &points_[j], true};
    }
    if (count > 1) combine(scene, point, inputs, count, sampler.bits(kGroupPicks + 2), final_[i], rays);
  });
  haveHistory_ = true;
  shadowRays_ = rayCount.combine(std::plus<uint64_t>());
}

}  // namespace pa::restir
