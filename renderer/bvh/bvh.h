#pragma once
// Public BVH interface: per-mesh bottom-level BVHs (Blas) and a top-level BVH over
// transformed instances (Tlas). Implementation details (binned SAH build, wide SIMD
// layout, watertight triangle test) live in the other files of this folder.
#include <cstdint>
#include <memory>
#include <span>

#include <glm/mat4x3.hpp>
#include <glm/vec3.hpp>

#include "renderer/core/bounds.h"
#include "renderer/core/ray.h"

namespace pa {

/// Build knobs, with defaults that suit game maps. Every knob is measured in docs/performance.md.
struct BvhBuildConfig {
  /// SAH bins per axis (32 beat 16 on real maps: docs/performance.md, "Trade-off knobs").
  uint32_t binCount = 32;
  /// Children per node of the traversed layout: 8 (AVX2, or AVX-512 run as 256-bit halves),
  /// 16 (AVX-512 at full width; needs AVX-512), or 0 for the faster one on this CPU (16 where
  /// 512-bit operations run at full width, docs/performance.md "Rays per map and per layout").
  uint32_t nodeWidth = 0;
  /// Hard upper bound on triangles per leaf of the binary SAH build. The wide layouts may merge
  /// leaves up to 16 triangles where the collapse's cost model prefers that (wide_collapse.h).
  uint32_t maxLeafTriangles = 8;
  float traversalCost = 1.0f;      ///< SAH cost of visiting a node, relative to one triangle test.
  uint32_t parallelThreshold = 4096;  ///< Subtrees smaller than this are built serially.
  /// Pre-splitting: extra references to parts of large triangles, as a fraction of the triangle
  /// count (0 = off, at most 4). Off by default: gains and losses by scene, 1.2-3.5x the build
  /// time at 0.3-1 (docs/performance.md, "Pre-splitting").
  float splitBudget = 0.0f;
  /// Traverse with the AVX-512 kernel where the CPU has it; false keeps the AVX2 (or SSE) kernel
  /// that CPUs without AVX-512 run, so both can be measured on one machine (`bench --isa avx2`).
  bool allowAvx512 = true;
};

/// Most rays one packet query (Blas::intersectPacket, Tlas::intersectPacket) traces.
inline constexpr uint32_t kMaxPacketRays = 16;

/// Most boxes Blas::pieceBounds cuts a mesh into.
inline constexpr size_t kMaxBlasPieces = 16;

/// What a hit on one triangle needs before it counts (BlasInput::rules).
enum class HitRule : uint8_t {
  Opaque = 0,     ///< Every hit counts.
  Filtered = 1,   ///< Each candidate hit goes through the ray's HitFilter callback (alpha test).
  /// Opaque on one face only: rays whose HitFilter::cull names a face skip hits on that face in
  /// the traversal kernels (no callback); other rays take every hit, as Opaque.
  OneSided = 2,
};

/// Triangle mesh input. Indices are 3 per triangle; rules (optional: empty = all Opaque) holds
/// one HitRule per triangle.
struct BlasInput {
  std::span<const glm::vec3> positions;
  std::span<const uint32_t> indices;
  std::span<const HitRule> rules;
};

/// Bottom-level acceleration structure over one triangle mesh.
/// Hit.prim is the triangle index in the input; Hit.instance is the instanceId passed in.
class Blas {
 public:
  Blas();
  ~Blas();
  Blas(Blas&&) noexcept;
  Blas& operator=(Blas&&) noexcept;

  /// Builds from scratch (multithreaded in the current TBB arena). Throws std::invalid_argument
  /// on out-of-range indices or non-finite positions. Degenerate triangles are kept but never hit.
  /// A rebuild reuses the previous build's memory; invalid input leaves the Blas unchanged.
  void build(const BlasInput& input, const BvhBuildConfig& config = {});
  /// Holds at least the memory that rebuilding example's mesh would use (and keeps it between
  /// builds), so that rebuilds of meshes up to that size and shape allocate nothing: dynamic
  /// meshes in play take this once instead of growing while they are shown.
  void reserveLike(const Blas& example);
  /// Updates node bounds for moved vertices with the same topology (animated meshes).
  void refit(std::span<const glm::vec3> positions);
  /// Closest hit in [ray.tmin, ray.tmax]; on a hit shortens ray.tmax, fills hit, returns true.
  bool intersect(Ray& ray, Hit& hit, const HitFilter& filter = {}, uint32_t instanceId = 0) const;
  /// Any hit in [ray.tmin, ray.tmax] (shadow rays).
  bool occluded(const Ray& ray, const HitFilter& filter = {}, uint32_t instanceId = 0) const;
  /// Closest hits of up to kMaxPacketRays rays traced together (coherent rays such as a tile's
  /// camera rays): for each bit i of active, as intersect(rays[i], hits[i], filters[i],
  /// instanceId). Returns the bits of the rays that hit. The spans hold at least the highest
  /// active bit's ray.
  uint32_t intersectPacket(std::span<Ray> rays, std::span<Hit> hits, uint32_t active,
                           std::span<const HitFilter> filters, uint32_t instanceId = 0) const;
  /// Any hits of up to kMaxPacketRays rays traced together (coherent rays such as a tile's
  /// shadow rays toward one light): for each bit i of active, as occluded(rays[i], filters[i],
  /// instanceId). Returns the bits of the rays that hit something. The spans hold at least the
  /// highest active bit's ray.
  uint32_t occludedPacket(std::span<const Ray> rays, uint32_t active, std::span<const HitFilter> filters,
                          uint32_t instanceId = 0) const;
  /// Bounds of all triangles.
  Bounds bounds() const;
  /// Boxes that together hold every triangle, for a mesh whose triangles lie scattered (a frame's
  /// impact marks and sprites over the whole map): the tree cut at up to out.size() (at most
  /// kMaxBlasPieces) nodes, the largest split first. Writes them and returns how many; 0 when
  /// their areas sum to half of bounds()'s or more (a compact mesh: its box is as tight).
  size_t pieceBounds(std::span<Bounds> out) const;
  /// Number of triangles built.
  uint32_t triangleCount() const;
  /// Children per node of the layout rays traverse (8 or 16; BvhBuildConfig::nodeWidth).
  uint32_t nodeWidth() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// One placed copy of a Blas. objectToWorld is a 3x4 affine transform (glm: 4 columns of vec3).
/// The Blas must outlive the Tlas build that references it.
struct TlasInstance {
  const Blas* blas = nullptr;
  glm::mat4x3 objectToWorld{1.0f};
  uint32_t mask = 0xffffffffu;   ///< Ray is tested against the instance only if (ray mask & mask) != 0.
};

/// Top-level acceleration structure over instances, rebuilt per frame.
/// Hit.instance is the index into the instance span given to build(); t is in world units.
class Tlas {
 public:
  Tlas();
  ~Tlas();
  Tlas(Tlas&&) noexcept;
  Tlas& operator=(Tlas&&) noexcept;

  /// Builds over the instances (copied). Throws std::invalid_argument on a null Blas or a
  /// non-finite / singular transform.
  void build(std::span<const TlasInstance> instances);
  /// Closest hit over all instances whose mask matches rayMask.
  bool intersect(Ray& ray, Hit& hit, uint32_t rayMask = 0xffffffffu, const HitFilter& filter = {}) const;
  /// Closest hits of up to kMaxPacketRays rays traced together, over all instances whose mask
  /// matches rayMask: for each bit i of active, as intersect(rays[i], hits[i], rayMask,
  /// filters[i]). Returns the bits of the rays that hit.
  uint32_t intersectPacket(std::span<Ray> rays, std::span<Hit> hits, uint32_t active, uint32_t rayMask,
                           std::span<const HitFilter> filters) const;
  /// Any hit over all instances whose mask matches rayMask.
  bool occluded(const Ray& ray, uint32_t rayMask = 0xffffffffu, const HitFilter& filter = {}) const;
  /// Any hits of up to kMaxPacketRays rays traced together (a tile's shadow rays toward one
  /// light): for each bit i of active, as occluded(rays[i], rayMask, filters[i]); the static world
  /// takes them as a packet (Blas::occludedPacket). Returns the bits of the rays that hit something.
  uint32_t occludedPacket(std::span<const Ray> rays, uint32_t active, uint32_t rayMask,
                          std::span<const HitFilter> filters) const;
  /// The bits of `active` (up to kMaxPacketRays rays) whose ray may enter an instance's box within
  /// its [tmin, tmax]: each instance's own box in its object space where there are at most four,
  /// else bounds(); the boxes widened by 2^-16 of the coordinates' size, so that a ray left out
  /// has no hit here. A cheap cull before a packet query that few rays need.
  uint32_t raysMayHit(std::span<const Ray> rays, uint32_t active) const;
  /// World bounds of all instances.
  Bounds bounds() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace pa
