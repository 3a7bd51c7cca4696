#include "renderer/bvh/testing/scene_generators.h"

#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

namespace pa::testing {
namespace {

glm::vec3 uniformInBox(std::mt19937& rng, const Bounds& b) {
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  return b.min + glm::vec3(u(rng), u(rng), u(rng)) * (b.max - b.min);
}

glm::vec3 uniformDirection(std::mt19937& rng) {
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  const float z = 1.0f - 2.0f * u(rng);
  const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
  const float phi = 2.0f * std::numbers::pi_v<float> * u(rng);
  return {r * std::cos(phi), r * std::sin(phi), z};
}

}  // namespace

Bounds TestMesh::bounds() const {
  Bounds b;
  for (const glm::vec3& p : positions) b.extend(p);
  return b;
}

void TestMesh::translate(const glm::vec3& offset) {
  for (glm::vec3& p : positions) p += offset;
}

void TestMesh::append(const TestMesh& other) {
  const auto base = static_cast<uint32_t>(positions.size());
  positions.insert(positions.end(), other.positions.begin(), other.positions.end());
  for (uint32_t i : other.indices) indices.push_back(base + i);
  if (!rules.empty() || !other.rules.empty()) {
    rules.resize(triangleCount() - other.triangleCount(), HitRule::Opaque);
    if (other.rules.empty()) rules.resize(triangleCount(), HitRule::Opaque);
    else rules.insert(rules.end(), other.rules.begin(), other.rules.end());
  }
}

TestMesh makeTriangleSoup(uint32_t count, uint32_t seed, float size) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> jitter(-size, size);
  const Bounds cube{glm::vec3(-1.0f), glm::vec3(1.0f)};
  TestMesh mesh;
  for (uint32_t t = 0; t < count; ++t) {
    const glm::vec3 c = uniformInBox(rng, cube);
    for (int k = 0; k < 3; ++k) {
      mesh.positions.push_back(c + glm::vec3(jitter(rng), jitter(rng), jitter(rng)));
      mesh.indices.push_back(3 * t + k);
    }
  }
  return mesh;
}

TestMesh makeThinTriangles(uint32_t count, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::uniform_int_distribution<int> axisPick(0, 3);
  TestMesh mesh;
  // Strips of 2 * segments triangles: a long thin quad cut into segments, all edges shared.
  constexpr uint32_t segments = 4;
  while (mesh.triangleCount() < count) {
    const glm::vec3 start(u(rng), u(rng), u(rng));
    const int axis = axisPick(rng);
    glm::vec3 along = axis < 3 ? glm::vec3(axis == 0, axis == 1, axis == 2) : glm::normalize(glm::vec3(u(rng), u(rng), u(rng)) + 1e-3f);
    glm::vec3 side = glm::normalize(glm::cross(along, glm::vec3(0.3f, 0.5f, 0.8f)));
    if (axis < 3) side = glm::vec3(axis == 1, axis == 2, axis == 0);   // axis aligned, as in brushes
    const float length = 0.5f + 0.5f * std::fabs(u(rng));
    const float width = 1e-3f * (1.0f + std::fabs(u(rng)));
    const auto base = static_cast<uint32_t>(mesh.positions.size());
    for (uint32_t s = 0; s <= segments; ++s) {
      const glm::vec3 p = start + along * (length * float(s) / segments);
      mesh.positions.push_back(p);
      mesh.positions.push_back(p + side * width);
    }
    for (uint32_t s = 0; s < segments && mesh.triangleCount() < count; ++s) {
      const uint32_t a = base + 2 * s, b = a + 1, c = a + 2, d = a + 3;
      mesh.indices.insert(mesh.indices.end(), {a, c, b});
      if (mesh.triangleCount() < count) mesh.indices.insert(mesh.indices.end(), {b, c, d});
    }
  }
  return mesh;
}

TestMesh makeSphere(uint32_t triangles, const glm::vec3& center, float radius) {
  // rings x segments grid: 2 * segments * (rings - 1) triangles; segments = 2 * rings.
  const auto rings = std::max<uint32_t>(3, static_cast<uint32_t>(std::sqrt(triangles / 4.0)));
  const uint32_t segments = 2 * rings;
  TestMesh mesh;
  mesh.positions.push_back(center + glm::vec3(0, 0, radius));   // north pole
  for (uint32_t r = 1; r < rings; ++r) {
    const float theta = std::numbers::pi_v<float> * float(r) / float(rings);
    for (uint32_t s = 0; s < segments; ++s) {
      const float phi = 2.0f * std::numbers::pi_v<float> * float(s) / float(segments);
      mesh.positions.push_back(center + radius * glm::vec3(std::sin(theta) * std::cos(phi),
                                                           std::sin(theta) * std::sin(phi), std::cos(theta)));
    }
  }
  const auto south = static_cast<uint32_t>(mesh.positions.size());
  mesh.positions.push_back(center + glm::vec3(0, 0, -radius));
  auto ring = [&](uint32_t r, uint32_t s) { return 1 + (r - 1) * segments + (s % segments); };
  for (uint32_t s = 0; s < segments; ++s) mesh.indices.insert(mesh.indices.end(), {0u, ring(1, s), ring(1, s + 1)});
  for (uint32_t r = 1; r + 1 < rings; ++r)
    for (uint32_t s = 0; s < segments; ++s) {
      const uint32_t a = ring(r, s), b = ring(r, s + 1), c = ring(r + 1, s), d = ring(r + 1, s + 1);
      mesh.indices.insert(mesh.indices.end(), {a, c, b, b, c, d});
    }
  for (uint32_t s = 0; s < segments; ++s)
    mesh.indices.insert(mesh.indices.end(), {south, ring(rings - 1, s + 1), ring(rings - 1, s)});
  return mesh;
}

std::vector<Ray> makeRandomRays(const Bounds& region, uint32_t count, uint32_t seed) {
  std::mt19937 rng(seed);
  std::vector<Ray> rays(count);
  for (Ray& r : rays) {
    r.origin = uniformInBox(rng, region);
    r.dir = uniformDirection(rng);
  }
  return rays;
}

std::vector<Ray> makeRaysFromPoint(const glm::vec3& origin, uint32_t count, uint32_t seed) {
  std::mt19937 rng(seed);
  std::vector<Ray> rays(count);
  for (Ray& r : rays) {
    r.origin = origin;
    r.dir = uniformDirection(rng);
  }
  return rays;
}

glm::mat4x3 makeRandomTransform(std::mt19937& rng, float spread) {
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  const float angle = std::numbers::pi_v<float> * u(rng);
  const float scale = std::exp2(u(rng));
  glm::mat4 m = glm::translate(glm::mat4(1.0f), spread * glm::vec3(u(rng), u(rng), u(rng)));
  m = glm::rotate(m, angle, glm::normalize(uniformDirection(rng)));
  m = glm::scale(m, glm::vec3(scale));
  return glm::mat4x3(m);
}

}  // namespace pa::testing
