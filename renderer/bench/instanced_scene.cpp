#include "renderer/bench/instanced_scene.h"

#include <cmath>
#include <numbers>
#include <random>
#include <stdexcept>

#include <glm/geometric.hpp>

#include "renderer/bvh/testing/scene_generators.h"

namespace pa::bench {

void buildInstancedScene(const BenchScene& scene, const Blas& world, const testing::EmbreeScene& embreeWorld,
                         const testing::EmbreeDevice& device, uint32_t movers, uint32_t seed, InstancedScene& out) {
  // A player in a Quake III map: about 56 units tall in a map some 4000 units across.
  const Bounds bounds = scene.mesh.bounds();
  const float radius = 0.007f * glm::length(bounds.max - bounds.min);
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
  std::uniform_real_distribution<float> uniform(-1.0f, 1.0f);
  // Each mover stands in front of a surface that a ray from the camera's position reaches, in any
  // direction (a game frame's players and items are around the viewer, a few of them in view),
  // turned about the up axis.
  for (uint32_t attempt = 0; out.instances.size() < size_t{movers} + 1; ++attempt) {
    if (attempt > 100 * (movers + 1)) throw std::runtime_error("--instances: too few rays from the camera hit the scene");
    Ray ray;
    ray.origin = cam.origin;
    ray.dir = glm::vec3(uniform(rng), uniform(rng), uniform(rng));
    if (!(glm::dot(ray.dir, ray.dir) <= 1.0f && glm::dot(ray.dir, ray.dir) > 1e-4f)) continue;
    Hit hit;
    if (!world.intersect(ray, hit) || ray.tmax < 3.0f * radius) continue;
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
