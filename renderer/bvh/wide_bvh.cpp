// Binary -> 8-wide conversion (along the SAH-optimal plan of wide_collapse.h) and triangle packing.
#include "renderer/bvh/wide_bvh.h"

#include <algorithm>
#include <limits>
#include <stdexcept>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "renderer/bvh/wide_collapse.h"
#include "renderer/core/reuse.h"

namespace pa::bvh_detail {
namespace {

/// The 8-wide layout for WideCollapser: a leaf is 1..16 consecutive 8-wide packs.
struct Layout8 {
  using Node = WideNode;
  using Bvh = WideBvh;
  static constexpr uint32_t kWidth = kWideWidth;
  static constexpr uint32_t kMaxPacks = 16;
  static Node emptyNode() { return makeEmptyWideNode(); }
  static void setChild(Node& node, uint32_t slot, const Bounds& box, uint32_t reference) {
    setWideChild(node, slot, box, reference);
  }
  static void finishNode(Node&, uint32_t) {}
  static uint32_t pool(uint32_t) { return 0; }
  static uint32_t packs(uint32_t count) { return (count + kPackWidth - 1) / kPackWidth; }
  static void resizePools(Bvh& bvh, const uint32_t (&sizes)[2]) { resizeReusing(bvh.packs, sizes[0]); }
  static uint32_t writeLeaf(Bvh& bvh, const TriangleMesh& mesh, std::span<const uint32_t> tris, uint32_t first) {
    const auto count = static_cast<uint32_t>(tris.size());
    const uint32_t n = packs(count);
    for (uint32_t p = 0; p < n; ++p)
      bvh.packs[first + p] = makeTrianglePack(mesh, tris.subspan(p * kPackWidth, std::min(kPackWidth, count - p * kPackWidth)));
    return kLeafBit | ((n - 1) << kPackCountShift) | first;
  }
};

}  // namespace

WideNode makeEmptyWideNode() { return makeEmptyNode<WideNode, kWideWidth>(); }

TrianglePack makeTrianglePack(const TriangleMesh& mesh, std::span<const uint32_t> tris) {
  return makePack<TrianglePack, kPackWidth>(mesh, tris);
}

WideBvh collapseToWide(const BinaryBvh& binary, const TriangleMesh& mesh) {
  WideBvh out;
  collapseToWide(binary, mesh, out);
  return out;
}

void collapseToWide(const BinaryBvh& binary, const TriangleMesh& mesh, WideBvh& out,
                    CollapseWorkspace* workspace) {
  if (binary.empty()) {
    out = WideBvh{};
    return;
  }
  CollapseCosts costs;
  costs.width = kWideWidth;
  costs.packWidth = kPackWidth;
  // Leaves of two packs where they pay (docs/performance.md, "Rays per map and per layout").
  costs.maxLeaf = 2 * kPackWidth;
  CollapseWorkspace local;
  WideCollapser<Layout8>(binary, mesh, costs, out, workspace != nullptr ? *workspace : local).run();
  out.kernel = bestWideKernel();
}

}  // namespace pa::bvh_detail
