#pragma once
// Path-traced frame timing through pa::Renderer (renderer/scene) for the bench.
#include <cstdint>
#include <optional>
#include <string>

#include "renderer/bench/bench_scene.h"

namespace pa::bench {

/// Median milliseconds of one 640x360 1-spp frame with 1 and 2 threads; empty with a note
/// when the renderer is not available in this build.
struct FrameTimes {
  std::optional<double> oneThreadMs, twoThreadsMs;
  std::string note;
};

/// Measures the frames (reps repetitions each).
FrameTimes measureFrames(const BenchScene& scene, uint32_t reps);

}  // namespace pa::bench
