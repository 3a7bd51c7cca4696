#pragma once
// Self-intersection avoidance for secondary rays: move a hit point off its surface along the
// geometric normal by a few float ulps (integer offset) far from the origin, and by a small
// absolute amount near it. After Waechter and Binder, "A Fast and Robust Method for Avoiding
// Self-Intersection", Ray Tracing Gems (2019), chapter 6.
#include <bit>
#include <cmath>
#include <cstdint>

#include <glm/vec3.hpp>

namespace pa {

namespace ray_offset_detail {
inline constexpr float kOrigin = 1.0f / 32.0f;       ///< Below this |coordinate|, offset in float units.
inline constexpr float kFloatScale = 1.0f / 65536.0f;  ///< Absolute offset scale near the origin.
inline constexpr float kIntScale = 256.0f;             ///< Ulp offset scale far from the origin.

inline float offsetComponent(float p, float n) {
  const int32_t ulps = static_cast<int32_t>(kIntScale * n);
  const int32_t bits = std::bit_cast<int32_t>(p);
  // Moving away from zero adds ulps to the magnitude; the sign of p decides the direction.
  const float moved = std::bit_cast<float>(bits + ((p < 0.0f) ? -ulps : ulps));
  return std::fabs(p) < kOrigin ? p + kFloatScale * n : moved;
}
}  // namespace ray_offset_detail

/// Returns p moved off the surface along geometricNormal (need not be normalised but should
/// have unit-ish length; it points to the side the new ray leaves towards). Use the negated
/// normal for rays that go through the surface (transmission).
inline glm::vec3 offsetRayOrigin(const glm::vec3& p, const glm::vec3& geometricNormal) {
  using ray_offset_detail::offsetComponent;
  return {offsetComponent(p.x, geometricNormal.x), offsetComponent(p.y, geometricNormal.y),
          offsetComponent(p.z, geometricNormal.z)};
}

}  // namespace pa
