#pragma once
// The 8-wide BVH layout traversed with SIMD slab tests, converted from the binary BVH, with leaf
// triangles precomputed into 8-wide structure-of-arrays packs for the SIMD watertight test.
#include <algorithm>
#include <cstdint>
#include <limits>
#include <span>
#include <stdexcept>
#include <vector>

#include "renderer/bvh/binary_bvh.h"
#include "renderer/bvh/triangle_mesh.h"
#include "renderer/core/ray.h"

namespace pa::bvh_detail {

struct CollapseWorkspace;

inline constexpr uint32_t kWideWidth = 8;
inline constexpr uint32_t kPackWidth = 8;

/// Child reference: inner node index, or (kLeafBit | packCount - 1 << kPackCountShift | firstPack).
inline constexpr uint32_t kLeafBit = 0x80000000u;
inline constexpr uint32_t kPackCountShift = 27;   ///< 4 bits: 1..16 packs (128 triangles) per leaf.
inline constexpr uint32_t kFirstPackMask = (1u << kPackCountShift) - 1;

/// Eight child boxes as structure of arrays; bounds[0] = lower, bounds[1] = upper, then axis.
/// Unused slots hold an empty box (lower = +inf, upper = -inf) that no ray can enter.
struct alignas(32) WideNode {
  float bounds[2][3][kWideWidth];
  uint32_t child[kWideWidth];
};
static_assert(sizeof(WideNode) == 224);

/// Up to kLanes triangles: vertices as structure of arrays (vertex, axis, lane), aligned to
/// one SIMD register of kLanes floats. Lanes not in validBits (padding, degenerate triangles)
/// are never reported.
template <uint32_t kLanes>
struct alignas(4 * kLanes) TrianglePackOf {
  float v[3][3][kLanes];
  uint32_t prim[kLanes];
  uint32_t validBits = 0;    ///< Lanes holding a real, non-degenerate triangle.
  uint32_t maskedBits = 0;   ///< Lanes whose hits go through the HitFilter (HitRule::Filtered).
  uint32_t oneSidedBits = 0; ///< Lanes of HitRule::OneSided triangles (culled by HitFilter::cull).
};

/// The 8-wide layout's pack (kPackWidth triangles).
using TrianglePack = TrianglePackOf<kPackWidth>;

/// Traversal kernel implementations. All give the same results bit for bit (same arithmetic).
enum class WideKernel : uint8_t {
  Baseline,   ///< The build's ISA: AVX2 for x86-64-v3, SSE halves for x86-64-v2.
  Avx512,     ///< AVX-512 F/VL/BW/DQ (mask registers, compress); x86-64-v3 builds only.
};

/// Whether this build has the kernel and this CPU (and OS) can run it.
bool wideKernelAvailable(WideKernel kernel);

/// The fastest available kernel; chosen once per collapse, so a BVH never changes kernel.
WideKernel bestWideKernel();

/// 8-wide BVH; node 0 is the root (when not empty).
struct WideBvh {
  std::vector<WideNode> nodes;
  std::vector<TrianglePack> packs;
  WideKernel kernel = WideKernel::Baseline;   ///< Which traversal runs (tests may pick any available one).
  bool empty() const { return nodes.empty(); }
};

/// A node of either width whose slots are empty (a box no ray enters, child reference 0; the
/// rest of the node zero).
template <class Node, uint32_t kWidth>
Node makeEmptyNode() {
  Node node{};
  for (int axis = 0; axis < 3; ++axis) {
    std::fill_n(node.bounds[0][axis], kWidth, std::numeric_limits<float>::infinity());
    std::fill_n(node.bounds[1][axis], kWidth, -std::numeric_limits<float>::infinity());
  }
  return node;
}

/// A node whose eight slots are empty.
WideNode makeEmptyWideNode();

/// Writes a child's box and reference into one slot of a node of either width.
template <class Node>
void setWideChild(Node& node, uint32_t slot, const Bounds& box, uint32_t child) {
  for (int axis = 0; axis < 3; ++axis) {
    node.bounds[0][axis][slot] = box.min[axis];
    node.bounds[1][axis][slot] = box.max[axis];
  }
  node.child[slot] = child;
}

/// Packs up to kLanes triangles of mesh (indices in tris) into one pack of either width; unused
/// lanes repeat the first triangle's vertices (finite math) and are not valid.
template <class Pack, uint32_t kLanes>
Pack makePack(const TriangleMesh& mesh, std::span<const uint32_t> tris) {
  if (tris.empty() || tris.size() > kLanes) throw std::invalid_argument("a triangle pack holds 1 to its width triangles");
  Pack pack{};
  for (uint32_t lane = 0; lane < kLanes; ++lane) {
    const bool padding = lane >= tris.size();
    const uint32_t tri = padding ? tris[0] : tris[lane];
    for (int vtx = 0; vtx < 3; ++vtx) {
      const glm::vec3 p3 = mesh.vertex(tri, vtx);
      for (int axis = 0; axis < 3; ++axis) pack.v[vtx][axis][lane] = p3[axis];
    }
    pack.prim[lane] = padding ? kInvalidId : tri;
    if (padding) continue;
    if (!mesh.degenerate[tri]) pack.validBits |= 1u << lane;
    if (mesh.isFiltered(tri)) pack.maskedBits |= 1u << lane;
    if (mesh.isOneSided(tri)) pack.oneSidedBits |= 1u << lane;
  }
  return pack;
}

/// Packs up to kPackWidth triangles into one 8-wide pack (makePack).
TrianglePack makeTrianglePack(const TriangleMesh& mesh, std::span<const uint32_t> tris);

/// Converts the binary BVH into the 8-wide layout along the SAH-optimal plan of wide_collapse.h
/// (leaves may merge binary leaves up to two packs) and packs the leaf triangles of mesh.
WideBvh collapseToWide(const BinaryBvh& binary, const TriangleMesh& mesh);
/// Same, into `out`, reusing its vectors' memory (rebuilds of a Blas), and the workspace's when
/// one is given.
void collapseToWide(const BinaryBvh& binary, const TriangleMesh& mesh, WideBvh& out,
                    CollapseWorkspace* workspace = nullptr);

/// Closest hit, same contract as Blas::intersect (the ray must be traceable).
bool intersectWide(const WideBvh& bvh, Ray& ray, Hit& hit, const HitFilter& filter, uint32_t instanceId);

/// Closest hits of the traceable rays (isTraceableRay) in `active` (bit i: rays[i], hits[i],
/// filters[i]; at most 16; the others are left as they are) traced
/// as packets of rays that share an octant (sixteen with the AVX-512 kernel, else eight): per ray
/// the contract of intersectWide. Returns the rays that hit.
unsigned intersectWidePacket(const WideBvh& bvh, Ray* rays, Hit* hits, unsigned active, const HitFilter* filters,
                             uint32_t instanceId);

/// Any hit, same contract as Blas::occluded (the ray must be traceable).
bool occludedWide(const WideBvh& bvh, const Ray& ray, const HitFilter& filter, uint32_t instanceId);

/// Any hits of the traceable rays in `active` traced as packets, as intersectWidePacket: per ray
/// the answer of occludedWide. Returns the rays that hit something.
unsigned occludedWidePacket(const WideBvh& bvh, const Ray* rays, unsigned active, const HitFilter* filters,
                            uint32_t instanceId);

/// The AVX-512 kernels behind intersectWide / occludedWide (wide_traversal_avx512.cpp); only
/// call them when wideKernelAvailable(WideKernel::Avx512).
bool intersectWideAvx512(const WideBvh& bvh, Ray& ray, Hit& hit, const HitFilter& filter, uint32_t instanceId);
bool occludedWideAvx512(const WideBvh& bvh, const Ray& ray, const HitFilter& filter, uint32_t instanceId);
unsigned intersectWidePacketAvx512(const WideBvh& bvh, Ray* rays, Hit* hits, unsigned active,
                                   const HitFilter* filters, uint32_t instanceId);
unsigned occludedWidePacketAvx512(const WideBvh& bvh, const Ray* rays, unsigned active, const HitFilter* filters,
                                  uint32_t instanceId);

}  // namespace pa::bvh_detail
