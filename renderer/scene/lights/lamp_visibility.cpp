#include "renderer/scene/lights/lamp_visibility.h"

#include <algorithm>
#include <bit>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/vector_relational.hpp>
#include <tbb/parallel_for.h>

#include "renderer/core/finite.h"
#include "renderer/scene/lights/light_sampler.h"

namespace pa {

namespace {

/// True when lamp l can light a surface at p facing n at all (range, cone, front hemisphere).
bool canLight(const LightDesc& l, const glm::vec3& p, const glm::vec3& n) {
  return localLightWeight(l, p) > 0.0f && glm::dot(l.position - p, n) + l.radius > 0.0f;
}

}  // namespace

bool LampVisibility::sameLamp(const LightDesc& a, const LightDesc& b) {
  return a.type == b.type && a.position == b.position && a.direction == b.direction && a.radius == b.radius &&
         a.falloff == b.falloff && a.range == b.range && a.cosInnerAngle == b.cosInnerAngle &&
         a.cosOuterAngle == b.cosOuterAngle;
}

LampVisibility::LampVisibility(std::span<const SurfacePoint> points, std::span<const LightDesc> lamps,
                               const ReachTest& reaches)
    : lamps_(lamps.begin(), lamps.end()) {
  if (lamps.empty()) return;
  grid_ = SurfaceGrid(points, kCellsLongestAxis);
  if (grid_.empty()) return;
  groups_ = uint32_t((lamps.size() + 7) / 8);
  // The points of each bin together: (bin, point) sorted.
  std::vector<std::pair<int64_t, uint32_t>> byBin;
  byBin.reserve(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    const SurfacePoint& s = points[i];
    if (!finite(s.position) || !finite(s.normal)) continue;
    const int64_t bin = grid_.bin(s.position, s.normal);
    if (bin >= 0) byBin.emplace_back(bin, uint32_t(i));
  }
  std::sort(byBin.begin(), byBin.end());
  std::vector<size_t> starts;   // the first entry of each bin's run, and the end
  for (size_t i = 0; i < byBin.size(); ++i)
    if (i == 0 || byBin[i].first != byBin[i - 1].first) starts.push_back(i);
  starts.push_back(byBin.size());
  const size_t binsWithPoints = starts.size() - 1;
  // A level with thousands of lamps would take minutes to judge: it gets no map (every lamp seen).
  if (uint64_t(binsWithPoints) * lamps.size() > kMostPairs) return;

  // Per bin with points: its hidden bits (groups_ bytes) and the rays it traced.
  std::vector<uint8_t> hidden(binsWithPoints * groups_, 0);
  std::vector<uint32_t> rays(binsWithPoints, 0);
  const float offset = grid_.offset();
  tbb::parallel_for(size_t{0}, binsWithPoints, [&](size_t b) {
    const size_t first = starts[b], count = starts[b + 1] - first;
    // Up to kMostRays points of the bin, spread over its run (the points are in surface order).
    const size_t stride = std::max<size_t>(1, count / kMostRays);
    for (size_t k = 0; k < lamps.size(); ++k) {
      const LightDesc& l = lamps[k];
      if (l.type == LightType::Directional) continue;
      uint32_t traced = 0;
      bool reached = false;
      for (size_t j = 0; j < count && traced < kMostRays && !reached; j += stride) {
        const SurfacePoint& s = points[byBin[first + j].second];
        if (!canLight(l, s.position, s.normal)) continue;
        ++traced;
        // Toward the centre, or the near side of a sphere lamp (whose centre may sit in its fitting).
        glm::vec3 target = l.position;
        if (l.radius > 0.0f) {
          const glm::vec3 toPoint = s.position - l.position;
          const float distance = glm::length(toPoint);
          if (distance > 0.0f) target += toPoint * (std::min(l.radius, 0.5f * distance) / distance);
        }
        reached = reaches(s.position + offset * s.normal, target);
      }
      rays[b] += traced;
      if (!reached && traced >= kLeastRays) hidden[b * groups_ + k / 8] |= uint8_t(1u << (k % 8));
    }
  });

  rowOf_.assign(grid_.binCount(), UINT32_MAX);
  for (size_t b = 0; b < binsWithPoints; ++b) {
    rays_ += rays[b];
    const auto row = hidden.begin() + std::ptrdiff_t(b * groups_);
    if (std::all_of(row, row + groups_, [](uint8_t bits) { return bits == 0; })) continue;
    rowOf_[size_t(byBin[starts[b]].first)] = uint32_t(bits_.size() / groups_);
    bits_.insert(bits_.end(), row, row + groups_);
  }
  if (bits_.empty()) rowOf_.clear();   // nothing hidden anywhere: every lookup says so at once
}

int64_t LampVisibility::row(const glm::vec3& p, const glm::vec3& n) const {
  if (rowOf_.empty()) return -1;
  const int64_t bin = grid_.bin(p, n);
  if (bin < 0) return -1;
  const uint32_t r = rowOf_[size_t(bin)];
  return r == UINT32_MAX ? -1 : int64_t(r);
}

size_t LampVisibility::hiddenCount() const {
  size_t count = 0;
  for (const uint8_t bits : bits_) count += size_t(std::popcount(bits));
  return count;
}

std::shared_ptr<const LampVisibility> LampVisibilityCache::get(
    const Bounds& bounds, std::span<const LightDesc> lamps,
    const std::function<std::vector<SurfacePoint>()>& surfacePoints, const LampVisibility::ReachTest& reaches) {
  if (lamps.empty()) return nullptr;
  if (map_ != nullptr) {
    const float slack = 0.05f * glm::length(bounds_.max - bounds_.min);
    const bool nearBounds = glm::all(glm::lessThanEqual(glm::abs(bounds.min - bounds_.min), glm::vec3(slack))) &&
                            glm::all(glm::lessThanEqual(glm::abs(bounds.max - bounds_.max), glm::vec3(slack)));
    const std::span<const LightDesc> traced = map_->lamps();
    size_t same = 0;
    while (same < std::min(traced.size(), lamps.size()) && LampVisibility::sameLamp(lamps[same], traced[same])) ++same;
    if (nearBounds && same > 0 && 2 * same >= traced.size()) return map_;
  }
  const std::vector<SurfacePoint> points = surfacePoints();
  map_ = std::make_shared<const LampVisibility>(points, lamps, reaches);
  bounds_ = bounds;
  return map_;
}

}  // namespace pa
