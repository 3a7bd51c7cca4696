// EmitterIndex: emitters prepared once, and a sphere tree to find the ones that can light a point.
#include "port/light_recovery/emitter_index.h"

#include <algorithm>
#include <cmath>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "port/q3formats/world/world_lights.h"

namespace pa::recovery {
namespace {

constexpr uint32_t kLeafSize = 4;
// value = power cos cos' / max(d^2, area) <= power / d^2: past power / threshold (with a margin
// for the cosines' rounding) an emitter gives less than the threshold.
constexpr float kReachMargin = 1.01f;

bool finite3(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

}  // namespace

EmitterIndex::EmitterIndex(const std::vector<CalibrationEmitter>& emitters, float minTracedValue)
    : minTracedValue_(minTracedValue) {
  emitters_.reserve(emitters.size());
  for (const CalibrationEmitter& e : emitters) {
    const glm::vec3 cross = glm::cross(e.b - e.a, e.c - e.a);
    const float twiceArea = glm::length(cross);
    const glm::vec3 centre = (e.a + e.b + e.c) / 3.0f;
    // The same expressions emitterLight evaluated per texel, so the sums keep every bit.
    if (!(twiceArea > 0.0f) || !std::isfinite(twiceArea) || !(e.radiance > 0.0f) || !finite3(centre)) continue;
    PreparedEmitter p;
    p.centre = centre;
    p.unitNormal = cross / twiceArea;
    p.area = 0.5f * twiceArea;
    p.power = q3::kQ3FullBright / 3.14159265f * e.radiance * p.area;
    p.twoSided = e.twoSided;
    p.group = e.group;
    emitters_.push_back(p);
  }
  if (emitters_.empty() || !(minTracedValue_ > 0.0f)) return;
  const size_t n = emitters_.size();
  reach2_.resize(n);
  std::vector<glm::vec3> lower(n), upper(n);
  for (size_t i = 0; i < n; ++i) {
    reach2_[i] = emitters_[i].power / minTracedValue_ * kReachMargin + 1.0f;
    const float reach = std::sqrt(reach2_[i]);
    lower[i] = emitters_[i].centre - glm::vec3(reach);
    upper[i] = emitters_[i].centre + glm::vec3(reach);
  }
  order_.resize(n);
  for (size_t i = 0; i < n; ++i) order_[i] = uint32_t(i);
  nodes_.reserve(2 * (n / kLeafSize + 1));
  nodes_.emplace_back();
  build(0, 0, uint32_t(n), lower, upper);
}

void EmitterIndex::build(uint32_t self, uint32_t begin, uint32_t end, const std::vector<glm::vec3>& lower,
                         const std::vector<glm::vec3>& upper) {
  glm::vec3 lo(INFINITY), hi(-INFINITY), centreLo(INFINITY), centreHi(-INFINITY);
  for (uint32_t i = begin; i < end; ++i) {
    lo = glm::min(lo, lower[order_[i]]);
    hi = glm::max(hi, upper[order_[i]]);
    centreLo = glm::min(centreLo, emitters_[order_[i]].centre);
    centreHi = glm::max(centreHi, emitters_[order_[i]].centre);
  }
  nodes_[self].lower = lo;
  nodes_[self].upper = hi;
  if (end - begin <= kLeafSize) {
    nodes_[self].first = begin;
    nodes_[self].count = end - begin;
    return;
  }
  const glm::vec3 extent = centreHi - centreLo;
  const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
  const uint32_t mid = begin + (end - begin) / 2;
  std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end, [&](uint32_t a, uint32_t b) {
    const float ca = emitters_[a].centre[axis], cb = emitters_[b].centre[axis];
    return ca < cb || (ca == cb && a < b);
  });
  const uint32_t left = uint32_t(nodes_.size());
  nodes_[self].first = left;
  nodes_[self].count = 0;
  nodes_.resize(nodes_.size() + 2);
  build(left, begin, mid, lower, upper);
  build(left + 1, mid, end, lower, upper);
}

void EmitterIndex::near(const glm::vec3& point, float threshold, std::vector<uint32_t>& out) const {
  out.clear();
  if (nodes_.empty() || threshold != minTracedValue_ || !(threshold > 0.0f)) {
    for (uint32_t i = 0; i < emitters_.size(); ++i) out.push_back(i);
    return;
  }
  // Median splits keep the depth at log2(n / kLeafSize) < 32: the stack never holds 64.
  uint32_t stack[64];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& node = nodes_[stack[--top]];
    if (!(point.x >= node.lower.x && point.y >= node.lower.y && point.z >= node.lower.z && point.x <= node.upper.x &&
          point.y <= node.upper.y && point.z <= node.upper.z))
      continue;
    if (node.count > 0) {
      for (uint32_t i = node.first; i < node.first + node.count; ++i) {
        const glm::vec3 d = emitters_[order_[i]].centre - point;
        if (glm::dot(d, d) <= reach2_[order_[i]]) out.push_back(order_[i]);
      }
    } else {
      stack[top++] = node.first;
      stack[top++] = node.first + 1;
    }
  }
  std::sort(out.begin(), out.end());
}

}  // namespace pa::recovery
