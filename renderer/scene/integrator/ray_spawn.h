#pragma once
// Self-intersection-free ray origins: moves a surface point off the surface along the
// geometric normal by a few ulps of its coordinates (integer ulp steps far from the origin,
// a small absolute step near it), after Waechter and Binder, Ray Tracing Gems ch. 6.
#include <bit>
#include <cmath>
#include <cstdint>

#include <glm/vec3.hpp>

namespace pa {

/// Offsets point p off its surface toward the side the unit normal n points to.
inline glm::vec3 offsetFromSurface(const glm::vec3& p, const glm::vec3& n) {
  constexpr float kOriginBand = 1.0f / 32.0f;
  constexpr float kFloatScale = 1.0f / 65536.0f;
  constexpr float kIntScale = 256.0f;
  glm::vec3 out;
  for (int i = 0; i < 3; ++i) {
    const auto ulps = static_cast<int32_t>(kIntScale * n[i]);
    const int32_t bits = std::bit_cast<int32_t>(p[i]);
    const float stepped = std::bit_cast<float>(bits + (p[i] < 0.0f ? -ulps : ulps));
    out[i] = std::abs(p[i]) < kOriginBand ? p[i] + kFloatScale * n[i] : stepped;
  }
  return out;
}

}  // namespace pa
