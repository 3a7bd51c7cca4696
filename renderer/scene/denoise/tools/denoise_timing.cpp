// pa-denoise-timing: median wall-clock time of one Denoiser::apply on a synthetic 1-spp-like
// frame (every pixel geometry: the worst case) with a given thread count, plus the variance
// reduction on its noisy planes and a hash of the output's bytes (to compare builds). A
// measurement tool, not a test.
//   pa-denoise-timing [width height threads repeats iterations history]   (defaults: 640 360 1 15 5 0)
// history 1: as after temporal accumulation in the game, a history-length guide (the left half's
// pixels 8 frames, carrying a per-pixel variance; the rest 1 frame, estimated spatially).
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <span>
#include <vector>

#include <tbb/task_arena.h>

#include "renderer/scene/denoise/denoiser.h"
#include "renderer/scene/tools/timing_tool.h"

using pa::timing::argOr;
using pa::timing::hashBytes;

namespace {

/// Green-channel variance of the frame's left half (a plane at constant light).
double leftHalfVariance(const std::vector<glm::vec3>& img, uint32_t width, uint32_t height) {
  double sum = 0.0, squares = 0.0, n = 0.0;
  for (uint32_t y = 8; y + 8 < height; ++y) {
    for (uint32_t x = 8; x + 8 < width / 2; ++x) {
      const double v = img[size_t{y} * width + x].g;
      sum += v;
      squares += v * v;
      n += 1.0;
    }
  }
  return squares / n - (sum / n) * (sum / n);
}

}  // namespace

int main(int argc, char** argv) {
  const uint32_t width = std::max(16u, argOr(argc, argv, 1, 640));
  const uint32_t height = std::max(16u, argOr(argc, argv, 2, 360));
  const uint32_t threads = std::max(1u, argOr(argc, argv, 3, 1));
  const uint32_t repeats = std::max(1u, argOr(argc, argv, 4, 15));
  pa::denoise::Config config;
  config.iterations = argOr(argc, argv, 5, config.iterations);
  const bool history = argOr(argc, argv, 6, 0) != 0;

  // Left half: a floor receding in depth; right half: a wall with another normal; noise
  // multiplies the radiance by (1 + 0.9 u), u uniform in [-1, 1) (about a 1-spp direct frame).
  const size_t n = size_t{width} * height;
  std::vector<glm::vec3> noisy(n), albedo(n, glm::vec3(0.5f)), normal(n);
  std::vector<float> depth(n), variance(n, 0.0f), length(n, 1.0f);
  uint32_t state = 1u;
  for (uint32_t y = 0; y < height; ++y) {
    for (uint32_t x = 0; x < width; ++x) {
      const size_t i = size_t{y} * width + x;
      state = state * 1664525u + 1013904223u;
      const float u = static_cast<float>(state >> 8) / static_cast<float>(1u << 23) - 1.0f;
      const bool floor = x < width / 2;
      normal[i] = floor ? glm::vec3(0, 0, 1) : glm::vec3(-1, 0, 0);
      depth[i] = floor ? 2.0f + 0.05f * static_cast<float>(y) : 20.0f;
      noisy[i] = glm::vec3(floor ? 0.25f : 0.1f) * (1.0f + 0.9f * u);
      if (floor) {
        length[i] = 8.0f;
        variance[i] = 0.01f * (1.5f + u);
      }
    }
  }
  pa::denoise::Guides guides{width, height, albedo, normal, depth, variance, 1, {}, {}};
  if (history) guides.historyLength = length;

  tbb::task_arena arena(static_cast<int>(threads));
  pa::denoise::Denoiser denoiser(config);
  std::vector<glm::vec3> image;
  std::vector<double> ms;
  arena.execute([&] {
    for (uint32_t r = 0; r <= repeats; ++r) {   // the first run warms the scratch buffers
      image = noisy;
      const auto start = std::chrono::steady_clock::now();
      denoiser.apply(guides, image);
      const std::chrono::duration<double, std::milli> took = std::chrono::steady_clock::now() - start;
      if (r > 0) ms.push_back(took.count());
    }
  });
  std::sort(ms.begin(), ms.end());
  const double before = leftHalfVariance(noisy, width, height);
  const double after = leftHalfVariance(image, width, height);
  std::printf("%ux%u threads %u iterations %u history %d: median %.2f ms (min %.2f, max %.2f, %u runs); "
              "plane variance %.3g -> %.3g (%.1fx lower); output hash %016llx\n",
              width, height, threads, config.iterations, history ? 1 : 0, ms[ms.size() / 2], ms.front(), ms.back(), repeats, before,
              after, before / after, static_cast<unsigned long long>(hashBytes(pa::timing::kHashStart, std::span<const glm::vec3>(image))));
  return 0;
}
