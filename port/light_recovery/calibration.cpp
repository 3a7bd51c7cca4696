// calibrateEstimatedLights: lightmap texel sampling, q3map2 direct-light prediction, NNLS fit.
#include "port/light_recovery/calibration.h"
#include "port/light_recovery/calibration_model.h"

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
using namespace model;

float knownLightAt(const WorldScene& scene, const glm::vec3& position, const glm::vec3& normal,
                   const SegmentBlocked& blocked, const EmitterIndex& emitters, const LightCalibrationOptions& o) {
  const float length = glm::length(normal);
  if (!blocked || !finite3(position) || !(length > 1e-4f) || !std::isfinite(length)) return 0.0f;
  const Sample s{position, normal / length, 0.0f};
  const glm::vec3 origin = s.position + s.normal * o.surfaceOffset;
  size_t rays = 0;
  SampleRandom random(o.seed ^ 0x27d4eb2fu, 0);
  std::vector<uint32_t> near;
  const float value = knownLight(scene, s, origin, blocked, emitters, o, random, rays, near);
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

  // Gains (shadowed) of every fitted light per sample, and the authored lights' light: the
  // shadow rays, most of the cost, traced for the samples in parallel.
  const size_t k = fitted.size(), n = k + 1;   // + the constant
  std::vector<double> gram(n * n, 0.0), rhs(n, 0.0);
  std::vector<size_t> litSamples(k, 0);
  double sumTexel = 0.0, sumBefore = 0.0;
  std::vector<std::vector<Entry>> perSample(samples.size());
  std::vector<float> authoredLight(samples.size());
  std::vector<size_t> raysPerSample(samples.size(), 0);
  const EmitterIndex emitterIndex(emitters, o.minTracedValue);
  parallelOverSamples(samples.size(), [&](size_t begin, size_t end) {
    std::vector<uint32_t> near;
    for (size_t j = begin; j < end; ++j) {
      const Sample& s = samples[j];
      const glm::vec3 origin = s.position + s.normal * o.surfaceOffset;
      SampleRandom random(o.seed ^ 0x5bd1e995u, j);
      authoredLight[j] = knownLight(scene, s, origin, blocked, emitterIndex, o, random, raysPerSample[j], near);
      appendShadowedGains(s, origin, fitted, 0, blocked, o, raysPerSample[j], perSample[j]);
    }
  });
  std::vector<float> targets(samples.size());
  std::vector<double> weights(samples.size(), 1.0);
  for (size_t j = 0; j < samples.size(); ++j) {
    const Sample& s = samples[j];
    const float authored = authoredLight[j];
    const std::vector<Entry>& entries = perSample[j];
    stats.shadowRays += raysPerSample[j] + (o.skyRays > 0 && o.skyLightValue > 0.0f ? size_t(o.skyRays) : 0);
    float predicted = authored;
    for (const Entry& e : entries)
      if (e.light < estimatedCount) predicted += e.gain * fitted[e.light]->quakeIntensity;
    const float target = s.value - authored;
    sumTexel += s.value;
    sumBefore += predicted;
    targets[j] = target;
    // Relative errors: a dark texel says as much as a bright one (weight 1 / (texel + 32)).
    const double w = weightOf(s.value, o);
    weights[j] = w;
    accumulateRow(entries, w, target, n, gram, rhs, litSamples);
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
