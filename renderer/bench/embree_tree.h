#pragma once
// Diagnostic for the bench: our 8-wide layout filled from a tree that Embree's own builder
// (rtcBuildBVH) made. Traced by our kernels next to our own tree, it tells how much of the
// distance to Embree is the tree and how much is the traversal (docs/performance.md, "Where the
// gap to Embree is").
#include <embree3/rtcore.h>

#include "renderer/bvh/testing/scene_generators.h"
#include "renderer/bvh/triangle_mesh.h"
#include "renderer/bvh/wide_bvh.h"

namespace pa::bench {

/// Settings of Embree's builder; the defaults match our builder's leaf rule (a range of up to
/// 8 triangles is one leaf, SAH counts triangles in blocks of 8, a node costs one block test).
struct EmbreeTreeConfig {
  unsigned sahBlockSize = 8;    ///< Triangles per SAH cost block.
  unsigned minLeafSize = 8;     ///< Ranges this small become leaves.
  unsigned maxLeafSize = 8;     ///< At most this many triangles per leaf (<= 128).
  float traversalCost = 1.0f;   ///< Cost of a node relative to one block test.
  /// Embree's high-quality build with spatial splits (SBVH), references up to
  /// (1 + splitBudget) x triangles; off: its medium-quality binned SAH build.
  bool spatialSplits = false;
  float splitBudget = 1.0f;
};

/// Our wide BVH over mesh, with the nodes and leaves of Embree's 8-wide SAH tree (children in
/// decreasing box area, as our collapse orders them). Throws std::runtime_error when Embree
/// fails to build.
bvh_detail::WideBvh buildWideFromEmbreeTree(RTCDevice device, const bvh_detail::TriangleMesh& mesh,
                                            const EmbreeTreeConfig& config = {});

}  // namespace pa::bench
