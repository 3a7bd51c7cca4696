#pragma once
// The 16-wide BVH layout for CPUs whose AVX-512 units are a full 512 bits wide: sixteen child
// boxes and sixteen leaf triangles per instruction (after Fuetterling et al., "Accelerated
// Single Ray Tracing for Wide Vector Units", HPG 2017). Converted from the same binary BVH as
// the 8-wide layout, with the same conservative slab test and watertight triangle test, so hit
// distances are bit-identical to the scalar reference. Children of a closest-hit ray are
// visited in an order fixed per ray octant at build time (no sorting during traversal).
#include <cstdint>
#include <span>
#include <vector>

#include "renderer/bvh/binary_bvh.h"
#include "renderer/bvh/triangle_mesh.h"
#include "renderer/bvh/wide_bvh.h"
#include "renderer/core/ray.h"

namespace pa::bvh_detail {

struct CollapseWorkspace;

inline constexpr uint32_t kWide16Width = 16;

/// Sixteen child boxes as structure of arrays (bounds[0] = lower, bounds[1] = upper, then axis),
/// their references (as in WideNode: kLeafBit | packs - 1 << kPackCountShift | first pack) and,
/// for each of the 8 ray octants (bit 0: x < 0, bit 1: y < 0, bit 2: z < 0), the slots from the
/// farthest to the nearest child along the octant's diagonal: bits 4o..4o+3 of order[i] are the
/// slot visited i-th last by a ray of octant o. Unused slots hold an empty box.
struct alignas(64) Wide16Node {
  float bounds[2][3][kWide16Width];
  uint32_t child[kWide16Width];
  uint32_t order[kWide16Width];
};
static_assert(sizeof(Wide16Node) == 512);

/// Up to sixteen triangles (see TrianglePackOf).
using TrianglePack16 = TrianglePackOf<kWide16Width>;

/// Leaf reference bit of the 16-wide layout: the leaf is one 8-wide TrianglePack (<= 8
/// triangles, in smallPacks) instead of 16-wide packs. Small leaves are most leaves of game maps,
/// and half the bytes of a 16-wide pack; both kinds are tested 16 lanes at once.
inline constexpr uint32_t kSmallLeafBit = 1u << 30;

/// 16-wide BVH; node 0 is the root (when not empty). Traversed only by the AVX-512 kernels.
/// Leaf references: kLeafBit | (kSmallLeafBit, index in smallPacks) or (packs - 1 <<
/// kPackCountShift, first of 1..4 consecutive packs).
struct Wide16Bvh {
  std::vector<Wide16Node> nodes;
  std::vector<TrianglePack16> packs;
  std::vector<TrianglePack> smallPacks;
  bool empty() const { return nodes.empty(); }
};

/// Whether this build has the 16-wide kernels and this CPU (and OS) can run them (AVX-512
/// F/VL/BW/DQ, like WideKernel::Avx512; see cpu_features.h).
bool wide16Available();

/// Packs up to 16 triangles of mesh (indices in tris) into one pack; unused lanes repeat the
/// first triangle's vertices (finite math) and are not valid.
TrianglePack16 makeTrianglePack16(const TriangleMesh& mesh, std::span<const uint32_t> tris);

/// Converts the binary BVH into the 16-wide layout along the SAH-optimal plan of
/// wide_collapse.h (leaves may merge binary leaves up to 16 triangles) into `out`, reusing its
/// vectors' memory, and the workspace's when one is given (nothing allocated for a tree of the
/// same size as the workspace's last).
void collapseToWide16(const BinaryBvh& binary, const TriangleMesh& mesh, Wide16Bvh& out,
                      CollapseWorkspace* workspace = nullptr);

/// Closest hit, same contract as Blas::intersect (the ray must be traceable). Needs
/// wide16Available().
bool intersectWide16(const Wide16Bvh& bvh, Ray& ray, Hit& hit, const HitFilter& filter, uint32_t instanceId);

/// Closest hits of the traceable rays (isTraceableRay) in `active` (bit i: rays[i], hits[i],
/// filters[i]; at most 16; the others are left as they are), traced as packets of rays that share an octant: per ray the contract of intersectWide16
/// (each ray's tmax shrinks to its hit). Returns the rays that hit. Needs wide16Available().
unsigned intersectWide16Packet(const Wide16Bvh& bvh, Ray* rays, Hit* hits, unsigned active, const HitFilter* filters,
                               uint32_t instanceId);

/// Any hit, same contract as Blas::occluded (the ray must be traceable). Needs wide16Available().
bool occludedWide16(const Wide16Bvh& bvh, const Ray& ray, const HitFilter& filter, uint32_t instanceId);

/// Any hits of the traceable rays in `active` traced as packets, as intersectWide16Packet: per
/// ray the answer of occludedWide16. Returns the rays that hit something. Needs wide16Available().
unsigned occludedWide16Packet(const Wide16Bvh& bvh, const Ray* rays, unsigned active, const HitFilter* filters,
                              uint32_t instanceId);

}  // namespace pa::bvh_detail
