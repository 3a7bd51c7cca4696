#pragma once
// Conservative ray/box slab test. The far distance is scaled by 1 + 2 * gamma(3)
// (Ize, "Robust BVH Ray Traversal", JCGT 2013) so rounding in (bound - origin) * invDir
// never makes a box the ray touches look missed. NaNs (0 * inf at a slab plane) are ordered
// so they never restrict the interval.
#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/vec3.hpp>

#include "renderer/core/bounds.h"

namespace pa::bvh_detail {

/// gamma(n) = n * eps / (1 - n * eps) with eps = 2^-24 (PBRT's bound on n rounded operations).
constexpr float gammaBound(int n) {
  constexpr float eps = std::numeric_limits<float>::epsilon() * 0.5f;
  return (float(n) * eps) / (1.0f - float(n) * eps);
}
/// Scale applied to far slab distances.
inline constexpr float kRobustFarScale = 1.0f + 2.0f * gammaBound(3);

/// Per-ray slab constants.
struct SlabRay {
  glm::vec3 origin;
  glm::vec3 invDir;
  int nearX, nearY, nearZ;   ///< 0 = take min bound as near plane, 1 = max bound

  SlabRay() = default;
  explicit SlabRay(const glm::vec3& o, const glm::vec3& d)
      : origin(o), invDir(1.0f / d.x, 1.0f / d.y, 1.0f / d.z),
        nearX(std::signbit(d.x)), nearY(std::signbit(d.y)), nearZ(std::signbit(d.z)) {}
};

/// NaN-tolerant max/min: when a is NaN the result is b.
inline float maxKeep(float a, float b) { return a > b ? a : b; }
inline float minKeep(float a, float b) { return a < b ? a : b; }

/// Entry distance when the box overlaps [tmin, tmax] along the ray, else +inf.
inline float slabEntry(const SlabRay& r, const Bounds& b, float tmin, float tmax) {
  const glm::vec3* lohi[2] = {&b.min, &b.max};
  const float nx = ((*lohi[r.nearX]).x - r.origin.x) * r.invDir.x;
  const float ny = ((*lohi[r.nearY]).y - r.origin.y) * r.invDir.y;
  const float nz = ((*lohi[r.nearZ]).z - r.origin.z) * r.invDir.z;
  const float fx = ((*lohi[1 - r.nearX]).x - r.origin.x) * r.invDir.x;
  const float fy = ((*lohi[1 - r.nearY]).y - r.origin.y) * r.invDir.y;
  const float fz = ((*lohi[1 - r.nearZ]).z - r.origin.z) * r.invDir.z;
  const float tNear = maxKeep(nx, maxKeep(ny, maxKeep(nz, tmin)));
  const float tFar = minKeep(fx, minKeep(fy, minKeep(fz, tmax))) * kRobustFarScale;
  return tNear <= tFar ? tNear : std::numeric_limits<float>::infinity();
}

}  // namespace pa::bvh_detail
