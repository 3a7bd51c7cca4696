#pragma once
// Point lights estimated from a map's baked light grid (BSP lump 15).
//
// q3map2 strips `light` entities from most compiled maps, but every grid point still records
// the light it received: an ambient colour, a "directed" colour and the direction towards the
// dominant light. For a point light of value V at distance d, q3map2 stores
// directed = V * pointScale / max(d, 16)^2 (light-value units, see world_lights.h).
// The estimator casts a line from every grid point with a significant directed component
// along its direction, votes the lines into a 3D accumulator, takes its peaks as light
// positions, refines each by least squares over the lines that pass close to it, and fits the
// light value from the directed magnitudes with q3map2's inverse-square falloff. Lines already
// explained by the scene's own lights (entity lights, suns, surface lights) are left out.
// A candidate is kept only when its lines agree on one light value and fall off like a point
// light (crossings of lines towards area lights or the sky do neither), and when the blend
// q3map2 would store from the other lights does not already explain its lines.
#include <cstddef>
#include <utility>
#include <vector>

#include <glm/vec3.hpp>

#include "port/q3formats/world/world_scene.h"

namespace pa::recovery {

/// Light the scene already has; the estimator must not create it again.
struct KnownLighting {
  /// Entity point/spot lights: origin and q3map2 light value.
  std::vector<std::pair<glm::vec3, float>> pointLights;
  std::vector<glm::vec3> towardSuns;    ///< Unit directions towards each sun.
  /// Emitting triangles (q3map_surfacelight) as bounding spheres: centre and radius.
  std::vector<std::pair<glm::vec3, float>> emitters;
};

/// Knobs of the estimator (defaults measured on OpenArena maps, see docs/performance.md, "Lights").
struct LightEstimateOptions {
  float minDirected = 12.0f;        ///< Grid points whose directed colour (max channel, 0..255) is weaker do not vote.
  float voxelSize = 16.0f;          ///< Accumulator voxel edge (Quake units); grown when the map is huge.
  size_t maxVoxels = size_t(1) << 21;  ///< Accumulator budget (floats).
  float maxLightValue = 20000.0f;   ///< Brightest plausible light value: bounds how far a line is followed.
  float maxLineLength = 2048.0f;    ///< Lines end here at the latest (Quake units).
  float minVotes = 24.0f;           ///< Peak threshold (votes summed over 3x3x3 voxels: ~3 per line).
  size_t minLines = 6;              ///< A light must be confirmed by this many grid points.
  float lineTolerance = 24.0f;      ///< Distance (units) within which a line counts as passing through a light...
  float angularTolerance = 0.03f;   ///< ...plus this much per unit of distance (direction bytes are 1.4 degrees apart).
  float explainedRadius = 64.0f;    ///< Candidates this close to a known light or emitter are dropped.
  float sunAngleCos = 0.9985f;      ///< Grid directions within ~3 degrees of a sun are the sun's.
  float blendAngleCos = 0.9976f;    ///< A grid direction within ~4 degrees of the other lights' blend is theirs.
  float minLightValue = 15.0f;      ///< Weaker estimates are dropped.
  /// Light values implied by a candidate's lines (directed * d^2 / pointScale) must agree:
  /// upper quartile / lower quartile at most this...
  float maxValueSpread = 1.6f;
  /// ...and at most this unless log(directed) falls with log(distance) steeper than
  /// pointFalloffSlope (-2 for an isolated inverse-square light). Candidates whose lines span
  /// too few distances (nearest to farthest under 1.5x) to measure a falloff are dropped.
  float looseValueSpread = 1.25f;
  float pointFalloffSlope = -1.0f;
  float minFalloffSlope = -0.5f;    ///< A flatter falloff is never a point light.
  size_t maxLights = 1024;          ///< Upper bound on the number of estimated lights.
  size_t maxPeaks = 2048;           ///< Strongest accumulator peaks examined (bounds the time on sky-lit maps).
};

/// What the estimator did (for logs and measurements).
struct LightEstimateStats {
  size_t gridPoints = 0;      ///< Points in the grid.
  size_t votingLines = 0;     ///< Points with a significant, unexplained directed component.
  size_t peaks = 0;           ///< Accumulator peaks examined.
  size_t lights = 0;          ///< Lights returned.
  float voxelSize = 0.0f;     ///< Accumulator voxel edge used.
};

/// Point lights (WorldLightType::Point, inverse-square, converted intensities) that explain
/// the light grid's directed light not explained by `known`. Returns nothing for an empty or
/// inconsistent grid (never throws on hostile data); `stats` may be null. `rejected`, when
/// given, receives the candidates that only the value-spread / falloff checks turned down
/// (weak lights whose grid lines are blended with others), for a later lightmap calibration.
std::vector<q3::WorldLight> estimateLightsFromGrid(const q3::WorldLightGrid& grid, const KnownLighting& known,
                                                   const LightEstimateOptions& options = {},
                                                   LightEstimateStats* stats = nullptr,
                                                   std::vector<q3::WorldLight>* rejected = nullptr);

/// The light the scene's own (not estimated) lights, suns and q3map_surfacelight surfaces already give.
KnownLighting knownLightingOf(const q3::WorldScene& scene);

/// True when the compiler stripped the map's `light` entities: `lights` (a scene's) hold fewer
/// than 16 authored point or spot lights (a map that kept that many was compiled with
/// -keeplights or never stripped, and its own lights are the authority). Such maps get
/// estimated lights.
bool lightsStripped(const std::vector<q3::WorldLight>& lights);

}  // namespace pa::recovery
