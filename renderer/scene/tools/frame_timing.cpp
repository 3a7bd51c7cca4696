// pa-scene-timing: wall-clock time of Path frames on a small procedural scene with 1 and with
// N threads, to measure tile-parallel scaling. Not a test (timings never are).
//   pa-scene-timing [width height spp frames threads]   (defaults: 640 360 1 8 2)
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include <cmath>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "renderer/scene/renderer.h"

namespace {

using namespace pa;

struct Mesh {
  std::vector<glm::vec3> positions;
  std::vector<uint32_t> indices;
  std::vector<MaterialId> materials;
};

Mesh box(const glm::vec3& lo, const glm::vec3& hi, MaterialId material) {
  Mesh m;
  for (int i = 0; i < 8; ++i) m.positions.push_back({(i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z});
  m.indices = {0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4, 2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3, 7, 5};
  m.materials.assign(12, material);
  return m;
}

/// A room (inside-out box), a few boxes, an emissive ceiling panel, a point light and a sky window.
std::vector<Mesh> buildScene(Renderer& r) {
  MaterialDesc wall;
  wall.baseColor = {0.7f, 0.65f, 0.6f, 1.0f};
  MaterialDesc glossy = wall;
  glossy.specular = 0.4f;
  glossy.roughness = 0.3f;
  MaterialDesc lamp;
  lamp.emission = glm::vec3(8.0f);
  const MaterialId w = r.addMaterial(wall), g = r.addMaterial(glossy), l = r.addMaterial(lamp);
  std::vector<Mesh> meshes;
  Mesh room = box({-6, -6, 0}, {6, 6, 5}, w);
  for (size_t i = 0; i < room.indices.size(); i += 3) std::swap(room.indices[i + 1], room.indices[i + 2]);
  meshes.push_back(room);
  for (int i = 0; i < 12; ++i) {
    const float x = -4.5f + 1.5f * static_cast<float>(i % 6), y = i < 6 ? -2.0f : 2.0f;
    meshes.push_back(box({x, y, 0}, {x + 0.8f, y + 0.8f, 0.5f + 0.3f * static_cast<float>(i % 4)}, i % 2 ? g : w));
  }
  meshes.push_back(box({-1, -1, 4.9f}, {1, 1, 4.95f}, l));
  for (const Mesh& m : meshes) {
    MeshDesc d;
    d.positions = m.positions;
    d.indices = m.indices;
    d.materials = m.materials;
    r.addInstance({r.addMesh(d)});
  }
  LightDesc point;
  point.position = {3, 3, 3};
  point.intensity = 20.0f;
  r.addLight(point);
  SkyDesc sky;
  sky.color = glm::vec3(0.3f, 0.4f, 0.6f);
  r.setSky(sky);
  r.commit();
  return meshes;
}

Camera makeCamera(const RenderSettings& settings) {
  Camera cam;
  cam.origin = {-5.5f, -5.5f, 2.5f};
  cam.forward = glm::normalize(glm::vec3(1, 1, -0.25f));
  cam.left = glm::normalize(glm::cross(glm::vec3(0, 0, 1), cam.forward));
  cam.up = glm::cross(cam.forward, cam.left);
  cam.fovX = 90.0f;
  cam.fovY = 2.0f * glm::degrees(std::atan(std::tan(glm::radians(45.0f)) * settings.height / settings.width));
  return cam;
}

double timeFrame(Renderer& r, const Camera& cam, const RenderSettings& settings) {
  const auto t0 = std::chrono::steady_clock::now();
  r.render(cam, settings);
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

int main(int argc, char** argv) {
  RenderSettings s;
  s.width = argc > 1 ? static_cast<uint32_t>(std::atoi(argv[1])) : 640;
  s.height = argc > 2 ? static_cast<uint32_t>(std::atoi(argv[2])) : 360;
  s.samplesPerPixel = argc > 3 ? static_cast<uint32_t>(std::atoi(argv[3])) : 1;
  const uint32_t frames = argc > 4 ? static_cast<uint32_t>(std::atoi(argv[4])) : 8;
  const uint32_t threads = argc > 5 ? static_cast<uint32_t>(std::atoi(argv[5])) : 2;
  s.integrator = Integrator::Path;
  s.maxBounces = 4;
  s.accumulate = true;
  // Frames of the two renderers alternate so both see the same background load; the best
  // frame of each is reported (the least disturbed one).
  Renderer single({1}), parallel({threads});
  const auto meshesA = buildScene(single);
  const auto meshesB = buildScene(parallel);
  const Camera cam = makeCamera(s);
  single.render(cam, s);   // warm-up (first-touch of the film)
  parallel.render(cam, s);
  double one = 1e30, many = 1e30;
  for (uint32_t i = 0; i < frames; ++i) {
    one = std::min(one, timeFrame(single, cam, s));
    many = std::min(many, timeFrame(parallel, cam, s));
  }
  std::printf("%ux%u %u spp Path, best of %u frames: 1 thread %.1f ms, %u threads %.1f ms, speed-up %.2f\n", s.width,
              s.height, s.samplesPerPixel, frames, one * 1e3, threads, many * 1e3, one / many);
  return 0;
}
