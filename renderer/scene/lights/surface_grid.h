#pragma once
// The coarse grid the light visibility maps share (environment_visibility.h, lamp_visibility.h):
// cells over the box of the middle 98% of a scene's surface points on each axis (far sky boxes
// would stretch it over empty space), each cell split into six bins by the facing of a surface
// (dominant axis and sign of its normal), so that the two faces of a wall inside one cell are
// judged apart.
#include <cstdint>
#include <span>

#include <glm/vec3.hpp>

namespace pa {

/// A point on a surface and the unit normal of the side it is seen from.
struct SurfacePoint {
  glm::vec3 position{0.0f};
  glm::vec3 normal{0.0f, 0.0f, 1.0f};
};

/// Cells and facing bins over a set of surface points. Empty (no bins) until built.
class SurfaceGrid {
 public:
  /// Normal bins per cell.
  static constexpr uint32_t kNormalBins = 6;

  SurfaceGrid() = default;
  /// A grid of `cellsLongestAxis` cells along the longest side of the points' robust box (the
  /// others in proportion, at least 1). Empty when no point is finite or the box is degenerate.
  SurfaceGrid(std::span<const SurfacePoint> points, uint32_t cellsLongestAxis);

  /// True before a build or when the points gave no box.
  bool empty() const { return counts_[0] == 0; }
  /// Number of bins (cells x kNormalBins; 0 when empty).
  size_t binCount() const { return size_t{counts_[0]} * counts_[1] * counts_[2] * kNormalBins; }
  /// The bin of point p on a surface facing n; -1 outside the grid (or when empty).
  int64_t bin(const glm::vec3& p, const glm::vec3& n) const;
  /// A distance well inside a cell, for moving a point off its surface.
  float offset() const { return offset_; }
  /// The bin of a normal: 2 x dominant axis + (1 when that component is negative).
  static uint32_t normalBin(const glm::vec3& n);

 private:
  glm::vec3 origin_{0.0f};
  glm::vec3 cellSize_{1.0f};
  uint32_t counts_[3] = {0, 0, 0};
  float offset_ = 0.0f;
};

}  // namespace pa
