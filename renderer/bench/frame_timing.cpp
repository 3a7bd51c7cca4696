// Frame timing through pa::Renderer: one 640x360 path-traced frame at 1 sample per pixel.
// glTF scenes are uploaded whole (materials, textures, lights); synthetic scenes get a grey
// diffuse material, a sky and a point light above the centre.
#include "renderer/bench/frame_timing.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "renderer/gltf_io/gltf_loader.h"
#include "renderer/gltf_io/gltf_upload.h"
#include "renderer/scene/renderer.h"

namespace pa::bench {
namespace {

constexpr uint32_t kWidth = 640, kHeight = 360;

void uploadScene(const BenchScene& scene, Renderer& renderer) {
  if (!scene.gltfPath.empty()) {
    gltf::uploadToRenderer(gltf::loadScene(scene.gltfPath), renderer);
    return;
  }
  MeshDesc mesh;
  mesh.positions = scene.mesh.positions;
  mesh.indices = scene.mesh.indices;
  InstanceDesc instance;
  instance.mesh = renderer.addMesh(mesh);
  renderer.addInstance(instance);
  const Bounds b = scene.mesh.bounds();
  LightDesc light;
  light.position = b.center() + glm::vec3(0.0f, 0.6f * (b.max.y - b.min.y), 0.0f);
  light.intensity = 10.0f * glm::dot(b.max - b.min, b.max - b.min);
  renderer.addLight(light);
  SkyDesc sky;
  sky.color = glm::vec3(0.3f, 0.4f, 0.5f);
  renderer.setSky(sky);
}

Camera toRendererCamera(const BenchCamera& c) {
  Camera cam;
  cam.origin = c.origin;
  cam.forward = glm::normalize(c.forward);
  const glm::vec3 right = glm::normalize(glm::cross(cam.forward, c.up));
  cam.left = -right;
  cam.up = glm::cross(right, cam.forward);
  const float fovY = c.yfov;
  const float fovX = fovAcross(fovY, float(kWidth) / float(kHeight));
  cam.fovY = glm::degrees(fovY);
  cam.fovX = glm::degrees(fovX);
  return cam;
}

double medianFrameMs(const BenchScene& scene, uint32_t threads, uint32_t reps) {
  Renderer renderer(RendererConfig{threads});
  uploadScene(scene, renderer);
  renderer.commit();
  RenderSettings settings;
  settings.width = kWidth;
  settings.height = kHeight;
  settings.samplesPerPixel = 1;
  settings.accumulate = false;
  const Camera camera = toRendererCamera(scene.camera);
  renderer.render(camera, settings);   // warm-up (first-touch allocations)
  std::vector<double> ms;
  for (uint32_t i = 0; i < reps; ++i) {
    settings.seed = i + 1;
    const auto start = std::chrono::steady_clock::now();
    renderer.render(camera, settings);
    ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
  }
  std::sort(ms.begin(), ms.end());
  return ms.size() % 2 ? ms[ms.size() / 2] : 0.5 * (ms[ms.size() / 2 - 1] + ms[ms.size() / 2]);
}

}  // namespace

FrameTimes measureFrames(const BenchScene& scene, uint32_t reps) {
  FrameTimes out;
  out.oneThreadMs = medianFrameMs(scene, 1, reps);
  out.twoThreadsMs = medianFrameMs(scene, 2, reps);
  out.note = "pa::Renderer, 640x360, 1 spp path tracing, wall-clock median";
  return out;
}

}  // namespace pa::bench
