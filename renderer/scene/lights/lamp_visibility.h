#pragma once
// Which lamps the surfaces of a region cannot see. The light sampler weighs every lamp at a
// shading point by its unshadowed contribution; in a lamp-lit level most of the lamps in range
// stand behind a wall (oa_dm3: four pixels in five got no light from a 1-sample frame), so most
// samples end on a shadow ray that hits the wall, and the frame the denoiser gets is a few lit
// specks on black. This map, traced once from the scene's surfaces, records per grid cell and
// facing (surface_grid.h) the lamps that no shadow ray from the surface points there reached; the
// sampler weighs those at kHiddenWeight of their contribution. Unbiased: a hidden lamp keeps a
// positive weight, so a bin judged wrongly (a point that sees a lamp none of the bin's sampled
// points saw) costs variance there, never light.
//
// Built from the same surface points as EnvironmentVisibility: per bin and lamp, shadow rays from
// the bin's points (up to kMostRays of them) toward the lamp's centre (a sphere lamp's near side)
// until one arrives; a lamp counts as hidden only when at least kLeastRays rays were traced and none
// arrived (points outside its range, spot cone or front hemisphere trace nothing). The map names
// the lamps it was traced for: the sampler applies it to a lamp only when that lamp sits at the
// same index with the same position, range, radius, falloff and cone (a map's lamps, committed
// first and in a fixed order); lamps that came later or moved (dynamic lights) keep their full
// weight everywhere.
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "renderer/core/bounds.h"
#include "renderer/scene/lights/surface_grid.h"
#include "renderer/scene/scene_types.h"

namespace pa {

/// Per bin of a surface grid, the lamps no shadow ray from its surfaces reached. Immutable once built.
class LampVisibility {
 public:
  /// Cells along the longest axis of the grid.
  static constexpr uint32_t kCellsLongestAxis = 64;
  /// Least rays traced toward a lamp from a bin before the lamp may count as hidden there.
  static constexpr uint32_t kLeastRays = 4;
  /// Most rays traced toward a lamp from one bin.
  static constexpr uint32_t kMostRays = 8;
  /// Most (bin, lamp) pairs judged: above it (some 800 lamps over a level's bins, about a minute
  /// of rays on two cores) the map is left empty.
  static constexpr uint64_t kMostPairs = uint64_t{1} << 25;
  /// Share of its weight a hidden lamp keeps in the sampler's choice.
  static constexpr float kHiddenWeight = 1.0f / 16.0f;

  /// True when a shadow ray from `from` reaches point `to` (on the lamp).
  using ReachTest = std::function<bool(const glm::vec3& from, const glm::vec3& to)>;

  LampVisibility() = default;
  /// Traces from `points` toward each of `lamps` (point and spot lights; others are never hidden).
  LampVisibility(std::span<const SurfacePoint> points, std::span<const LightDesc> lamps, const ReachTest& reaches);

  /// The row of hidden-lamp bits for point p on a surface facing n; -1 where no lamp is hidden
  /// (outside the grid, bins without points or without a hidden lamp).
  int64_t row(const glm::vec3& p, const glm::vec3& n) const;
  /// Bits of lamps 8 x group .. 8 x group + 7 hidden in `row` (bit i: lamp 8 x group + i); 0
  /// for groups past the lamps the map was traced for (a sampler's later lamps: dynamic lights).
  uint8_t hidden(int64_t row, uint32_t group) const {
    return group < groups_ ? bits_[size_t(row) * groups_ + group] : uint8_t(0);
  }
  /// The bytes of `row`, hidden(row, g) for g below groupCount() (one pointer for a point's groups).
  const uint8_t* rowBits(int64_t row) const { return bits_.data() + size_t(row) * groups_; }
  /// Groups of eight lamps the map was traced for.
  uint32_t groupCount() const { return groups_; }
  /// The lamps the map was traced for, in order.
  std::span<const LightDesc> lamps() const { return lamps_; }
  /// True when `a` stands where lamp `b` stood when traced (same kind, place, reach and cone).
  static bool sameLamp(const LightDesc& a, const LightDesc& b);
  /// Bins with at least one hidden lamp, and (lamp, bin) pairs hidden in all.
  size_t rowCount() const { return groups_ == 0 ? 0 : bits_.size() / groups_; }
  size_t hiddenCount() const;
  /// Shadow rays traced to build the map.
  uint64_t rayCount() const { return rays_; }

 private:
  SurfaceGrid grid_;
  std::vector<uint32_t> rowOf_;   ///< Per grid bin: its row in bits_, or UINT32_MAX (no lamp hidden).
  std::vector<uint8_t> bits_;     ///< Rows of groups_ bytes.
  uint32_t groups_ = 0;           ///< Groups of eight lamps.
  std::vector<LightDesc> lamps_;
  uint64_t rays_ = 0;
};

/// The last map built and what it was traced for: a commit reuses it while the scene bounds stay
/// within 5% of their diagonal and at least half of its lamps stand where they were, in order (a
/// game re-commits every frame with its dynamic lights after the map's lamps).
class LampVisibilityCache {
 public:
  /// The map for these lamps (`bounds`: the scene's), traced from surfacePoints() with `reaches`
  /// unless the kept map still fits; null when there is no lamp.
  std::shared_ptr<const LampVisibility> get(const Bounds& bounds, std::span<const LightDesc> lamps,
                                            const std::function<std::vector<SurfacePoint>()>& surfacePoints,
                                            const LampVisibility::ReachTest& reaches);

 private:
  std::shared_ptr<const LampVisibility> map_;
  Bounds bounds_;
};

}  // namespace pa
