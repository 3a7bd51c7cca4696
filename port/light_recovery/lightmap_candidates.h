#pragma once
// Point-light candidates read from the baked lightmaps themselves.
//
// Where the light grid is too coarse (czest1tourney: gridsize 256) or its directions blend many
// lights, the lightmaps still show where light fell. Every lightmap texel covered by a world
// triangle is placed in the world (position and normal from the triangle). Peaks of the texel
// values (a local maximum in the lightmap, the strongest within a world-space radius, standing
// out from its surroundings) that the scene's known light (authored lights, emitters, sky: a
// caller-supplied prediction) leaves mostly unexplained become candidates: a point light along
// the peak's normal at the height whose q3map2 falloff (cos / max(d, 16)^2 plus a constant) best
// fits the texels around the peak on its plane, not inside solid and seeing the peak. The
// lightmap calibration (calibration.h) then fits their values against the lightmaps,
// shadowed, and admits those the lightmaps confirm.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include <glm/vec3.hpp>

#include "port/light_recovery/calibration.h"
#include "port/q3formats/world/world_scene.h"

namespace pa::recovery {

/// One lightmap texel placed on the world surface it lights.
struct LightmapTexel {
  glm::vec3 position{0.0f};   ///< World position of the texel centre (Quake units).
  glm::vec3 normal{0.0f};     ///< Unit surface normal there.
  float value = 0.0f;         ///< Texel light value, summed over RGB (stored bytes).
};

/// The world model's lightmap texels: per lightmap, which texel of `texels` each pixel is.
struct LightmapTexels {
  /// One lightmap's pixels: index into texels, -1 where no world triangle covers the pixel.
  struct Page {
    uint32_t lightmap = 0;   ///< Index into q3::WorldScene::lightmaps.
    uint32_t width = 0, height = 0;
    std::vector<int32_t> texel;
  };
  std::vector<Page> pages;
  std::vector<LightmapTexel> texels;
};

/// Places the texels of the world model's lightmapped, visible, opaque, non-emitting surfaces. A pixel belongs to the first triangle whose lightmap UVs contain its
/// centre. Bounded: at most `maxPixelTests` pixel-in-triangle tests and `maxPagePixels` pixels of
/// lightmap pages; malformed meshes and lightmaps are skipped.
LightmapTexels placeLightmapTexels(const q3::WorldScene& scene, size_t maxPixelTests = size_t(1) << 24,
                                   size_t maxPagePixels = size_t(1) << 23);

/// Light value (summed over RGB) the scene's known light gives a surface point (position, normal).
using KnownLightAt = std::function<float(const glm::vec3& position, const glm::vec3& normal)>;

/// Knobs of the lightmap candidates.
struct LightmapLightOptions {
  float minPeakValue = 48.0f;       ///< Peaks dimmer than this (summed RGB, 64 x 3 = full bright white) are ignored.
  float minProminence = 0.12f;      ///< A peak must exceed the lowest texel 2 pixels around it by this share.
  float suppressionRadius = 48.0f;  ///< A peak must be the brightest within this distance (Quake units).
  float minUnexplainedShare = 0.5f; ///< Share of the peak the known light must leave unexplained.
  size_t maxKnownEvaluations = 512; ///< Brightest peaks examined (their known light is evaluated until maxCandidates are found).
  int fitWindow = 16;               ///< Falloff fit over the peak's lightmap pixels within this many pixels...
  float fitRadius = 384.0f;         ///< ...and this distance on its plane.
  float minHeight = 16.0f;          ///< Candidate heights above the peak: minHeight x 1.08^k up to maxHeight (q3map2 clamps distances below 16).
  float maxHeight = 768.0f;
  /// A candidate may give its own (unsaturated) peak at most this times the peak's unexplained
  /// light (WorldLight::maxQuakeIntensity).
  float peakSlack = 1.5f;
  float mergeDistance = 32.0f;      ///< Candidates this close to a stronger one or a known light are dropped.
  size_t maxCandidates = 64;        ///< Candidates returned (from the brightest unexplained peaks).
};

/// What the lightmap candidates step did (for logs, tools and tests).
struct LightmapLightStats {
  size_t texels = 0;         ///< Lightmap texels placed on the world.
  size_t peaks = 0;          ///< Peaks found (before the known-light test).
  size_t unexplained = 0;    ///< Peaks the known light leaves unexplained (examined until maxCandidates are found).
  size_t candidates = 0;     ///< Candidates returned.
  size_t rejected = 0;       ///< Peaks without a valid height (every height blocked or in solid).
};

/// Point-light candidates (estimated, WorldLightType::Point, the peak's colour, first-guess value)
/// in front of the lightmap peaks that `known` does not explain, brightest peak first. `avoid` lists lights
/// already fitted or known (no candidate within mergeDistance of them). `blocked` and `inSolid`
/// may be empty (then not tested). Never throws on hostile data; `stats` may be null.
std::vector<q3::WorldLight> lightsFromLightmaps(const q3::WorldScene& scene, const KnownLightAt& known,
                                                const std::vector<glm::vec3>& avoid, const SegmentBlocked& blocked,
                                                const PointInSolid& inSolid, const LightmapLightOptions& options = {},
                                                LightmapLightStats* stats = nullptr);

}  // namespace pa::recovery
