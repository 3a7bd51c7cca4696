#pragma once
// Path-traced frame timing through pa::Renderer (renderer/scene) for the bench.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "renderer/bench/bench_scene.h"

namespace pa::bench {

/// One 640x360 1-spp frame with 1 and 2 threads: medians (wall clock and process CPU time) and
/// every wall-clock sample; empty with a note when the renderer is not available in this build.
struct FrameTimes {
  std::optional<double> oneThreadMs, twoThreadsMs;         ///< Median wall-clock ms.
  std::optional<double> oneThreadCpuMs, twoThreadsCpuMs;   ///< Median process CPU ms.
  std::optional<double> speedup;   ///< Median over the repetitions of (1-thread wall / 2-thread wall).
  std::vector<double> oneThreadSamplesMs, twoThreadsSamplesMs;   ///< Wall-clock ms, in order.
  std::string note;
};

/// Measures reps frames with each thread count, alternating 1 and 2 threads so that load
/// changes on a shared machine hit both alike.
FrameTimes measureFrames(const BenchScene& scene, uint32_t reps);

}  // namespace pa::bench
