#pragma once
// Warps from the unit square to directions and points, orthonormal frames and MIS weights.
#include <algorithm>
#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace pa::sampling {

inline constexpr float kPi = std::numbers::pi_v<float>;
inline constexpr float kInvPi = 1.0f / kPi;

/// Orthonormal basis around a unit vector n (Duff et al. 2017, branchless).
struct Frame {
  glm::vec3 t, b, n;
  /// Builds the frame around unit vector n.
  explicit Frame(const glm::vec3& normal) : n(normal) {
    const float sign = std::copysign(1.0f, n.z);
    const float a = -1.0f / (sign + n.z);
    const float c = n.x * n.y * a;
    t = glm::vec3(1.0f + sign * n.x * n.x * a, sign * c, -sign * n.x);
    b = glm::vec3(c, sign + n.y * n.y * a, -n.y);
  }
  /// Local (x, y, z) to world.
  glm::vec3 toWorld(const glm::vec3& v) const { return v.x * t + v.y * b + v.z * n; }
  /// World to local.
  glm::vec3 toLocal(const glm::vec3& v) const { return {glm::dot(v, t), glm::dot(v, b), glm::dot(v, n)}; }
};

/// Concentric (Shirley-Chiu) map of the square to the unit disk.
inline glm::vec2 concentricDisk(const glm::vec2& u) {
  const glm::vec2 p = 2.0f * u - 1.0f;
  if (p.x == 0.0f && p.y == 0.0f) return {0.0f, 0.0f};
  float r, phi;
  if (std::abs(p.x) > std::abs(p.y)) {
    r = p.x;
    phi = (kPi / 4.0f) * (p.y / p.x);
  } else {
    r = p.y;
    phi = (kPi / 2.0f) - (kPi / 4.0f) * (p.x / p.y);
  }
  return {r * std::cos(phi), r * std::sin(phi)};
}

/// Cosine-weighted direction about +z; pdf = z / pi.
inline glm::vec3 cosineHemisphere(const glm::vec2& u) {
  const glm::vec2 d = concentricDisk(u);
  const float z = std::sqrt(std::max(0.0f, 1.0f - d.x * d.x - d.y * d.y));
  return {d.x, d.y, z};
}

/// Uniform direction on the unit sphere; pdf = 1 / (4 pi).
inline glm::vec3 uniformSphere(const glm::vec2& u) {
  const float z = 1.0f - 2.0f * u.x;
  const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
  const float phi = 2.0f * kPi * u.y;
  return {r * std::cos(phi), r * std::sin(phi), z};
}

/// Uniform direction in the cone of half-angle acos(cosMax) about +z; pdf = 1 / (2 pi (1 - cosMax)).
inline glm::vec3 uniformCone(const glm::vec2& u, float cosMax) {
  const float z = 1.0f - u.x * (1.0f - cosMax);
  const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
  const float phi = 2.0f * kPi * u.y;
  return {r * std::cos(phi), r * std::sin(phi), z};
}

/// Uniform barycentrics (b1, b2) on a triangle (b0 = 1 - b1 - b2).
inline glm::vec2 uniformTriangle(const glm::vec2& u) {
  const float su = std::sqrt(u.x);
  return {u.y * su, 1.0f - su};
}

/// Power heuristic (beta = 2) weight of strategy a against b.
inline float powerHeuristic(float pdfA, float pdfB) {
  const float a = pdfA * pdfA;
  const float b = pdfB * pdfB;
  if (!(a + b > 0.0f)) return 0.0f;
  if (std::isinf(a)) return 1.0f;
  return a / (a + b);
}

/// Rec. 709 luminance of linear RGB.
inline float luminance(const glm::vec3& c) { return 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b; }

}  // namespace pa::sampling
