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

/// Which face of one-sided triangles (BlasInput::rules, HitRule::OneSided) a ray skips. The
/// front face is the one whose vertices p0, p1, p2 the ray sees counter-clockwise:
/// dot(cross(p1 - p0, p2 - p0), dir) < 0 (in world space for Tlas queries).
enum class FaceCull : uint8_t {
  None,    ///< Both faces are hit (shadow rays; the default).
  Back,    ///< Hits on the back face are skipped (camera and bounce rays).
  Front,   ///< Hits on the front face are skipped (the Tlas's view of Back on a mirrored instance).
};

/// Per-ray hit rules: the callback that decides candidate hits on filtered triangles (alpha
/// test; called during traversal only for HitRule::Filtered triangles, with the candidate's
/// barycentrics u, v and its distance t along the ray, within [tmin, tmax]; ctx is caller data),
/// and the face of one-sided triangles the ray skips without a call.
struct HitFilter {
  bool (*accept)(const void* ctx, uint32_t instance, uint32_t prim, float u, float v, float t) = nullptr;
  const void* ctx = nullptr;
  FaceCull cull = FaceCull::None;   ///< Face of HitRule::OneSided triangles skipped by the kernels.
  bool operator()(uint32_t instance, uint32_t prim, float u, float v, float t) const {
    return accept == nullptr || accept(ctx, instance, prim, u, v, t);
  }
};

}  // namespace pa
