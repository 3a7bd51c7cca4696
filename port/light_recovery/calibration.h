#pragma once
// Calibration of light-grid estimated lights against the baked lightmaps.
//
// The light grid gives positions well but values poorly (its directed colour is a blend of
// every light a point sees). The lightmaps are what q3map2 computed on the surfaces, so they
// are the ground truth: the calibration samples lightmap texels on the world's surfaces
// (position and normal from the triangle, value from the texel the lightmap UV names),
// predicts each texel's direct light from every estimated light with q3map2's falloff
// (value * pointScale * cos / max(d, 16)^2, shadowed through a caller-supplied visibility
// test), and fits the light values by non-negative least squares, with a non-negative
// constant for what no point light explains (bounced light, ambient, surface lights) and a
// weak prior towards the grid's values. Rejected grid candidates (the estimator's `rejected`)
// join the fit and are admitted when the lightmaps need them. Authored lights stay as they are
// and their light is subtracted first. Lightmap candidates (lightmap_candidates.h) are fitted
// in a second solve, on what the grid's lights leave, with the grid's values kept: they add
// light where the grid's lights miss it, each below its WorldLight::maxQuakeIntensity.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include <glm/vec3.hpp>

#include "port/q3formats/world/world_scene.h"

namespace pa::recovery {

class EmitterIndex;   // emitter_index.h

/// True when a point lies inside solid geometry (a light there lights nothing the lightmaps
/// saw, but leaks through cracks between brushes in a renderer).
using PointInSolid = std::function<bool(const glm::vec3& point)>;

/// True when the straight segment from `from` to `to` hits an opaque surface.
using SegmentBlocked = std::function<bool(const glm::vec3& from, const glm::vec3& to)>;

/// An emitting triangle as the renderer lights with it (q3map_surfacelight, glow stages): its
/// light is subtracted from the texels like the authored lights'.
struct CalibrationEmitter {
  glm::vec3 a, b, c;            ///< Corners (Quake units).
  float radiance = 0.0f;        ///< Emitted radiance, summed over RGB (renderer units).
  bool twoSided = false;        ///< Emits from both faces (else towards its counter-clockwise front).
  int32_t group = -1;           ///< Emitter group whose scale fitEmitterScales fits (its material); -1: known light.
};

/// Knobs of the calibration.
struct LightCalibrationOptions {
  size_t maxSamples = 12000;       ///< Lightmap texels sampled (area-weighted over world surfaces).
  uint32_t seed = 0x9e3779b9u;     ///< Sample placement (deterministic).
  float surfaceOffset = 1.0f;      ///< Shadow rays start this far off the surface (Quake units).
  float minTracedValue = 0.5f;     ///< Light-value contributions below this (at 4x the grid value) are not traced.
  float priorWeight = 0.002f;      ///< Pull towards the grid value, relative to a light's own data weight (regularises look-alike lights).
  float minLightValue = 15.0f;     ///< Fitted lights weaker than this are dropped.
  size_t minLitSamples = 12;       ///< A light must light this many samples to be refitted or admitted.
  int sweeps = 400;                ///< Coordinate-descent sweeps of the NNLS solve.
  /// Light value (summed over RGB) a surface open to the whole sky receives from the sky as the
  /// renderer lights with it (64 x its lighting radiance): subtracted from the texels like the
  /// authored lights, so that estimated lights never take the sky's share. 0 = no sky light.
  float skyLightValue = 0.0f;
  bool relativeErrors = true;      ///< Weight texels by 1 / (value + 32) (else plain least squares).
  size_t maxCandidates = 256;      ///< Candidates examined (the estimator lists the strongest peaks first).
  size_t maxLightSamplePairs = 2000000;  ///< Budget: samples x fitted grid lights (fewer samples on crowded maps).
  bool admitCandidates = true;     ///< Fit the candidates too (false: refit the estimated lights only).
  int skyRays = 16;                ///< Cosine-distributed rays per sample measuring its open sky.
  size_t maxLightmapCandidates = 256;   ///< Lightmap candidates examined (besides maxCandidates grid candidates).
  /// Propose lightmap candidates (lightmap_candidates.h) on maps whose lights were stripped
  /// (calibrateWithShadowRays, recover_lights.h).
  bool lightsFromLightmaps = true;
};

/// What the calibration did (for logs, tools and tests).
struct LightCalibrationStats {
  size_t samples = 0;            ///< Texels used.
  size_t shadowRays = 0;         ///< Visibility tests made.
  size_t refitted = 0;           ///< Estimated lights whose value was refitted.
  size_t dropped = 0;            ///< Estimated lights fitted below minLightValue.
  size_t admitted = 0;           ///< Rejected candidates admitted (grid and lightmap candidates).
  size_t admittedFromLightmaps = 0;  ///< Of those, lightmap candidates (lightmap_candidates.h).
  size_t inSolid = 0;            ///< Estimated lights and candidates dropped for lying inside solid geometry.
  float unexplained = 0.0f;      ///< Fitted constant (light value, summed over RGB).
  float meanTexel = 0.0f;        ///< Mean texel (light value, summed over RGB).
  float meanBefore = 0.0f;       ///< Mean predicted direct light with the grid values.
  float meanAfter = 0.0f;        ///< Mean predicted direct light with the fitted values.
  size_t lightmapPeaks = 0;      ///< Lightmap peaks examined by the caller (lightmap_candidates.h).
  size_t lightmapUnexplained = 0;  ///< Of those, peaks the known light leaves unexplained.
  size_t lightmapCandidates = 0;   ///< Lightmap candidates handed to the calibration.
  double lightmapMs = 0.0;         ///< Time the lightmap candidates took (milliseconds).
};

/// `lights` with every estimated light's value refitted against the scene's lightmaps and the
/// candidates the lightmaps confirm added (`gridCandidates`, then `lightmapCandidates`, e.g. from
/// lightsFromLightmaps). Lights not estimated are returned unchanged. Returns `lights` as they
/// are when there is nothing to fit (no estimated light or candidate, no lightmapped surface).
std::vector<q3::WorldLight> calibrateEstimatedLights(const q3::WorldScene& scene, const std::vector<q3::WorldLight>& lights,
                                                     const std::vector<q3::WorldLight>& gridCandidates,
                                                     const SegmentBlocked& blocked,
                                                     const LightCalibrationOptions& options = {},
                                                     LightCalibrationStats* stats = nullptr,
                                                     const std::vector<CalibrationEmitter>& emitters = {},
                                                     const PointInSolid& inSolid = {},
                                                     const std::vector<q3::WorldLight>& lightmapCandidates = {});

/// Light value (summed over RGB) that the scene's authored (not estimated) lights, `emitters` (made
/// for options.minTracedValue: an index made for another threshold visits every emitter) and
/// the sky (options.skyLightValue, options.skyRays rays) give a surface point, shadows traced as
/// the calibration traces them: the light no estimated light is needed for.
float knownLightAt(const q3::WorldScene& scene, const glm::vec3& position, const glm::vec3& normal,
                   const SegmentBlocked& blocked, const EmitterIndex& emitters,
                   const LightCalibrationOptions& options = {});

}  // namespace pa::recovery
