// Frame timing through pa::Renderer: one 640x360 path-traced frame at 1 sample per pixel.
// glTF scenes are uploaded whole (materials, textures, lights); synthetic scenes get a grey
// diffuse material, a sky and a point light above the centre.
#include "renderer/bench/frame_timing.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <string>
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
  InstanceDesc instance;
  instance.mesh = renderer.addMesh(meshDescOf(scene.mesh));
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

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

double processCpuMs() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return 1e3 * double(ts.tv_sec) + 1e-6 * double(ts.tv_nsec);
}

/// A renderer with the scene uploaded, ready to time frames.
struct TimedRenderer {
  Renderer renderer;
  RenderSettings settings;
  Camera camera;

  TimedRenderer(const BenchScene& scene, uint32_t threads) : renderer(RendererConfig{threads}) {
    uploadScene(scene, renderer);
    renderer.commit();
    settings.width = kWidth;
    settings.height = kHeight;
    settings.samplesPerPixel = 1;
    settings.accumulate = false;
    camera = toRendererCamera(scene.camera);
    renderer.render(camera, settings);   // warm-up (first-touch allocations)
  }

  /// Renders one frame; returns wall-clock ms and adds the process CPU ms to cpuMs.
  double frame(uint32_t seed, std::vector<double>& cpuMs) {
    settings.seed = seed;
    const double cpuStart = processCpuMs();
    const auto start = std::chrono::steady_clock::now();
    renderer.render(camera, settings);
    const double wall = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    cpuMs.push_back(processCpuMs() - cpuStart);
    return wall;
  }
};

}  // namespace

FrameTimes measureFrames(const BenchScene& scene, uint32_t reps) {
  TimedRenderer one(scene, 1), two(scene, 2);
  FrameTimes out;
  std::vector<double> cpuOne, cpuTwo, speedups;
  for (uint32_t i = 0; i < reps; ++i) {
    out.oneThreadSamplesMs.push_back(one.frame(i + 1, cpuOne));
    out.twoThreadsSamplesMs.push_back(two.frame(i + 1, cpuTwo));
    speedups.push_back(out.oneThreadSamplesMs.back() / out.twoThreadsSamplesMs.back());
  }
  out.oneThreadMs = median(out.oneThreadSamplesMs);
  out.twoThreadsMs = median(out.twoThreadsSamplesMs);
  out.oneThreadCpuMs = median(cpuOne);
  out.twoThreadsCpuMs = median(cpuTwo);
  out.speedup = median(speedups);
  out.note = "pa::Renderer, 640x360, 1 spp path tracing, 1 and 2 threads alternating, medians of " +
             std::to_string(reps);
  return out;
}

}  // namespace pa::bench
