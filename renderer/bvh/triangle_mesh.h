#pragma once
// The BLAS's own copy of its mesh, validated, plus per-triangle flags used by every layout.
#include <bit>
#include <cstdint>
#include <limits>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/common.hpp>
#include <glm/vec3.hpp>

#include "renderer/bvh/bvh.h"
#include "renderer/core/bounds.h"
#include "renderer/core/ray.h"

namespace pa::bvh_detail {

/// Validated triangle mesh. degenerate[i] != 0 marks zero-area triangles, which never hit.
struct TriangleMesh {
  std::vector<glm::vec3> positions;
  std::vector<uint32_t> indices;
  std::vector<HitRule> rules;        ///< Empty (all Opaque), or one rule per triangle.
  std::vector<uint8_t> degenerate;   ///< One flag per triangle.

  uint32_t triangleCount() const { return static_cast<uint32_t>(indices.size() / 3); }
  HitRule rule(uint32_t tri) const { return rules.empty() ? HitRule::Opaque : rules[tri]; }
  /// Hits on the triangle go through the HitFilter callback.
  bool isFiltered(uint32_t tri) const { return rule(tri) == HitRule::Filtered; }
  /// Rays that cull a face skip the triangle's hits on that face.
  bool isOneSided(uint32_t tri) const { return rule(tri) == HitRule::OneSided; }
  glm::vec3 vertex(uint32_t tri, int corner) const { return positions[indices[3 * tri + corner]]; }
};

/// Throws std::invalid_argument naming the field when input cannot be built (non-finite
/// positions, index count not a multiple of 3, out-of-range indices, rules size mismatch or unknown rule).
void validateBlasInput(const BlasInput& input);

/// Copies and validates input (validateBlasInput).
TriangleMesh makeTriangleMesh(const BlasInput& input);

/// Copies input, which must have passed validateBlasInput, into mesh, reusing its vectors.
void assignTriangleMesh(const BlasInput& input, TriangleMesh& mesh);

/// Replaces positions (same count) after validation and recomputes the degenerate flags.
void updatePositions(TriangleMesh& mesh, std::span<const glm::vec3> positions);

/// Bounds of every triangle.
std::vector<Bounds> triangleBounds(const TriangleMesh& mesh);
/// Same, into out (its memory reused).
void triangleBounds(const TriangleMesh& mesh, std::vector<Bounds>& out);

/// True when the ray can be traced: finite origin and direction, non-zero direction,
/// tmin <= tmax and neither NaN. Invalid rays report no hit. Inline, without branches: every
/// instance a ray enters checks it.
inline bool isTraceableRay(const Ray& ray) {
  constexpr float kLargest = std::numeric_limits<float>::max();
  const glm::vec3 o = glm::abs(ray.origin), d = glm::abs(ray.dir);   // NaN and infinity fail <= kLargest
  const bool finite = (o.x <= kLargest) & (o.y <= kLargest) & (o.z <= kLargest) & (d.x <= kLargest) &
                      (d.y <= kLargest) & (d.z <= kLargest);
  return finite & (d.x + d.y + d.z > 0.0f) & (ray.tmin <= ray.tmax);   // <= fails for a NaN
}

/// The bits of `active` a packet call traces (those below kMaxPacketRays). Throws
/// std::invalid_argument naming `caller` when the shortest of the call's spans (`shortestSpan`
/// rays, hits or filters) does not reach the highest of them.
inline uint32_t activePacketLanes(uint32_t active, size_t shortestSpan, const char* caller) {
  active &= (1u << kMaxPacketRays) - 1;
  const uint32_t highest = active ? 32 - std::countl_zero(active) : 0;
  if (shortestSpan < highest) throw std::invalid_argument(std::string(caller) + ": spans shorter than the active rays");
  return active;
}

}  // namespace pa::bvh_detail
