#include "renderer/scene/lights/surface_grid.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <glm/common.hpp>

#include "renderer/core/bounds.h"
#include "renderer/core/finite.h"

namespace pa {

namespace {

/// The box holding the middle of the points on every axis (kOutlierShare cut at each end).
Bounds robustBounds(std::span<const SurfacePoint> points) {
  constexpr double kOutlierShare = 0.01;
  Bounds box;
  std::vector<float> axis;
  for (int a = 0; a < 3; ++a) {
    axis.clear();
    for (const SurfacePoint& p : points)
      if (finite(p.position)) axis.push_back(p.position[a]);
    if (axis.empty()) return Bounds{};
    const size_t lo = size_t(kOutlierShare * double(axis.size()));
    const size_t hi = axis.size() - 1 - lo;
    std::nth_element(axis.begin(), axis.begin() + lo, axis.end());
    box.min[a] = axis[lo];
    std::nth_element(axis.begin(), axis.begin() + hi, axis.end());
    box.max[a] = axis[hi];
  }
  return box;
}

}  // namespace

SurfaceGrid::SurfaceGrid(std::span<const SurfacePoint> points, uint32_t cellsLongestAxis) {
  const Bounds bounds = robustBounds(points);
  if (bounds.empty() || cellsLongestAxis == 0) return;
  const glm::vec3 extent = bounds.max - bounds.min;
  const float longest = std::max({extent.x, extent.y, extent.z});
  if (!(longest > 0.0f) || !std::isfinite(longest)) return;
  const float cell = longest / float(cellsLongestAxis);
  for (int a = 0; a < 3; ++a)
    counts_[a] = std::clamp(uint32_t(std::ceil(extent[a] / cell)), 1u, cellsLongestAxis);
  origin_ = bounds.min;
  // A flat axis (all points on one plane) gets one cell of the common size, centred on the plane.
  cellSize_ = glm::max(extent / glm::vec3(counts_[0], counts_[1], counts_[2]), glm::vec3(cell));
  origin_ -= 0.5f * (cellSize_ * glm::vec3(counts_[0], counts_[1], counts_[2]) - extent);
  offset_ = 1e-4f * longest;
}

uint32_t SurfaceGrid::normalBin(const glm::vec3& n) {
  const glm::vec3 a = glm::abs(n);
  const int axis = a.x >= a.y && a.x >= a.z ? 0 : (a.y >= a.z ? 1 : 2);
  return uint32_t(2 * axis + (n[axis] < 0.0f ? 1 : 0));
}

int64_t SurfaceGrid::bin(const glm::vec3& p, const glm::vec3& n) const {
  const glm::vec3 f = (p - origin_) / cellSize_;
  if (!(f.x >= 0.0f && f.y >= 0.0f && f.z >= 0.0f)) return -1;
  const uint32_t x = uint32_t(f.x), y = uint32_t(f.y), z = uint32_t(f.z);
  if (x >= counts_[0] || y >= counts_[1] || z >= counts_[2]) return -1;
  return int64_t((x + counts_[0] * (size_t{y} + counts_[1] * size_t{z})) * kNormalBins + normalBin(n));
}

}  // namespace pa
