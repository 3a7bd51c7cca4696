// The resolve, 8 output pixels a step (taau::Upscaler), against the one-pixel-at-a-time resolve it
// replaced (scalar_upscaler.h), on synthetic sequences that take every path: still and moving
// pixels in one step, motion that varies across a row, disocclusion, the sky under a turning
// camera, the history's borders, rows whose width is not a multiple of 8, several scales.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <vector>

#include <tbb/task_arena.h>

#include "renderer/scene/taau/taau.h"
#include "scalar_upscaler.h"

namespace pa::taau {
namespace {

/// What differs between two RGBA8 images: the largest difference of a byte, and the pixels that differ.
struct Difference {
  int largest = 0;
  size_t pixels = 0;
};

Difference compare(std::span<const uint8_t> a, std::span<const uint8_t> b) {
  Difference d;
  EXPECT_EQ(a.size(), b.size());
  for (size_t p = 0; p * 4 < std::min(a.size(), b.size()); ++p) {
    int worst = 0;
    for (size_t c = 0; c < 4; ++c) worst = std::max(worst, std::abs(int(a[p * 4 + c]) - int(b[p * 4 + c])));
    d.largest = std::max(d.largest, worst);
    d.pixels += worst > 0 ? 1 : 0;
  }
  return d;
}

/// One traced frame of a coloured scene: a textured background that pans (or, with `swirl`,
/// turns about a point so the motion differs along each row), a square in front that moves the
/// other way (its own instance), and a sky band at the top (infinite depth, no motion).
struct Sequence {
  Sequence(uint32_t tracedWidth, uint32_t tracedHeight, uint32_t outWidth, uint32_t outHeight)
      : w(tracedWidth), h(tracedHeight), W(outWidth), H(outHeight) {}
  uint32_t w, h, W, H;
  bool swirl = false;
  bool still = false;
  std::vector<uint8_t> rgba;
  std::vector<glm::vec2> motion;
  std::vector<float> depth;
  std::vector<InstanceId> instance;
  Camera camera;

  Frame frame(uint32_t t) {
    const size_t n = size_t{w} * h;
    rgba.assign(n * 4, 255);
    motion.assign(n, glm::vec2(0.0f));
    depth.assign(n, 2.0f);
    instance.assign(n, 0);
    const glm::vec2 jit = jitter(t);
    const float sx = float(w) / float(W), sy = float(h) / float(H);
    const float angle = 0.02f * float(t);
    camera.forward = glm::vec3(std::cos(angle), std::sin(angle), 0.0f);
    camera.left = glm::vec3(-std::sin(angle), std::cos(angle), 0.0f);
    camera.fovX = 90.0f;
    camera.fovY = 2.0f * std::atan(std::tan(0.25f * 3.14159265f) * float(H) / float(W)) * 180.0f / 3.14159265f;
    const float tf = still ? 0.0f : float(t);
    for (uint32_t y = 0; y < h; ++y)
      for (uint32_t x = 0; x < w; ++x) {
        const size_t i = size_t{y} * w + x;
        const float ox = (float(x) + 0.5f + jit.x) / sx, oy = (float(y) + 0.5f + jit.y) / sy;   // output pixels
        glm::vec2 m = still ? glm::vec2(0.0f) : glm::vec2(1.3f, -0.4f);   // previous position minus this one
        if (swirl && !still) {   // turning about the image centre: motion grows with the distance
          const float dx = ox - 0.5f * float(W), dy = oy - 0.5f * float(H);
          m = glm::vec2(-0.06f * dy, 0.06f * dx) + glm::vec2(0.02f * dx, 0.02f * dy);
        }
        const float bx = ox + m.x * tf, by = oy + m.y * tf;   // background texture coordinates
        float r = 0.5f + 0.45f * std::sin(0.9f * bx) * std::cos(0.7f * by);
        float g = ((int(std::floor(bx / 3.0f)) + int(std::floor(by / 3.0f))) & 1) ? 0.8f : 0.1f;
        float b = std::fmod(std::fabs(0.35f * bx - by), 7.0f) < 1.5f ? 0.95f : 0.2f;
        const float cx = 0.6f * float(W) - 1.7f * tf, cy = 0.5f * float(H) + 0.3f * tf;
        if (std::fabs(ox - cx) < 0.15f * float(W) && std::fabs(oy - cy) < 0.2f * float(H)) {
          r = 0.95f, g = 0.4f, b = 0.7f;
          m = still ? glm::vec2(0.0f) : glm::vec2(1.7f, -0.3f);
          instance[i] = 1;
          depth[i] = 1.0f;
        }
        motion[i] = {m.x * sx, m.y * sy};
        if (oy < 0.15f * float(H)) {   // sky
          r = 0.3f, g = 0.5f, b = 0.9f - 0.002f * ox;
          depth[i] = std::numeric_limits<float>::infinity();
          motion[i] = glm::vec2(std::numeric_limits<float>::quiet_NaN());
          instance[i] = kNoId;
        }
        if (t % 5 == 3 && x % 7 == 2) motion[i] = glm::vec2(std::numeric_limits<float>::quiet_NaN());   // new surfaces
        rgba[i * 4 + 0] = static_cast<uint8_t>(std::lround(255.0f * r));
        rgba[i * 4 + 1] = static_cast<uint8_t>(std::lround(255.0f * g));
        rgba[i * 4 + 2] = static_cast<uint8_t>(std::lround(255.0f * b));
      }
    return Frame{w, h, rgba, motion, depth, instance, jit, &camera};
  }
};

/// Runs `frames` frames of `sequence` through both resolves, every frame's output compared.
Difference run(Sequence sequence, uint32_t frames) {
  Upscaler lanes;
  test::ScalarUpscaler scalar;
  Difference worst;
  for (uint32_t t = 0; t < frames; ++t) {
    const Frame f = sequence.frame(t);
    const std::vector<uint8_t> expected = [&] {
      const std::span<const uint8_t> o = scalar.resolve(f, sequence.W, sequence.H);
      return std::vector<uint8_t>(o.begin(), o.end());
    }();
    const Difference d = compare(lanes.resolve(f, sequence.W, sequence.H), expected);
    worst.largest = std::max(worst.largest, d.largest);
    worst.pixels += d.pixels;
    EXPECT_EQ(lanes.historyWeight().size(), scalar.historyWeight().size());
  }
  return worst;
}

void expectSame(const Sequence& s, uint32_t frames) {
  const Difference d = run(s, frames);
  std::printf("%ux%u -> %ux%u%s%s, %u frames: largest byte difference %d, %zu pixel-frames differ\n", s.w, s.h, s.W,
              s.H, s.swirl ? ", swirling" : "", s.still ? ", still" : "", frames, d.largest, d.pixels);
  EXPECT_LE(d.largest, 1);
}

TEST(TaauLanes, MatchesTheScalarResolvePanning) { expectSame(Sequence{50, 31, 99, 61}, 20); }

TEST(TaauLanes, MatchesTheScalarResolveWithMotionThatVariesAlongARow) {
  Sequence s{48, 32, 96, 64};
  s.swirl = true;
  expectSame(s, 20);
}

TEST(TaauLanes, MatchesTheScalarResolveStill) {
  Sequence s{40, 27, 83, 53};
  s.still = true;
  expectSame(s, 20);
}

TEST(TaauLanes, MatchesTheScalarResolveAtOtherScales) {
  Sequence one{37, 23, 37, 23};   // scale 1
  one.swirl = true;
  expectSame(one, 12);
  expectSame(Sequence{20, 13, 61, 39}, 12);   // scale 1/3
  expectSame(Sequence{5, 3, 7, 5}, 8);        // narrower than one step
}

TEST(TaauLanes, OutputIsIdenticalWithOneOrTwoThreads) {
  const auto last = [](int threads) {
    tbb::task_arena arena(threads);
    std::vector<uint8_t> out;
    arena.execute([&] {
      Sequence s{50, 31, 99, 61};
      s.swirl = true;
      Upscaler upscaler;
      for (uint32_t t = 0; t < 10; ++t) {
        const std::span<const uint8_t> o = upscaler.resolve(s.frame(t), s.W, s.H);
        out.assign(o.begin(), o.end());
      }
    });
    return out;
  };
  EXPECT_EQ(last(1), last(2));
}

}  // namespace
}  // namespace pa::taau
