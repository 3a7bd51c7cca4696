#include "renderer/bench/ray_sets.h"

#include <cmath>
#include <numbers>
#include <random>
#include <stdexcept>

#include <glm/geometric.hpp>

#include "renderer/bvh/ray_offset.h"

namespace pa::bench {
namespace {

struct SurfacePoint {
  glm::vec3 position;
  glm::vec3 normal;   ///< Geometric, facing the incoming ray.
};

/// Orthonormal basis around n (Duff et al. 2017).
void basis(const glm::vec3& n, glm::vec3& t, glm::vec3& b) {
  const float sign = std::copysign(1.0f, n.z);
  const float a = -1.0f / (sign + n.z);
  const float c = n.x * n.y * a;
  t = {1.0f + sign * n.x * n.x * a, sign * c, -sign * n.x};
  b = {c, sign + n.y * n.y * a, -n.y};
}

}  // namespace

RaySets makeRaySets(const BenchScene& scene, const Blas& blas, uint32_t width, uint32_t height,
                    uint32_t secondaryCount, uint32_t seed) {
  if (width % 4 != 0 || height % 4 != 0) throw std::invalid_argument("primary image size must be a multiple of 4");
  RaySets sets;
  const BenchCamera& cam = scene.camera;
  const glm::vec3 right = glm::normalize(glm::cross(cam.forward, cam.up));
  const glm::vec3 up = glm::cross(right, cam.forward);
  const float tanY = std::tan(0.5f * cam.yfov);
  const float tanX = tanY * float(width) / float(height);
  sets.primary.reserve(size_t(width) * height);
  for (uint32_t ty = 0; ty < height; ty += 4)
    for (uint32_t tx = 0; tx < width; tx += 4)
      for (uint32_t y = ty; y < ty + 4; ++y)
        for (uint32_t x = tx; x < tx + 4; ++x) {
          const float sx = (2.0f * (float(x) + 0.5f) / float(width) - 1.0f) * tanX;
          const float sy = (1.0f - 2.0f * (float(y) + 0.5f) / float(height)) * tanY;
          Ray r;
          r.origin = cam.origin;
          r.dir = glm::normalize(cam.forward + sx * right + sy * up);
          sets.primary.push_back(r);
        }

  // The lamp: beside and above the camera, off its rays' origin (most of what it sees is lit).
  const glm::vec3 lamp = cam.origin + 0.02f * glm::length(scene.mesh.bounds().max - scene.mesh.bounds().min) *
                                          (right + 0.5f * up);
  std::vector<SurfacePoint> points;
  for (Ray r : sets.primary) {
    Hit hit;
    if (!blas.intersect(r, hit)) continue;
    const auto& m = scene.mesh;
    const glm::vec3 a = m.positions[m.indices[3 * hit.prim]], b = m.positions[m.indices[3 * hit.prim + 1]],
                    c = m.positions[m.indices[3 * hit.prim + 2]];
    glm::vec3 n = glm::cross(b - a, c - a);
    const float len = glm::length(n);
    if (!(len > 0.0f)) continue;
    n /= len;
    if (glm::dot(n, r.dir) > 0.0f) n = -n;
    const glm::vec3 p = (1.0f - hit.u - hit.v) * a + hit.u * b + hit.v * c;
    points.push_back({offsetRayOrigin(p, n), n});
    // From the lamp to the point (the rays of a tile share their origin), short of its ends.
    Ray fromLamp;
    fromLamp.origin = lamp;
    fromLamp.dir = points.back().position - lamp;
    fromLamp.tmin = 0.001f;
    fromLamp.tmax = 0.999f;
    sets.lampShadow.push_back(fromLamp);
  }
  sets.surfacePoints = static_cast<uint32_t>(points.size());
  if (points.empty()) throw std::runtime_error("no primary ray hits the scene: cannot make secondary rays");

  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
  std::uniform_int_distribution<size_t> pick(0, points.size() - 1);
  // Light region: the top tenth of the scene bounds.
  Bounds light = scene.mesh.bounds();
  const glm::vec3 extent = light.max - light.min;
  light.min.y = light.max.y - 0.1f * extent.y;
  sets.incoherent.reserve(secondaryCount);
  sets.shadow.reserve(secondaryCount);
  for (uint32_t i = 0; i < secondaryCount; ++i) {
    const SurfacePoint& sp = points[pick(rng)];
    glm::vec3 t, b;
    basis(sp.normal, t, b);
    const float r = std::sqrt(uniform(rng)), phi = 2.0f * std::numbers::pi_v<float> * uniform(rng);
    const float z = std::sqrt(std::max(0.0f, 1.0f - r * r));
    Ray bounce;
    bounce.origin = sp.position;
    bounce.dir = r * std::cos(phi) * t + r * std::sin(phi) * b + z * sp.normal;
    sets.incoherent.push_back(bounce);

    const SurfacePoint& sp2 = points[pick(rng)];
    const glm::vec3 target = light.min + glm::vec3(uniform(rng), uniform(rng), uniform(rng)) * (light.max - light.min);
    Ray shadow;
    shadow.origin = sp2.position;
    shadow.dir = target - sp2.position;
    shadow.tmax = 0.999f;
    sets.shadow.push_back(shadow);
  }
  return sets;
}

}  // namespace pa::bench
