// Blas: validated mesh copy + reference binary BVH (+ the wide SIMD layout it is converted to).
// A rebuild reuses the previous build's memory (mesh copy, binary nodes, and, from the second
// build on, the builder's scratch arrays), so meshes rebuilt every frame do not page-fault
// fresh memory on each build.
#include <algorithm>
#include <array>
#include <stdexcept>

#include "renderer/bvh/binary_bvh.h"
#include "renderer/bvh/bvh.h"
#include "renderer/bvh/cpu_features.h"
#include "renderer/bvh/triangle_mesh.h"
#include "renderer/bvh/wide_collapse.h"
#include "renderer/bvh/wide16_bvh.h"
#include "renderer/bvh/wide_bvh.h"

namespace pa {

struct Blas::Impl {
  bvh_detail::TriangleMesh mesh;
  bvh_detail::BinaryBvh binary;   // reference layout, kept for refit and validation
  bvh_detail::WideBvh wide;       // what rays traverse when nodeWidth is 8
  bvh_detail::Wide16Bvh wide16;   // what rays traverse when nodeWidth is 16
  uint32_t nodeWidth = 8;         // as the build resolved it
  bool allowAvx512 = true;        // the build's BvhBuildConfig::allowAvx512 (a refit keeps it)
  Bounds bounds;
  bvh_detail::BinaryBuildScratch scratch;   // kept between builds once the Blas is rebuilt
  bvh_detail::CollapseWorkspace collapseWorkspace;   // likewise, for the conversion to the wide layout
  std::vector<Bounds> triangleBoxes;        // a refit's triangle boxes (kept: refits repeat)
  uint32_t builds = 0;
  bool keepsBuildMemory = false;   // reserveLike: the first build keeps its scratch too

  /// Converts binary into the layout of nodeWidth (the other layout is emptied); allowAvx512
  /// false keeps the 8-wide layout on its baseline kernel.
  void collapse() {
    if (nodeWidth == 16) {
      wide = bvh_detail::WideBvh{};
      bvh_detail::collapseToWide16(binary, mesh, wide16, &collapseWorkspace);
      return;
    }
    wide16 = bvh_detail::Wide16Bvh{};
    bvh_detail::collapseToWide(binary, mesh, wide, &collapseWorkspace);   // reuses the previous layout's memory
    if (!allowAvx512) wide.kernel = bvh_detail::WideKernel::Baseline;
  }
};

namespace {

/// The node width a build with config uses (BvhBuildConfig::nodeWidth).
uint32_t resolveNodeWidth(const BvhBuildConfig& config) {
  const bool wide16 = config.allowAvx512 && bvh_detail::wide16Available();
  if (config.nodeWidth == 16) {
    if (!wide16) throw std::invalid_argument("BvhBuildConfig.nodeWidth 16 needs AVX-512 (and allowAvx512)");
    return 16;
  }
  if (config.nodeWidth == 8) return 8;
  return wide16 && bvh_detail::cpuFeatures().fullWidthAvx512 ? 16 : 8;
}

}  // namespace

Blas::Blas() : impl_(std::make_unique<Impl>()) {}
Blas::~Blas() = default;
Blas::Blas(Blas&&) noexcept = default;
Blas& Blas::operator=(Blas&&) noexcept = default;

void Blas::build(const BlasInput& input, const BvhBuildConfig& config) {
  // Invalid input or config throws here, before anything changes.
  bvh_detail::validateBuildConfig(config);
  bvh_detail::validateBlasInput(input);
  if (!impl_) impl_ = std::make_unique<Impl>();
  Impl& impl = *impl_;
  BvhBuildConfig resolved = config;
  resolved.nodeWidth = resolveNodeWidth(config);
  try {
    bvh_detail::assignTriangleMesh(input, impl.mesh);
    bvh_detail::buildBinaryBvh(impl.mesh, resolved, impl.scratch, impl.binary);
    impl.nodeWidth = resolved.nodeWidth;
    impl.allowAvx512 = config.allowAvx512;
    impl.collapse();
    // The root box is the union of all triangles.
    impl.bounds = impl.binary.empty() ? Bounds{} : impl.binary.nodes[0].bounds;
  } catch (...) {
    impl_ = std::make_unique<Impl>();   // out of memory or too large for the wide layout: left empty
    throw;
  }
  // A Blas built once (static geometry) does not hold on to the scratch arrays; one that is
  // rebuilt is likely to be rebuilt again (dynamic geometry) and keeps them.
  // A Blas that keeps its memory also makes room for a refit's triangle boxes, so that its
  // first refit in play allocates nothing either.
  if (++impl.builds == 1 && !impl.keepsBuildMemory) {
    impl.scratch.release();
    impl.collapseWorkspace = bvh_detail::CollapseWorkspace{};
  } else if (impl.triangleBoxes.capacity() < impl.mesh.triangleCount()) {
    impl.triangleBoxes.reserve(impl.mesh.triangleCount());
  }
}

namespace {

/// Makes room for n elements in v without changing its contents.
template <class Vector>
void reserveAtLeast(Vector& v, size_t n) {
  if (n > v.capacity()) v.reserve(n);
}

}  // namespace

void Blas::reserveLike(const Blas& example) {
  if (!impl_) impl_ = std::make_unique<Impl>();
  Impl& impl = *impl_;
  impl.keepsBuildMemory = true;
  if (!example.impl_) return;
  const Impl& other = *example.impl_;
  // The most triangles the example has held (its per-triangle arrays keep their capacity), not
  // only what it holds now: a pooled slot may show a smaller mesh at the moment.
  const size_t triangles = std::max<size_t>(other.mesh.triangleCount(), other.mesh.degenerate.capacity());
  reserveAtLeast(impl.mesh.positions, other.mesh.positions.capacity());
  reserveAtLeast(impl.mesh.indices, other.mesh.indices.capacity());
  reserveAtLeast(impl.mesh.rules, other.mesh.rules.capacity());
  reserveAtLeast(impl.mesh.degenerate, other.mesh.degenerate.capacity());
  reserveAtLeast(impl.binary.nodes, other.binary.nodes.capacity());
  reserveAtLeast(impl.binary.primIndices, other.binary.primIndices.capacity());
  impl.scratch.memory.reserve(bvh_detail::binaryBuildScratchBytes(triangles));
  reserveAtLeast(impl.scratch.renumberStack, 2 * triangles + 1);   // the depth-first stack: at most the depth
  const auto width = other.nodeWidth;
  impl.collapseWorkspace.plan.reserve(other.binary.nodes.capacity(), width);
  const size_t leaves = std::max<size_t>(other.binary.leafCount, other.collapseWorkspace.leaves.capacity());
  reserveAtLeast(impl.collapseWorkspace.leaves, leaves);
  reserveAtLeast(impl.collapseWorkspace.firstPack, leaves);
  reserveAtLeast(impl.wide.nodes, other.wide.nodes.capacity());
  reserveAtLeast(impl.wide.packs, other.wide.packs.capacity());
  reserveAtLeast(impl.wide16.nodes, other.wide16.nodes.capacity());
  reserveAtLeast(impl.wide16.packs, other.wide16.packs.capacity());
  reserveAtLeast(impl.wide16.smallPacks, other.wide16.smallPacks.capacity());
  reserveAtLeast(impl.triangleBoxes, triangles);
}

void Blas::refit(std::span<const glm::vec3> positions) {
  if (!impl_) impl_ = std::make_unique<Impl>();
  bvh_detail::updatePositions(impl_->mesh, positions);
  std::vector<Bounds>& triBounds = impl_->triangleBoxes;
  bvh_detail::triangleBounds(impl_->mesh, triBounds);
  bvh_detail::refitBinaryBvh(impl_->binary, triBounds);
  // A refit moves boxes, not the tree: the build's plan, where the workspace still holds it (a
  // Blas that keeps its memory; not after a release or a reserveLike, which drop it), gives the
  // same wide tree, whose arrays are already the right size; planning again over the moved boxes
  // could choose more nodes or small packs than the build did, and allocate.
  impl_->collapseWorkspace.keepPlan = true;
  impl_->collapse();   // the build's layout and kernel
  impl_->collapseWorkspace.keepPlan = false;
  impl_->bounds = Bounds{};
  for (const Bounds& b : triBounds) impl_->bounds.extend(b);
}

bool Blas::intersect(Ray& ray, Hit& hit, const HitFilter& filter, uint32_t instanceId) const {
  if (!impl_ || !bvh_detail::isTraceableRay(ray)) return false;
  if (impl_->nodeWidth == 16) return bvh_detail::intersectWide16(impl_->wide16, ray, hit, filter, instanceId);
  return bvh_detail::intersectWide(impl_->wide, ray, hit, filter, instanceId);
}

uint32_t Blas::intersectPacket(std::span<Ray> rays, std::span<Hit> hits, uint32_t active,
                               std::span<const HitFilter> filters, uint32_t instanceId) const {
  if (!impl_) return 0;
  active = bvh_detail::activePacketLanes(active, std::min({rays.size(), hits.size(), filters.size()}),
                                         "Blas::intersectPacket");
  // The kernels skip the rays that are not traceable (isTraceableRay).
  if (impl_->nodeWidth == 16)
    return bvh_detail::intersectWide16Packet(impl_->wide16, rays.data(), hits.data(), active, filters.data(),
                                             instanceId);
  return bvh_detail::intersectWidePacket(impl_->wide, rays.data(), hits.data(), active, filters.data(), instanceId);
}

uint32_t Blas::occludedPacket(std::span<const Ray> rays, uint32_t active, std::span<const HitFilter> filters,
                              uint32_t instanceId) const {
  if (!impl_) return 0;
  active = bvh_detail::activePacketLanes(active, std::min(rays.size(), filters.size()), "Blas::occludedPacket");
  // The kernels skip the rays that are not traceable (isTraceableRay).
  if (impl_->nodeWidth == 16)
    return bvh_detail::occludedWide16Packet(impl_->wide16, rays.data(), active, filters.data(), instanceId);
  return bvh_detail::occludedWidePacket(impl_->wide, rays.data(), active, filters.data(), instanceId);
}

bool Blas::occluded(const Ray& ray, const HitFilter& filter, uint32_t instanceId) const {
  if (!impl_ || !bvh_detail::isTraceableRay(ray)) return false;
  if (impl_->nodeWidth == 16) return bvh_detail::occludedWide16(impl_->wide16, ray, filter, instanceId);
  return bvh_detail::occludedWide(impl_->wide, ray, filter, instanceId);
}

Bounds Blas::bounds() const { return impl_ ? impl_->bounds : Bounds{}; }

size_t Blas::pieceBounds(std::span<Bounds> out) const {
  const size_t limit = std::min(out.size(), kMaxBlasPieces);
  if (!impl_ || limit < 2 || impl_->binary.empty() || impl_->binary.nodes.empty()) return 0;
  const std::vector<bvh_detail::BinaryNode>& nodes = impl_->binary.nodes;
  std::array<uint32_t, kMaxBlasPieces> cut{};   // node indices; their subtrees hold every triangle once
  size_t count = 1;
  while (count < limit) {
    size_t widest = count;
    for (size_t i = 0; i < count; ++i)
      if (!nodes[cut[i]].isLeaf() &&
          (widest == count || nodes[cut[i]].bounds.halfArea() > nodes[cut[widest]].bounds.halfArea()))
        widest = i;
    if (widest == count) break;   // every piece is a leaf
    const bvh_detail::BinaryNode& split = nodes[cut[widest]];
    cut[widest] = split.left;
    cut[count++] = split.right;
  }
  float area = 0.0f;
  for (size_t i = 0; i < count; ++i) area += nodes[cut[i]].bounds.halfArea();
  if (count < 2 || !(area < 0.5f * nodes[0].bounds.halfArea())) return 0;
  for (size_t i = 0; i < count; ++i) out[i] = nodes[cut[i]].bounds;
  return count;
}

uint32_t Blas::triangleCount() const { return impl_ ? impl_->mesh.triangleCount() : 0; }

uint32_t Blas::nodeWidth() const { return impl_ ? impl_->nodeWidth : 8; }

}  // namespace pa
