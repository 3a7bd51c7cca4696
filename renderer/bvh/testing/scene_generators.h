#pragma once
// Deterministic synthetic scenes and ray sets for BVH tests and the bench.
#include <cstdint>
#include <random>
#include <vector>

#include <glm/mat4x3.hpp>
#include <glm/vec3.hpp>

#include "renderer/bvh/bvh.h"
#include "renderer/core/bounds.h"
#include "renderer/core/ray.h"

namespace pa::testing {

/// Owned triangle mesh.
struct TestMesh {
  std::vector<glm::vec3> positions;
  std::vector<uint32_t> indices;
  std::vector<HitRule> rules;   ///< Empty (all Opaque), or one rule per triangle.

  /// View for Blas::build.
  BlasInput input() const { return {positions, indices, rules}; }
  /// Number of triangles.
  uint32_t triangleCount() const { return static_cast<uint32_t>(indices.size() / 3); }
  /// Bounds of all vertices.
  Bounds bounds() const;
  /// Moves every vertex by offset.
  void translate(const glm::vec3& offset);
  /// Appends another mesh.
  void append(const TestMesh& other);
};

/// count independent random triangles (edge length ~ size) in the cube [-1, 1]^3.
TestMesh makeTriangleSoup(uint32_t count, uint32_t seed, float size = 0.05f);

/// count long thin triangles (length ~1, width ~1e-3) in axis-aligned and slanted orientations,
/// sharing edges in strips as game-map brush faces do after T-junction fixing.
TestMesh makeThinTriangles(uint32_t count, uint32_t seed);

/// Closed UV sphere (shared vertices, single-vertex poles) with about `triangles` triangles.
TestMesh makeSphere(uint32_t triangles, const glm::vec3& center = glm::vec3(0.0f), float radius = 1.0f);

/// Random rays: origins uniform in `region`, directions uniform on the sphere, [0, inf).
std::vector<Ray> makeRandomRays(const Bounds& region, uint32_t count, uint32_t seed);

/// Random rays from `origin` in uniform directions (e.g. from inside a closed mesh).
std::vector<Ray> makeRaysFromPoint(const glm::vec3& origin, uint32_t count, uint32_t seed);

/// A random rigid-plus-scale 3x4 transform (rotation, uniform scale in [0.5, 2], translation
/// within +-spread).
glm::mat4x3 makeRandomTransform(std::mt19937& rng, float spread);

}  // namespace pa::testing
