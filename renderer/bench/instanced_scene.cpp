#include "renderer/bench/instanced_scene.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <stdexcept>

#include <glm/geometric.hpp>

#include "renderer/bvh/testing/scene_generators.h"

namespace pa::bench {

void buildInstancedScene(const BenchScene& scene, const Blas& world, const testing::EmbreeScene& embreeWorld,
                         const testing::EmbreeDevice& device, uint32_t movers, uint32_t seed, InstancedScene& out) {
  const Bounds bounds = scene.mesh.bounds();
  const testing::TestMesh sphere = testing::makeSphere(400);
  out.mover.build(sphere.input());
  out.embreeMover = std::make_unique<testing::EmbreeScene>(device);
  out.embreeMover->addMesh(sphere);
  out.embreeMover->commit();

  out.instances.clear();
  out.instances.push_back({&world, glm::mat4x3(1.0f), 0xffffffffu});
  const BenchCamera& cam = scene.camera;
  const glm::vec3 right = glm::normalize(glm::cross(cam.forward, cam.up));
  const glm::vec3 up = glm::cross(right, cam.forward);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> uniform(-1.0f, 1.0f), unit(0.0f, 1.0f);
  // A ray from the camera's position towards a random point of the scene's bounds, traced.
  const auto placementRay = [&](Ray& ray) {
    const glm::vec3 target = bounds.min + glm::vec3(unit(rng), unit(rng), unit(rng)) * (bounds.max - bounds.min);
    ray = Ray{};
    ray.origin = cam.origin;
    ray.dir = target - cam.origin;
    if (!(glm::dot(ray.dir, ray.dir) > 0.0f)) return false;
    ray.dir = glm::normalize(ray.dir);
    Hit hit;
    return world.intersect(ray, hit);
  };
  // A mover's size: a twentieth of the median distance such rays travel (a player seen across a
  // room), whatever the scene's units.
  std::vector<float> distances;
  for (int i = 0; i < 257; ++i) {
    Ray ray;
    if (placementRay(ray)) distances.push_back(ray.tmax);
  }
  if (distances.size() < 16) throw std::runtime_error("--instances: too few rays from the camera hit the scene");
  std::nth_element(distances.begin(), distances.begin() + distances.size() / 2, distances.end());
  const float radius = 0.05f * distances[distances.size() / 2];
  // Each mover stands in front of a surface such a ray reaches (a game frame's players and items
  // are around the viewer, a few of them in view), turned about the up axis.
  for (uint32_t attempt = 0; out.instances.size() < size_t{movers} + 1; ++attempt) {
    if (attempt > 100 * (movers + 1)) throw std::runtime_error("--instances: too few rays from the camera hit the scene");
    Ray ray;
    if (!placementRay(ray) || ray.tmax < 3.0f * radius) continue;
    const glm::vec3 centre = ray.origin + (ray.tmax - 1.5f * radius) * ray.dir;
    const float angle = std::numbers::pi_v<float> * uniform(rng);
    glm::mat4x3 m(0.0f);
    m[0] = radius * (std::cos(angle) * right + std::sin(angle) * cam.forward);
    m[1] = radius * up;
    m[2] = glm::cross(m[0], m[1]) / radius;
    m[3] = centre;
    out.instances.push_back({&out.mover, m, 0xffffffffu});
  }
  out.tlas.build(out.instances);
  out.embreeTop = std::make_unique<testing::EmbreeScene>(device);
  out.embreeTop->addInstance(embreeWorld, out.instances[0].objectToWorld);
  for (size_t i = 1; i < out.instances.size(); ++i) out.embreeTop->addInstance(*out.embreeMover, out.instances[i].objectToWorld);
  out.embreeTop->commit();
}

}  // namespace pa::bench
