// pa-temporal-timing: median wall-clock time of one TemporalFilter::accumulate (reprojection,
// rejection and blend) on a synthetic 1-spp-like frame sequence in its steady state, with a given
// thread count, and a hash of the last frame's output bytes (to compare builds). The view pans
// by a fraction of a pixel a frame, so every pixel takes bilinear taps of a long history. A
// measurement tool, not a test.
//   pa-temporal-timing [width height threads repeats]   (defaults: 640 360 1 15)
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <span>
#include <vector>

#include <tbb/task_arena.h>

#include "renderer/scene/temporal/temporal.h"
#include "renderer/scene/tools/timing_tool.h"

using pa::timing::argOr;
using pa::timing::hashBytes;

int main(int argc, char** argv) {
  const uint32_t width = std::max(16u, argOr(argc, argv, 1, 640));
  const uint32_t height = std::max(16u, argOr(argc, argv, 2, 360));
  const uint32_t threads = std::max(1u, argOr(argc, argv, 3, 1));
  const uint32_t repeats = std::max(1u, argOr(argc, argv, 4, 15));

  // Top eighth: sky; then left half a floor receding in depth, right half a wall with another
  // normal and a second material; a lamp's emission on a strip of the wall. Noise multiplies the
  // radiance by (1 + 0.9 u), u uniform in [-1, 1) (about a 1-spp direct frame), new every frame.
  const size_t n = size_t{width} * height;
  std::vector<glm::vec3> emission(n, glm::vec3(0.0f)), albedo(n), normal(n), radiance(n);
  std::vector<float> depth(n);
  pa::temporal::GBuffer gbuffer;
  gbuffer.resize(width, height);
  for (uint32_t y = 0; y < height; ++y) {
    for (uint32_t x = 0; x < width; ++x) {
      const size_t i = size_t{y} * width + x;
      const bool sky = y < height / 8, floor = x < width / 2;
      normal[i] = floor ? glm::vec3(0, 0, 1) : glm::vec3(-1, 0, 0);
      albedo[i] = glm::vec3(0.5f, 0.4f + 0.2f * static_cast<float>((x / 4 + y / 4) % 2), 0.3f);
      depth[i] = sky ? std::numeric_limits<float>::infinity() : floor ? 2.0f + 0.05f * static_cast<float>(y) : 20.0f;
      if (!floor && x % 32 < 2) emission[i] = glm::vec3(2.0f);
      gbuffer.instance[i] = sky ? pa::kNoId : 0;
      gbuffer.material[i] = sky ? pa::kNoId : floor ? 0 : 1;
      gbuffer.motion[i] = sky ? glm::vec2(pa::temporal::GBuffer::kNoMotion) : glm::vec2(0.37f, -0.21f);
      gbuffer.previousDepth[i] = depth[i];
      gbuffer.previousNormal[i] = normal[i];
    }
  }
  const pa::temporal::FrameInputs frame{width, height, emission, albedo, normal, depth, &gbuffer, {}};

  tbb::task_arena arena(static_cast<int>(threads));
  pa::temporal::TemporalFilter filter;
  std::vector<double> ms;
  uint32_t state = 1u;
  arena.execute([&] {
    // 64 frames fill the histories to their cap, then `repeats` frames are timed.
    for (uint32_t r = 0; r < 64 + repeats; ++r) {
      for (size_t i = 0; i < n; ++i) {
        state = state * 1664525u + 1013904223u;
        const float u = static_cast<float>(state >> 8) / static_cast<float>(1u << 23) - 1.0f;
        radiance[i] = albedo[i] * (normal[i].z > 0.5f ? 0.5f : 0.2f) * (1.0f + 0.9f * u) + emission[i];
      }
      if (r % 16 == 15) radiance[n / 2 + width / 4] = glm::vec3(std::numeric_limits<float>::quiet_NaN());
      const auto start = std::chrono::steady_clock::now();
      filter.accumulate(frame, radiance);
      const std::chrono::duration<double, std::milli> took = std::chrono::steady_clock::now() - start;
      if (r >= 64) ms.push_back(took.count());
      filter.endFrame();
    }
  });
  std::sort(ms.begin(), ms.end());
  uint64_t hash = pa::timing::kHashStart;
  hash = hashBytes(hash, std::span<const glm::vec3>(radiance));
  hash = hashBytes(hash, filter.variance());
  hash = hashBytes(hash, filter.historyLength());
  std::printf("%ux%u threads %u: median %.2f ms (min %.2f, max %.2f, %u runs); output hash %016llx\n", width,
              height, threads, ms[ms.size() / 2], ms.front(), ms.back(), repeats,
              static_cast<unsigned long long>(hash));
  return 0;
}
