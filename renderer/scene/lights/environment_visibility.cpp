#include "renderer/scene/lights/environment_visibility.h"

#include <algorithm>
#include <cmath>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vector_relational.hpp>
#include <tbb/parallel_for.h>

#include "renderer/core/finite.h"
#include "renderer/scene/sampling/sobol_sampler.h"
#include "renderer/scene/sampling/warp.h"

namespace pa {

EnvironmentVisibility::EnvironmentVisibility(std::span<const SurfacePoint> points,
                                             std::span<const glm::vec3> sunDirections, bool sky,
                                             const EscapeTest& escapes) {
  if (sunDirections.empty() && !sky) return;
  grid_ = SurfaceGrid(points, kCellsLongestAxis);
  if (grid_.empty()) return;
  const float offset = grid_.offset();   // off the surface, well inside its cell

  // Per point: its slot (-1 outside the grid) and how many of its rays escaped.
  const uint32_t trials = uint32_t(sunDirections.size()) + (sky ? kSkyRaysPerPoint : 0u);
  std::vector<int64_t> slotOf(points.size(), -1);
  std::vector<uint8_t> escaped(points.size(), 0);
  tbb::parallel_for(size_t{0}, points.size(), [&](size_t i) {
    const SurfacePoint& s = points[i];
    if (!finite(s.position) || !finite(s.normal)) return;
    slotOf[i] = grid_.bin(s.position, s.normal);
    if (slotOf[i] < 0) return;
    const glm::vec3 origin = s.position + offset * s.normal;
    uint32_t count = 0;
    for (const glm::vec3& sun : sunDirections)
      if (glm::dot(-sun, s.normal) > 0.0f && escapes(origin, -sun)) ++count;
    uint32_t h = sampling::hash32(uint32_t(i));
    for (uint32_t r = 0; sky && r < kSkyRaysPerPoint; ++r) {
      const float u0 = sampling::toUnitFloat(h = sampling::hash32(h + 1u));
      const float u1 = sampling::toUnitFloat(h = sampling::hash32(h + 2u));
      glm::vec3 dir = sampling::uniformSphere({u0, u1});
      if (glm::dot(dir, s.normal) < 0.0f) dir = -dir;
      if (escapes(origin, dir)) ++count;
    }
    escaped[i] = uint8_t(std::min(count, 255u));
  });
  // Share of a bin: the fraction of its rays that escaped, at least kHiddenShare; 1 without points.
  std::vector<uint32_t> rays(grid_.binCount(), 0);
  std::vector<uint32_t> hits(rays.size(), 0);
  for (size_t i = 0; i < points.size(); ++i) {
    if (slotOf[i] < 0) continue;
    rays[size_t(slotOf[i])] += trials;
    hits[size_t(slotOf[i])] += escaped[i];
  }
  share_.assign(rays.size(), 1.0f);
  for (size_t b = 0; b < rays.size(); ++b)
    if (rays[b] > 0) share_[b] = std::max(kHiddenShare, float(hits[b]) / float(rays[b]));
}

float EnvironmentVisibility::share(const glm::vec3& p, const glm::vec3& n) const {
  if (share_.empty()) return 1.0f;
  const int64_t at = grid_.bin(p, n);
  return at < 0 ? 1.0f : share_[size_t(at)];
}

size_t EnvironmentVisibility::closedCount() const {
  return size_t(std::count(share_.begin(), share_.end(), kHiddenShare));
}

std::shared_ptr<const EnvironmentVisibility> EnvironmentVisibilityCache::get(
    const Bounds& bounds, std::span<const glm::vec3> sunDirections, bool sky, std::span<const glm::vec3> skyWindows,
    const std::function<std::vector<SurfacePoint>()>& surfacePoints,
    const EnvironmentVisibility::EscapeTest& escapes) {
  glm::vec3 windowSum(0.0f);
  for (const glm::vec3& w : skyWindows) windowSum += glm::abs(w);
  for (size_t i = 0; i < entries_.size(); ++i) {
    const Entry& e = entries_[i];
    // Bounds within 5% of the cached diagonal: moving entities (players, projectiles) nudge the
    // scene's box every frame; a map of their own needs a real change (and other windows).
    const float slack = 0.05f * glm::length(e.bounds.max - e.bounds.min);
    const bool nearBounds = glm::all(glm::lessThanEqual(glm::abs(bounds.min - e.bounds.min), glm::vec3(slack))) &&
                            glm::all(glm::lessThanEqual(glm::abs(bounds.max - e.bounds.max), glm::vec3(slack)));
    // Windows compared with a tolerance: the game re-sends them every frame, and their summed
    // area moves with moving brush entities and summation order.
    const bool nearWindows = skyWindows.size() == e.windowCount &&
                             glm::all(glm::lessThanEqual(glm::abs(windowSum - e.windowSum),
                                                         0.01f * glm::max(glm::abs(windowSum), glm::abs(e.windowSum))));
    // Suns by count only: the game re-sends its directional lights every frame and some of them
    // turn (in demo088 a third one comes and goes); a map traced for older directions costs
    // variance, never bias, and a new map brings other bounds and windows.
    const bool sameSuns = sunDirections.size() == e.sunCount;
    const bool same = nearBounds && sky == e.sky && nearWindows && sameSuns;
    if (!same) continue;
    std::rotate(entries_.begin(), entries_.begin() + static_cast<std::ptrdiff_t>(i),
                entries_.begin() + static_cast<std::ptrdiff_t>(i) + 1);
    return entries_.front().map;
  }
  const std::vector<SurfacePoint> points = surfacePoints();
  Entry entry;
  entry.map = std::make_shared<const EnvironmentVisibility>(points, sunDirections, sky, escapes);
  entry.bounds = bounds;
  entry.sunCount = sunDirections.size();
  entry.sky = sky;
  entry.windowCount = skyWindows.size();
  entry.windowSum = windowSum;
  entries_.insert(entries_.begin(), std::move(entry));
  if (entries_.size() > kEntries) entries_.pop_back();
  return entries_.front().map;
}

}  // namespace pa
