// pa-taau-timing: wall-clock time of one TAAU resolve (renderer/scene/taau) from a traced frame to
// the output size, with 1 and with N threads: the median over many frames of a synthetic frame
// (textured gradient, a moving camera's motion, a sky band), and the CPU time of the 1-thread
// resolve (on a shared machine the wall time is noisy). Not a test (timings never are).
//   pa-taau-timing [outWidth outHeight scale frames threads motion]   (defaults: 640 360 0.5 200 2 pan)
// motion: pan (the same motion at every pixel: each step's history taps are consecutive pixels)
// or zoom (a zoom and a roll about the centre: motion that changes along each row, so that a
// step's taps skip or repeat a column or span two rows, as in play).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <string>
#include <vector>

#include <time.h>

#include <tbb/task_arena.h>

#include "renderer/scene/taau/taau.h"

namespace {

/// CPU time of the calling thread, ms (a 1-thread arena runs its work on the calling thread).
double threadCpuMs() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return 1e3 * static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_nsec);
}

/// Median wall-clock ms of a resolve with `threads` threads; cpuMs: median CPU ms of the calling thread.
double medianMs(uint32_t threads, uint32_t W, uint32_t H, float scale, uint32_t frames, bool zoom, double& cpuMs) {
  const uint32_t w = std::max(1u, static_cast<uint32_t>(std::lround(W * scale)));
  const uint32_t h = std::max(1u, static_cast<uint32_t>(std::lround(H * scale)));
  const size_t n = size_t{w} * h;
  std::vector<uint8_t> rgba(n * 4, 255);
  std::vector<glm::vec2> motion(n, glm::vec2(0.3f, -0.1f));
  std::vector<float> depth(n, 10.0f);
  std::vector<pa::InstanceId> instance(n, 0);
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x) {
      const size_t i = size_t{y} * w + x;
      rgba[i * 4 + 0] = static_cast<uint8_t>((x * 7 + y * 3) & 255);
      rgba[i * 4 + 1] = static_cast<uint8_t>(((x / 4 + y / 4) & 1) * 200);
      rgba[i * 4 + 2] = static_cast<uint8_t>(y & 255);
      if (zoom) {   // 5% of the distance from the centre a frame outward, and as much around it
        const glm::vec2 d(static_cast<float>(x) - 0.5f * static_cast<float>(w),
                          static_cast<float>(y) - 0.5f * static_cast<float>(h));
        motion[i] = -0.05f * (d + glm::vec2(-d.y, d.x));
      }
      if (y < h / 8) {   // sky band: reprojected by the camera's turn
        depth[i] = std::numeric_limits<float>::infinity();
        motion[i] = glm::vec2(std::numeric_limits<float>::quiet_NaN());
      }
    }
  pa::Camera camera;
  camera.forward = {1, 0, 0};
  camera.left = {0, 1, 0};
  camera.up = {0, 0, 1};
  camera.fovX = 90.0f;
  camera.fovY = 59.0f;
  std::vector<double> times, cpu;
  tbb::task_arena arena(static_cast<int>(threads));
  arena.execute([&] {
    pa::taau::Upscaler upscaler;
    for (uint32_t f = 0; f < frames; ++f) {
      camera.forward = glm::vec3(std::cos(0.001f * f), std::sin(0.001f * f), 0.0f);
      camera.left = glm::vec3(-std::sin(0.001f * f), std::cos(0.001f * f), 0.0f);
      const pa::taau::Frame frame{w, h, rgba, motion, depth, instance, pa::taau::jitter(f), &camera};
      const double cpuStart = threadCpuMs();
      const auto start = std::chrono::steady_clock::now();
      upscaler.resolve(frame, W, H);
      times.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
      cpu.push_back(threadCpuMs() - cpuStart);
    }
  });
  std::nth_element(cpu.begin(), cpu.begin() + cpu.size() / 2, cpu.end());
  cpuMs = cpu[cpu.size() / 2];
  std::nth_element(times.begin(), times.begin() + times.size() / 2, times.end());
  return times[times.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  const uint32_t W = argc > 1 ? static_cast<uint32_t>(std::atoi(argv[1])) : 640;
  const uint32_t H = argc > 2 ? static_cast<uint32_t>(std::atoi(argv[2])) : 360;
  const float scale = argc > 3 ? static_cast<float>(std::atof(argv[3])) : 0.5f;
  const uint32_t frames = argc > 4 ? static_cast<uint32_t>(std::atoi(argv[4])) : 200;
  const uint32_t threads = argc > 5 ? static_cast<uint32_t>(std::atoi(argv[5])) : 2;
  const std::string motion = argc > 6 ? argv[6] : "pan";
  if (W == 0 || H == 0 || !(scale > 0.0f && scale <= 1.0f) || frames == 0 || threads == 0 ||
      (motion != "pan" && motion != "zoom")) {
    std::fprintf(stderr, "usage: pa-taau-timing [outWidth outHeight scale frames threads pan|zoom]\n");
    return 2;
  }
  const bool zoom = motion == "zoom";
  double cpuOne = 0.0, cpuMany = 0.0;
  const double one = medianMs(1, W, H, scale, frames, zoom, cpuOne);
  const double many = medianMs(threads, W, H, scale, frames, zoom, cpuMany);
  std::printf("TAAU %ux%u from scale %.2f, %s, median of %u frames: 1 thread %.2f ms wall (%.2f ms CPU), %u threads "
              "%.2f ms wall\n", W, H, scale, motion.c_str(), frames, one, cpuOne, threads, many);
  return 0;
}
