#pragma once
// Axis-aligned bounding boxes.
#include <algorithm>
#include <limits>

#include <glm/common.hpp>
#include <glm/vec3.hpp>

namespace pa {

/// Axis-aligned box; the default is empty (min = +inf, max = -inf).
struct Bounds {
  glm::vec3 min{std::numeric_limits<float>::infinity()};
  glm::vec3 max{-std::numeric_limits<float>::infinity()};

  /// Grows the box to contain p.
  void extend(const glm::vec3& p) { min = glm::min(min, p); max = glm::max(max, p); }
  /// Grows the box to contain b.
  void extend(const Bounds& b) { min = glm::min(min, b.min); max = glm::max(max, b.max); }
  /// True when no point was added.
  bool empty() const { return min.x > max.x || min.y > max.y || min.z > max.z; }
  /// Centre of the box.
  glm::vec3 center() const { return 0.5f * (min + max); }
  /// Half the surface area (what SAH costs compare); 0 for an empty box.
  float halfArea() const {
    if (empty()) return 0.0f;
    const glm::vec3 d = max - min;
    return d.x * d.y + d.y * d.z + d.z * d.x;
  }
};

}  // namespace pa
