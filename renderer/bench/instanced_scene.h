#pragma once
// A game frame's two-level scene for the bench (--instances N): the scene's mesh as the static
// world (one instance, identity transform) plus N small movers (closed spheres of a few hundred
// triangles, each about the size of a player in a Quake III map) standing in front of surfaces
// around the camera, a few of them in view, as ours (Tlas over Blases) and as Embree's (a scene of instanced scenes).
#include <cstdint>
#include <memory>
#include <vector>

#include "renderer/bench/bench_scene.h"
#include "renderer/bvh/bvh.h"
#include "renderer/bvh/testing/embree_oracle.h"

namespace pa::bench {

/// Both contenders' two-level scenes over the same instances.
struct InstancedScene {
  Blas mover;                      ///< The movers' mesh (one Blas, instanced N times).
  std::vector<TlasInstance> instances;   ///< [0] the world, then the movers.
  Tlas tlas;
  std::unique_ptr<testing::EmbreeScene> embreeMover, embreeTop;
};

/// Builds both over `world` (our Blas of scene.mesh) and `embreeWorld` (Embree's committed scene
/// of the same mesh), with `movers` movers placed from `seed` around the camera.
/// Throws std::runtime_error when no camera ray hits the world.
void buildInstancedScene(const BenchScene& scene, const Blas& world, const testing::EmbreeScene& embreeWorld,
                         const testing::EmbreeDevice& device, uint32_t movers, uint32_t seed, InstancedScene& out);

}  // namespace pa::bench
