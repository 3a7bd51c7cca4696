// calibrateEstimatedLights: lightmap texel sampling, q3map2 direct-light prediction, NNLS fit.
#include "port/light_recovery/calibration.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>

#include <glm/geometric.hpp>

#include "port/q3formats/bsp/bsp_file.h"
#include "port/q3formats/world/world_lights.h"

namespace pa::recovery {

using namespace q3;
namespace {

constexpr float kMinLightDistance = 16.0f;   // q3map2 clamps point-light distances here
constexpr float kSunDistance = 65536.0f;     // shadow rays towards a sun end this far away

/// One sampled lightmap texel.
struct Sample {
  glm::vec3 position;
  glm::vec3 normal;
  float value;   // texel light value, summed over RGB
};

/// A lightmapped world triangle eligible for sampling.
struct SampleTriangle {
  const WorldMesh* mesh;
  size_t firstIndex;
  const WorldImage* lightmap;
};

float uniform01(std::mt19937& rng) { return float(rng() >> 8) * (1.0f / 16777216.0f); }

bool finite3(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

/// Area-weighted texel samples over the world model's lightmapped, visible, opaque surfaces.
std::vector<Sample> sampleLightmaps(const WorldScene& scene, const LightCalibrationOptions& o) {
  std::vector<SampleTriangle> triangles;
  std::vector<double> cumulativeArea;
  double total = 0.0;
  if (scene.models.empty()) return {};
  for (const WorldMesh& mesh : scene.models[0].meshes) {
    if (lightmapPageOf(mesh.lightmap, scene.lightmaps.size()) < 0 || mesh.material >= scene.materials.size())
      continue;
    const WorldMaterial& m = scene.materials[mesh.material];
    if (!m.visible || m.sky || m.vertexLit || m.alphaMode != WorldAlphaMode::Opaque) continue;
    const WorldImage& image = scene.lightmaps[mesh.lightmap];
    if (image.width == 0 || image.height == 0 || image.rgba8.size() != size_t(image.width) * image.height * 4) continue;
    const size_t n = mesh.positions.size();
    if (mesh.normals.size() != n || mesh.lightmapUvs.size() != n) continue;
    for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
      const uint32_t a = mesh.indices[t], b = mesh.indices[t + 1], c = mesh.indices[t + 2];
      if (a >= n || b >= n || c >= n) continue;
      const double area = 0.5 * double(glm::length(glm::cross(mesh.positions[b] - mesh.positions[a],
                                                               mesh.positions[c] - mesh.positions[a])));
      if (!(area > 0.0) || !std::isfinite(area)) continue;
      total += area;
      triangles.push_back({&mesh, t, &image});
      cumulativeArea.push_back(total);
    }
  }
  std::vector<Sample> samples;
  if (triangles.empty()) return samples;
  std::mt19937 rng(o.seed);
  samples.reserve(o.maxSamples);
  for (size_t s = 0; s < o.maxSamples; ++s) {
    const double pick = double(uniform01(rng)) * total;
    const size_t t = std::min(size_t(std::lower_bound(cumulativeArea.begin(), cumulativeArea.end(), pick) -
                                     cumulativeArea.begin()),
                              triangles.size() - 1);
    const SampleTriangle& tri = triangles[t];
    const WorldMesh& mesh = *tri.mesh;
    float u = uniform01(rng), v = uniform01(rng);
    if (u + v > 1.0f) u = 1.0f - u, v = 1.0f - v;
    const uint32_t ia = mesh.indices[tri.firstIndex], ib = mesh.indices[tri.firstIndex + 1],
                   ic = mesh.indices[tri.firstIndex + 2];
    const float w = 1.0f - u - v;
    const glm::vec3 p = w * mesh.positions[ia] + u * mesh.positions[ib] + v * mesh.positions[ic];
    glm::vec3 normal = w * mesh.normals[ia] + u * mesh.normals[ib] + v * mesh.normals[ic];
    const glm::vec2 uv = w * mesh.lightmapUvs[ia] + u * mesh.lightmapUvs[ib] + v * mesh.lightmapUvs[ic];
    const float length = glm::length(normal);
    if (!(length > 1e-4f) || !finite3(p) || !std::isfinite(uv.x) || !std::isfinite(uv.y)) continue;
    normal /= length;
    const WorldImage& image = *tri.lightmap;
    const int64_t x = std::clamp<int64_t>(int64_t(std::floor(uv.x * float(image.width))), 0, image.width - 1);
    const int64_t y = std::clamp<int64_t>(int64_t(std::floor(uv.y * float(image.height))), 0, image.height - 1);
    const uint8_t* texel = &image.rgba8[(size_t(y) * image.width + size_t(x)) * 4];
    // Saturated texels are kept at their clamped value: a lower bound, but leaving them out
    // would let lights grow unchecked where q3map2 saturated (measured 5x too bright on oa_dm6).
    samples.push_back({p, normal, float(texel[0]) + float(texel[1]) + float(texel[2])});
  }
  return samples;
}

float colorSum(const WorldLight& l) { return std::max(0.0f, l.color.r) + std::max(0.0f, l.color.g) + std::max(0.0f, l.color.b); }

/// Unshadowed light value a unit-valued inverse-square point light at `light` gives the sample
/// (q3map2's pointScale, cosine and 16-unit distance clamp), summed over RGB.
float pointGain(const Sample& s, const WorldLight& light) {
  const glm::vec3 toLight = light.position - s.position;
  const float d = glm::length(toLight);
  if (!(d > 1e-3f)) return 0.0f;
  const float cosine = glm::dot(s.normal, toLight) / d;
  if (!(cosine > 0.0f)) return 0.0f;
  if (light.type == WorldLightType::Spot && glm::dot(-toLight / d, light.direction) < light.cosOuterAngle) return 0.0f;
  const float clamped = std::max(d, kMinLightDistance);
  return kQ3mapPointScale * cosine / (clamped * clamped) * colorSum(light);
}

/// Light value (summed over RGB) an authored light gives the sample, shadows included.
float authoredLight(const Sample& s, const WorldLight& light, const glm::vec3& origin, const SegmentBlocked& blocked,
                    size_t& rays) {
  if (light.type == WorldLightType::Sun) {
    const float len = glm::length(light.direction);
    if (!(len > 1e-6f)) return 0.0f;
    const glm::vec3 toward = -light.direction / len;
    const float cosine = glm::dot(s.normal, toward);
    if (!(cosine > 0.0f)) return 0.0f;
    ++rays;
    return blocked(origin, origin + toward * kSunDistance) ? 0.0f : light.quakeIntensity * cosine * colorSum(light);
  }
  float value;
  if (light.linearFalloff) {
    const glm::vec3 toLight = light.position - s.position;
    const float d = glm::length(toLight);
    const float cosine = d > 1e-3f ? glm::dot(s.normal, toLight) / d : 0.0f;
    value = cosine > 0.0f ? std::max(0.0f, cosine * light.quakeIntensity * kQ3mapPointScale * kQ3mapLinearScale - d) *
                                colorSum(light)
                          : 0.0f;
  } else {
    value = light.quakeIntensity * pointGain(s, light);
  }
  if (!(value > 0.0f)) return 0.0f;
  ++rays;
  return blocked(origin, light.position) ? 0.0f : value;
}

/// Cosine-weighted share of the hemisphere above the sample through which the sky is seen.
float openSky(const Sample& s, const glm::vec3& origin, const SegmentBlocked& blocked, std::mt19937& rng, int rays) {
  const glm::vec3 n = s.normal;
  const glm::vec3 helper = std::abs(n.x) > 0.9f ? glm::vec3(0.0f, 1.0f, 0.0f) : glm::vec3(1.0f, 0.0f, 0.0f);
  const glm::vec3 t = glm::normalize(glm::cross(helper, n)), b = glm::cross(n, t);
  int open = 0;
  for (int r = 0; r < rays; ++r) {
    const float u = uniform01(rng), v = uniform01(rng);
    const float radius = std::sqrt(u), phi = 6.2831853f * v;
    const glm::vec3 dir = t * (radius * std::cos(phi)) + b * (radius * std::sin(phi)) + n * std::sqrt(std::max(0.0f, 1.0f - u));
    open += blocked(origin, origin + dir * kSunDistance) ? 0 : 1;
  }
  return float(open) / float(rays);
}

/// Light value (summed over RGB) an emitting triangle gives the sample: the renderer's
/// irradiance L * A * cos * cos' / d^2 (d^2 kept above the area near the triangle) in
/// light-value units (x 64 / pi), shadowed towards its centre.
float emitterLight(const Sample& s, const CalibrationEmitter& e, const glm::vec3& origin, const SegmentBlocked& blocked,
                   const LightCalibrationOptions& o, size_t& rays) {
  const glm::vec3 centre = (e.a + e.b + e.c) / 3.0f;
  const glm::vec3 cross = glm::cross(e.b - e.a, e.c - e.a);
  const float twiceArea = glm::length(cross);
  if (!(twiceArea > 0.0f) || !(e.radiance > 0.0f)) return 0.0f;
  const glm::vec3 toEmitter = centre - s.position;
  const float d2 = glm::dot(toEmitter, toEmitter);
  if (!(d2 > 1e-6f)) return 0.0f;
  const glm::vec3 dir = toEmitter / std::sqrt(d2);
  const float cosReceiver = glm::dot(s.normal, dir);
  float cosEmitter = -glm::dot(cross / twiceArea, dir);
  if (e.twoSided) cosEmitter = std::abs(cosEmitter);
  if (!(cosReceiver > 0.0f) || !(cosEmitter > 0.0f)) return 0.0f;
  const float area = 0.5f * twiceArea;
  const float value = kQ3FullBright / 3.14159265f * e.radiance * area * cosReceiver * cosEmitter / std::max(d2, area);
  if (value < o.minTracedValue) return 0.0f;
  ++rays;
  return blocked(origin, centre - dir * 0.5f) ? 0.0f : value;
}

/// Light value (summed over RGB) the scene's own light gives the sample: authored lights,
/// emitting triangles and the open sky, shadows included. Shadow rays towards lights and
/// emitters are counted in `rays` (the sky's are not).
float knownLight(const WorldScene& scene, const Sample& s, const glm::vec3& origin, const SegmentBlocked& blocked,
                 const std::vector<CalibrationEmitter>& emitters, const LightCalibrationOptions& o, std::mt19937& rng,
                 size_t& rays) {
  float value = 0.0f;
  for (const WorldLight& l : scene.lights)
    if (!l.estimated) value += authoredLight(s, l, origin, blocked, rays);
  for (const CalibrationEmitter& e : emitters) value += emitterLight(s, e, origin, blocked, o, rays);
  if (o.skyLightValue > 0.0f && o.skyRays > 0) value += o.skyLightValue * openSky(s, origin, blocked, rng, o.skyRays);
  return value;
}

/// Least-squares weight of a texel: 1 (absolute errors) or 1 / (texel + 32) (relative).
double weightOf(float texel, const LightCalibrationOptions& o) {
  return o.relativeErrors ? 1.0 / (double(texel) + 32.0) : 1.0;
}

/// One fitted light's gain on one sample.
struct Entry {
  uint32_t light;
  float gain;
};

/// min 1/2 x'(G + L)x - (b + L x0)'x subject to lower <= x <= upper (lower >= 0), by
/// coordinate descent; the last unknown is the constant (no prior).
std::vector<double> solveBounded(const std::vector<double>& gram, const std::vector<double>& rhs, std::vector<double> x,
                                 const std::vector<double>& lower, const std::vector<double>& upper, int sweeps) {
  const size_t n = rhs.size();
  std::vector<double> gradient(n);
  for (size_t i = 0; i < n; ++i) {
    double g = -rhs[i];
    for (size_t k = 0; k < n; ++k) g += gram[i * n + k] * x[k];
    gradient[i] = g;
  }
  for (int sweep = 0; sweep < sweeps; ++sweep) {
    double largest = 0.0, scale = 1e-12;
    for (size_t i = 0; i < n; ++i) {
      const double diagonal = gram[i * n + i];
      if (!(diagonal > 0.0)) continue;
      const double updated = std::clamp(x[i] - gradient[i] / diagonal, lower[i], upper[i]);
      const double delta = updated - x[i];
      if (delta == 0.0) continue;
      x[i] = updated;
      for (size_t k = 0; k < n; ++k) gradient[k] += delta * gram[k * n + i];
      largest = std::max(largest, std::abs(delta));
      scale = std::max(scale, std::abs(updated));
    }
    if (largest < 1e-6 * scale) break;
  }
  return x;
}

}  // namespace

float knownLightAt(const WorldScene& scene, const glm::vec3& position, const glm::vec3& normal,
                   const SegmentBlocked& blocked, const std::vector<CalibrationEmitter>& emitters,
                   const LightCalibrationOptions& o) {
  const float length = glm::length(normal);
  if (!blocked || !finite3(position) || !(length > 1e-4f) || !std::isfinite(length)) return 0.0f;
  const Sample s{position, normal / length, 0.0f};
  const glm::vec3 origin = s.position + s.normal * o.surfaceOffset;
  size_t rays = 0;
  std::mt19937 rng(o.seed ^ 0x27d4eb2fu);
  const float value = knownLight(scene, s, origin, blocked, emitters, o, rng, rays);
  return std::isfinite(value) ? value : 0.0f;
}

std::vector<WorldLight> calibrateEstimatedLights(const WorldScene& scene, const std::vector<WorldLight>& lights,
                                                 const std::vector<WorldLight>& gridCandidates, const SegmentBlocked& blocked,
                                                 const LightCalibrationOptions& o, LightCalibrationStats* statsOut,
                                                 const std::vector<CalibrationEmitter>& emitters,
                                                 const PointInSolid& inSolid,
                                                 const std::vector<WorldLight>& lightmapCandidates) {
  LightCalibrationStats stats;
  // The lights to fit: estimated ones, then the rejected candidates.
  std::vector<const WorldLight*> fitted;
  std::vector<const WorldLight*> solid;   // estimated lights inside solid: dropped
  for (const WorldLight& l : lights)
    if (l.estimated && l.type == WorldLightType::Point && !l.linearFalloff) {
      if (inSolid && inSolid(l.position)) solid.push_back(&l);
      else fitted.push_back(&l);
    }
  const size_t estimatedCount = fitted.size();
  for (const WorldLight& l : gridCandidates)
    if (o.admitCandidates && fitted.size() < estimatedCount + o.maxCandidates && l.estimated && l.type == WorldLightType::Point && !l.linearFalloff && finite3(l.position)) {
      if (inSolid && inSolid(l.position)) ++stats.inSolid;
      else fitted.push_back(&l);
    }
  const size_t gridCount = fitted.size();
  for (const WorldLight& l : lightmapCandidates)
    if (o.admitCandidates && fitted.size() < gridCount + o.maxLightmapCandidates && l.estimated &&
        l.type == WorldLightType::Point && !l.linearFalloff && finite3(l.position)) {
      if (inSolid && inSolid(l.position)) ++stats.inSolid;
      else fitted.push_back(&l);
    }
  stats.inSolid += solid.size();
  if (fitted.empty() || !blocked) {
    if (statsOut) *statsOut = stats;
    return lights;
  }
  LightCalibrationOptions budgeted = o;
  // The budget counts the grid's lights: lightmap candidates light small regions (few shadow
  // rays each) and must not thin out the samples the grid's lights were admitted with.
  const size_t budgetLights = std::max<size_t>(1, gridCount > 0 ? gridCount : fitted.size());
  budgeted.maxSamples = std::min(o.maxSamples, std::max<size_t>(1000, o.maxLightSamplePairs / budgetLights));
  const std::vector<Sample> samples = sampleLightmaps(scene, budgeted);
  stats.samples = samples.size();
  if (samples.empty()) {
    if (statsOut) *statsOut = stats;
    return lights;
  }

  std::mt19937 rng(o.seed ^ 0x5bd1e995u);
  // Gains (shadowed) of every fitted light per sample, and the authored lights' light.
  const size_t k = fitted.size(), n = k + 1;   // + the constant
  std::vector<double> gram(n * n, 0.0), rhs(n, 0.0);
  std::vector<size_t> litSamples(k, 0);
  std::vector<Entry> entries;
  double sumTexel = 0.0, sumBefore = 0.0;
  std::vector<std::vector<Entry>> perSample(samples.size());
  std::vector<float> targets(samples.size());
  std::vector<double> weights(samples.size(), 1.0);
  for (size_t j = 0; j < samples.size(); ++j) {
    const Sample& s = samples[j];
    const glm::vec3 origin = s.position + s.normal * o.surfaceOffset;
    const float authored = knownLight(scene, s, origin, blocked, emitters, o, rng, stats.shadowRays);
    stats.shadowRays += o.skyRays > 0 && o.skyLightValue > 0.0f ? size_t(o.skyRays) : 0;
    entries.clear();
    float predicted = authored;
    for (size_t i = 0; i < k; ++i) {
      const float gain = pointGain(s, *fitted[i]);
      if (!(gain > 0.0f) || gain * 4.0f * std::max(fitted[i]->quakeIntensity, o.minLightValue) < o.minTracedValue) continue;
      ++stats.shadowRays;
      if (blocked(origin, fitted[i]->position)) continue;
      entries.push_back({uint32_t(i), gain});
      if (i < estimatedCount) predicted += gain * fitted[i]->quakeIntensity;
    }
    const float target = s.value - authored;
    sumTexel += s.value;
    sumBefore += predicted;
    targets[j] = target;
    // Relative errors: a dark texel says as much as a bright one (weight 1 / (texel + 32)).
    const double w = weightOf(s.value, o);
    weights[j] = w;
    for (const Entry& a : entries) {
      ++litSamples[a.light];
      for (const Entry& b : entries) gram[a.light * n + b.light] += w * a.gain * b.gain;
      gram[a.light * n + k] += w * a.gain;
      gram[k * n + a.light] += w * a.gain;
      rhs[a.light] += w * a.gain * target;
    }
    gram[k * n + k] += w;
    rhs[k] += w * target;
    perSample[j] = entries;
  }

  // Lights that reach too few samples are not fitted: estimated ones keep their grid value
  // (their column is replaced by a pinned unknown), candidates stay out.
  const size_t minLit = std::max<size_t>(1, o.minLitSamples);
  std::vector<double> start(n, 0.0), upper(n, std::numeric_limits<double>::infinity());
  for (size_t i = 0; i < k; ++i) {
    const double prior = fitted[i]->quakeIntensity;
    start[i] = prior;
    if (fitted[i]->maxQuakeIntensity >= 0.0f) upper[i] = fitted[i]->maxQuakeIntensity;   // NaN: unbounded
    if (litSamples[i] < minLit) {
      for (size_t c = 0; c < n; ++c) gram[i * n + c] = gram[c * n + i] = 0.0;
      rhs[i] = 0.0;
      continue;
    }
    const double lambda = o.priorWeight * gram[i * n + i];
    gram[i * n + i] += lambda;
    rhs[i] += lambda * (i < estimatedCount ? prior : 0.0);
  }
  // Pinned (unfitted) estimated lights still explain part of their samples' light.
  for (size_t j = 0; j < samples.size(); ++j)
    for (const Entry& e : perSample[j])
      if (litSamples[e.light] < minLit && e.light < estimatedCount) {
        const double pinned = double(e.gain) * fitted[e.light]->quakeIntensity;
        for (const Entry& f : perSample[j])
          if (litSamples[f.light] >= minLit) rhs[f.light] -= weights[j] * f.gain * pinned;
        rhs[k] -= weights[j] * pinned;
      }
  // Two solves: the grid's lights and candidates first, as if no lightmap candidate existed;
  // then the lightmap candidates (and the constant) on what they leave, the grid's values kept.
  // Lightmap candidates thus add light where the grid's lights miss it and never take light
  // from where the grid's lights put it.
  std::vector<double> lower(n, 0.0), gridUpper = upper, x = start;
  for (size_t i = gridCount; i < k; ++i) gridUpper[i] = x[i] = 0.0;
  for (size_t i = 0; i < n; ++i) x[i] = std::min(x[i], gridUpper[i]);
  x = solveBounded(gram, rhs, x, lower, gridUpper, o.sweeps);
  if (gridCount < k) {
    std::vector<double> lightmapLower = lower, lightmapUpper = upper;
    for (size_t i = 0; i < gridCount; ++i) lightmapLower[i] = lightmapUpper[i] = x[i];
    x = solveBounded(gram, rhs, x, lightmapLower, lightmapUpper, o.sweeps);
  }

  std::vector<WorldLight> out;
  double sumAfter = 0.0;
  for (size_t j = 0; j < samples.size(); ++j) {
    double predicted = samples[j].value - targets[j];
    for (const Entry& e : perSample[j])
      predicted += double(e.gain) * (litSamples[e.light] < minLit ? (e.light < estimatedCount ? start[e.light] : 0.0)
                                                                 : x[e.light]);
    sumAfter += predicted;
  }
  size_t next = 0;
  for (const WorldLight& l : lights) {
    if (std::find(solid.begin(), solid.end(), &l) != solid.end()) continue;
    if (next < estimatedCount && &l == fitted[next]) {
      const size_t i = next++;
      if (litSamples[i] < minLit) {
        out.push_back(l);
        continue;
      }
      if (!(x[i] >= o.minLightValue)) {
        ++stats.dropped;
        continue;
      }
      WorldLight refit = l;
      refit.quakeIntensity = float(x[i]);
      refit.intensity = pointLightIntensity(refit.quakeIntensity);
      out.push_back(refit);
      ++stats.refitted;
      continue;
    }
    out.push_back(l);
  }
  for (size_t i = estimatedCount; i < k; ++i) {
    if (litSamples[i] < minLit || !(x[i] >= o.minLightValue)) continue;
    WorldLight admitted = *fitted[i];
    admitted.quakeIntensity = float(x[i]);
    admitted.intensity = pointLightIntensity(admitted.quakeIntensity);
    admitted.source += ", admitted by the lightmaps (first guess " + std::to_string(int(fitted[i]->quakeIntensity)) +
                       ", " + std::to_string(litSamples[i]) + " texels)";
    out.push_back(admitted);
    ++stats.admitted;
    stats.admittedFromLightmaps += i >= gridCount ? 1 : 0;
  }
  const double count = double(samples.size());
  stats.unexplained = float(x[k]);
  stats.meanTexel = float(sumTexel / count);
  stats.meanBefore = float(sumBefore / count);
  stats.meanAfter = float(sumAfter / count);
  if (statsOut) *statsOut = stats;
  return out;
}

}  // namespace pa::recovery
