#pragma once
// Rays and hits shared by the BVH, the scene and the integrator.
#include <cstdint>
#include <limits>

#include <glm/vec3.hpp>

namespace pa {

/// Sentinel for "no primitive / no instance".
inline constexpr uint32_t kInvalidId = 0xffffffffu;

/// A ray segment [tmin, tmax] along origin + t * dir. dir need not be normalised.
struct Ray {
  glm::vec3 origin{0.0f};
  float tmin = 0.0f;
  glm::vec3 dir{0.0f, 0.0f, 1.0f};
  float tmax = std::numeric_limits<float>::infinity();
};

/// Closest hit: distance, barycentrics (u on v1, v on v2), triangle and instance ids.
struct Hit {
  float t = std::numeric_limits<float>::infinity();
  float u = 0.0f;
  float v = 0.0f;
  uint32_t prim = kInvalidId;
  uint32_t instance = kInvalidId;
  bool valid() const { return prim != kInvalidId; }
};

/// Decides whether a candidate hit on an alpha-masked triangle counts (alpha test).
/// Called during traversal only for triangles flagged as masked; ctx is caller data.
struct HitFilter {
  bool (*accept)(const void* ctx, uint32_t instance, uint32_t prim, float u, float v) = nullptr;
  const void* ctx = nullptr;
  bool operator()(uint32_t instance, uint32_t prim, float u, float v) const {
    return accept == nullptr || accept(ctx, instance, prim, u, v);
  }
};

}  // namespace pa
