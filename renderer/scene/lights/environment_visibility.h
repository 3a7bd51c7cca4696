#pragma once
// Where the environment (sun lights and sky) can reach: a coarse grid over the scene whose bins
// record which fraction of the rays toward the suns and the sky escape from the surfaces in them.
// The light sampler gives the sun and sky categories a share in proportion to their power through
// the sky windows, whatever the shading point sees; in the closed corridors of a level under a
// bright sun those samples all end on a wall (black pixels at few samples). The sampler scales
// their share by the bin's fraction (never below kHiddenShare: a bin judged wrongly costs
// variance, never bias).
//
// Built from points on the scene's surfaces (spread over them by area, moved a hair off their
// front face, the side a game level's surfaces are seen from): from each, one ray along every
// sun's direction (none escapes toward a sun behind the surface) and kSkyRaysPerPoint uniform
// directions of its front hemisphere. Each cell keeps one fraction per facing (the dominant axis
// and sign of the normal: six bins), so that the two faces of a wall inside one cell, a closed
// corridor's and an open yard's, are judged apart. Bins without points, and points outside the
// grid, keep the full share (the sampler's choice is then unchanged). The grid (surface_grid.h) has
// kCellsLongestAxis cells along its longest side.
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "renderer/core/bounds.h"
#include "renderer/scene/lights/surface_grid.h"

namespace pa {

/// Coarse map of the cells from which the environment is reachable. Immutable once built.
class EnvironmentVisibility {
 public:
  /// Cells along the longest axis of the grid (the others in proportion, at least 1).
  static constexpr uint32_t kCellsLongestAxis = 96;
  /// Sky rays per surface point.
  static constexpr uint32_t kSkyRaysPerPoint = 4;
  /// Least fraction of the sun and sky share kept (in a bin where no ray escaped).
  static constexpr float kHiddenShare = 1.0f / 128.0f;

  /// True when a ray from origin along unit dir reaches the environment (sky windows pass).
  using EscapeTest = std::function<bool(const glm::vec3& origin, const glm::vec3& dir)>;

  EnvironmentVisibility() = default;
  /// Traces from `points` toward each sun (unit directions the light travels) and, when `sky` is
  /// set, the sky. No finite point, or neither sun nor sky, gives an empty map (all open).
  EnvironmentVisibility(std::span<const SurfacePoint> points, std::span<const glm::vec3> sunDirections, bool sky,
                        const EscapeTest& escapes);

  /// Normal bins per cell.
  static constexpr uint32_t kNormalBins = SurfaceGrid::kNormalBins;
  /// Fraction of the sun and sky share kept at p, on a surface facing unit normal n: in
  /// [kHiddenShare, 1], 1 outside the grid and in bins without points.
  float share(const glm::vec3& p, const glm::vec3& n) const;
  /// Number of bins (cells x kNormalBins, 0 when empty) and of those where no ray escaped.
  size_t binCount() const { return share_.size(); }
  size_t closedCount() const;
  /// The bin of a normal: 2 x dominant axis + (1 when that component is negative).
  static uint32_t normalBin(const glm::vec3& n) { return SurfaceGrid::normalBin(n); }

 private:
  SurfaceGrid grid_;
  std::vector<float> share_;   ///< Per grid bin.
};

/// The last maps built and what they were traced from: a render that needs one retraces only
/// when the number of suns, the sky or the sky windows change or the scene bounds move by more
/// than 5% of their diagonal, not for every moved entity or turned sun (a map that is a little
/// stale costs variance, never bias).
class EnvironmentVisibilityCache {
 public:
  /// The map for these inputs (`bounds`: the scene's), traced from surfacePoints() with `escapes`
  /// unless one of the kept maps matches.
  std::shared_ptr<const EnvironmentVisibility> get(const Bounds& bounds, std::span<const glm::vec3> sunDirections,
                                                   bool sky, std::span<const glm::vec3> skyWindows,
                                                   const std::function<std::vector<SurfacePoint>()>& surfacePoints,
                                                   const EnvironmentVisibility::EscapeTest& escapes);

 private:
  /// One traced map and the inputs it was traced for.
  struct Entry {
    std::shared_ptr<const EnvironmentVisibility> map;
    Bounds bounds;
    size_t sunCount = 0;   ///< Suns it was traced for (directions are not compared).
    bool sky = false;
    size_t windowCount = 0;
    glm::vec3 windowSum{0.0f};   ///< Summed |area x normal| of the windows.
  };
  /// Maps kept, most recent first: a game alternates scenes within a frame (world view, HUD
  /// model views) and must not retrace at each switch.
  static constexpr size_t kEntries = 4;
  std::vector<Entry> entries_;
};

}  // namespace pa
