#pragma once
// The three ray sets the bench traces with both BVHs: primary (camera, 4x4 pixel tiles so 16
// consecutive rays form a coherent packet), incoherent (cosine-distributed bounces leaving the
// surface points the primary rays found) and shadow (segments from those points to random
// points of a light region).
#include <cstdint>
#include <vector>

#include "renderer/bench/bench_scene.h"
#include "renderer/bvh/bvh.h"
#include "renderer/core/ray.h"

namespace pa::bench {

/// Rays shared by both contenders.
struct RaySets {
  std::vector<Ray> primary;      ///< width * height, in 4x4 tile order
  std::vector<Ray> incoherent;
  std::vector<Ray> shadow;
  /// Shadow rays between one lamp beside the camera and the primary rays' hits, in their tile
  /// order, traced from the lamp (a tile's shadow rays toward one light, sharing their origin:
  /// coherent, traced as packets of 16).
  std::vector<Ray> lampShadow;
  uint32_t surfacePoints = 0;    ///< Primary rays that hit something.
};

/// Builds the sets; `blas` (over scene.mesh) finds the surface points. Secondary sets have
/// `secondaryCount` rays (surface points are reused round-robin when there are fewer).
RaySets makeRaySets(const BenchScene& scene, const Blas& blas, uint32_t width, uint32_t height,
                    uint32_t secondaryCount, uint32_t seed);

}  // namespace pa::bench
