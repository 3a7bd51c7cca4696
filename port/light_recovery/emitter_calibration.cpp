// fitEmitterScales: each emitting material's share of its compiled light, fitted to the lightmaps.
#include "port/light_recovery/emitter_calibration.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "port/light_recovery/calibration_model.h"

namespace pa::recovery {

using namespace q3;
using namespace model;

std::vector<float> fitEmitterScales(const WorldScene& scene, const std::vector<WorldLight>& lights,
                                    const std::vector<WorldLight>& gridCandidates,
                                    const std::vector<WorldLight>& lightmapCandidates,
                                    const std::vector<CalibrationEmitter>& emitters, size_t groupCount,
                                    const SegmentBlocked& blocked, const LightCalibrationOptions& o,
                                    EmitterFitStats* statsOut) {
  EmitterFitStats stats;
  std::vector<float> scales(groupCount, 1.0f);
  const bool anyGroup = std::any_of(emitters.begin(), emitters.end(), [&](const CalibrationEmitter& e) {
    return e.group >= 0 && size_t(e.group) < groupCount;
  });
  if (!anyGroup || !blocked) {
    if (statsOut) *statsOut = stats;
    return scales;
  }
  // Unknowns: the groups, the estimated lights, the grid and lightmap candidates, then the
  // constant.
  std::vector<const WorldLight*> fitted;
  for (const WorldLight& l : lights)
    if (l.estimated && l.type == WorldLightType::Point && !l.linearFalloff && finite3(l.position)) fitted.push_back(&l);
  const size_t estimatedCount = fitted.size();
  for (const WorldLight& l : gridCandidates)
    if (o.admitCandidates && fitted.size() < estimatedCount + o.maxCandidates && l.estimated &&
        l.type == WorldLightType::Point && !l.linearFalloff && finite3(l.position))
      fitted.push_back(&l);
  const size_t gridCount = fitted.size();
  for (const WorldLight& l : lightmapCandidates)
    if (fitted.size() < gridCount + o.maxLightmapCandidates && l.estimated && l.type == WorldLightType::Point &&
        !l.linearFalloff && finite3(l.position))
      fitted.push_back(&l);
  const size_t g = groupCount, k = fitted.size(), n = g + k + 1;   // + the constant
  LightCalibrationOptions budgeted = o;
  // A third of the calibration's texels: the shares are few unknowns, and the shadow rays
  // towards every candidate are most of the load-time cost.
  budgeted.maxSamples = std::min(o.maxSamples / 3, std::max<size_t>(1000, o.maxLightSamplePairs / std::max<size_t>(1, gridCount)));
  const std::vector<Sample> samples = sampleLightmaps(scene, budgeted);
  stats.samples = samples.size();
  if (samples.empty()) {
    if (statsOut) *statsOut = stats;
    return scales;
  }
  std::vector<CalibrationEmitter> known, grouped;   // ungrouped emitters: known light
  for (const CalibrationEmitter& e : emitters)
    (e.group >= 0 && size_t(e.group) < groupCount ? grouped : known).push_back(e);
  const EmitterIndex knownIndex(known, o.minTracedValue), groupedIndex(grouped, o.minTracedValue);

  // Each sample's row (its shadow rays are most of the cost) in parallel, then the normal
  // equations in sample order.
  std::vector<std::vector<Entry>> rows(samples.size());
  std::vector<float> fixedLight(samples.size());
  parallelOverSamples(samples.size(), [&](size_t begin, size_t end) {
    std::vector<double> groupGain(g);
    std::vector<uint32_t> near;
    size_t rays = 0;
    for (size_t j = begin; j < end; ++j) {
      const Sample& s = samples[j];
      const glm::vec3 origin = s.position + s.normal * o.surfaceOffset;
      // Authored lights (knownLight skips the estimated ones), the sky and ungrouped emitters.
      SampleRandom random(o.seed ^ 0x68e31da4u, j);
      fixedLight[j] = knownLight(scene, s, origin, blocked, knownIndex, o, random, rays, near);
      std::vector<Entry>& entries = rows[j];
      std::fill(groupGain.begin(), groupGain.end(), 0.0);
      groupedIndex.near(s.position, o.minTracedValue, near);
      for (const uint32_t i : near) {
        const PreparedEmitter& e = groupedIndex.emitters()[i];
        groupGain[size_t(e.group)] += emitterLight(s, e, origin, blocked, o, rays);
      }
      for (size_t i = 0; i < g; ++i)
        if (groupGain[i] > 0.0) entries.push_back({uint32_t(i), float(groupGain[i])});
      appendShadowedGains(s, origin, fitted, uint32_t(g), blocked, o, rays, entries);
    }
  });
  std::vector<double> gram(n * n, 0.0), rhs(n, 0.0);
  std::vector<size_t> lit(n, 0);
  for (size_t j = 0; j < samples.size(); ++j)
    accumulateRow(rows[j], weightOf(samples[j].value, o), double(samples[j].value) - double(fixedLight[j]), n, gram, rhs,
                  lit);

  // Start and prior: groups at their shader's value (1), estimated lights at the grid's value,
  // candidates at 0; unknowns lighting too few texels stay out of the solve at their start.
  const size_t minLit = std::max<size_t>(1, o.minLitSamples);
  std::vector<double> x(n, 0.0), lower(n, 0.0), upper(n, std::numeric_limits<double>::infinity());
  for (size_t i = 0; i < n - 1; ++i) {
    const bool group = i < g;
    const double prior = group ? 1.0 : (i - g < estimatedCount ? double(fitted[i - g]->quakeIntensity) : 0.0);
    x[i] = prior;
    if (group) upper[i] = 1.0;
    else if (fitted[i - g]->maxQuakeIntensity >= 0.0f) upper[i] = fitted[i - g]->maxQuakeIntensity;
    x[i] = std::min(x[i], upper[i]);
    if (lit[i] < minLit) {
      // Pinned: its light at the start value is known light for the others.
      for (size_t c = 0; c < n; ++c)
        if (c != i) rhs[c] -= gram[c * n + i] * x[i];
      for (size_t c = 0; c < n; ++c) gram[i * n + c] = gram[c * n + i] = 0.0;
      rhs[i] = 0.0;
      lower[i] = upper[i] = x[i];
      continue;
    }
    const double lambda = o.priorWeight * gram[i * n + i];
    gram[i * n + i] += lambda;
    rhs[i] += lambda * prior;
  }
  x = solveBounded(gram, rhs, x, lower, upper, o.sweeps);
  for (size_t i = 0; i < g; ++i) {
    if (lit[i] < minLit) continue;
    ++stats.groups;
    scales[i] = std::isfinite(x[i]) ? float(std::clamp(x[i], 0.0, 1.0)) : 1.0f;
    stats.lowered += scales[i] < 0.9f ? 1 : 0;
  }
  if (statsOut) *statsOut = stats;
  return scales;
}

}  // namespace pa::recovery
