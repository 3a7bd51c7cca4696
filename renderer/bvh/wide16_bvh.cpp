// Binary -> 16-wide conversion along the SAH-optimal plan (wide_collapse.h), 16-triangle packs,
// and the per-octant child order.
#include "renderer/bvh/wide16_bvh.h"

#include <algorithm>
#include <array>
#include <limits>
#include <stdexcept>

#include "renderer/bvh/wide_collapse.h"
#include "renderer/core/reuse.h"

namespace pa::bvh_detail {
namespace {

/// Writes order[] of node for its `count` used slots (see Wide16Node::order): per octant, the
/// slots sorted by the distance of their box's entry corner along the octant's diagonal, farthest
/// first; unused slots (never entered) come before all used ones.
void setOctantOrder(Wide16Node& node, uint32_t count) {
  std::fill_n(node.order, kWide16Width, 0u);
  for (uint32_t octant = 0; octant < 8; ++octant) {
    // Used slots by decreasing key (insertion sort: at most 16, stable), after the unused ones.
    float key[kWide16Width];
    uint32_t slots[kWide16Width];
    const uint32_t unused = kWide16Width - count;
    for (uint32_t i = 0; i < unused; ++i) slots[i] = count + i;
    for (uint32_t slot = 0; slot < count; ++slot) {
      float k = 0.0f;
      for (int axis = 0; axis < 3; ++axis) {
        // The corner a ray of this octant enters first: the lower bound for a positive direction.
        k += (octant >> axis & 1) ? -node.bounds[1][axis][slot] : node.bounds[0][axis][slot];
      }
      uint32_t at = unused + slot;
      while (at > unused && key[at - 1] < k) {
        key[at] = key[at - 1];
        slots[at] = slots[at - 1];
        --at;
      }
      key[at] = k;
      slots[at] = slot;
    }
    for (uint32_t i = 0; i < kWide16Width; ++i) node.order[i] |= slots[i] << (4 * octant);
  }
}

/// The 16-wide layout for WideCollapser: leaves of up to 8 triangles in one small pack, larger
/// ones in 16-wide packs.
struct Layout16 {
  using Node = Wide16Node;
  using Bvh = Wide16Bvh;
  static constexpr uint32_t kWidth = kWide16Width;
  static constexpr uint32_t kMaxPacks = 8;   // the count field below kSmallLeafBit
  static Node emptyNode() { return makeEmptyNode<Wide16Node, kWide16Width>(); }
  static void setChild(Node& node, uint32_t slot, const Bounds& box, uint32_t reference) {
    setWideChild(node, slot, box, reference);
  }
  static void finishNode(Node& node, uint32_t count) { setOctantOrder(node, count); }
  static uint32_t pool(uint32_t count) { return count <= kPackWidth ? 0 : 1; }
  static uint32_t packs(uint32_t count) { return count <= kPackWidth ? 1 : (count + kWidth - 1) / kWidth; }
  static void resizePools(Bvh& bvh, const uint32_t (&sizes)[2]) {
    resizeReusing(bvh.smallPacks, sizes[0]);
    resizeReusing(bvh.packs, sizes[1]);
  }
  static uint32_t writeLeaf(Bvh& bvh, const TriangleMesh& mesh, std::span<const uint32_t> tris, uint32_t first) {
    const auto count = static_cast<uint32_t>(tris.size());
    if (count <= kPackWidth) {
      bvh.smallPacks[first] = makeTrianglePack(mesh, tris);
      return kLeafBit | kSmallLeafBit | first;
    }
    const uint32_t n = packs(count);
    for (uint32_t p = 0; p < n; ++p)
      bvh.packs[first + p] = makeTrianglePack16(mesh, tris.subspan(p * kWidth, std::min(kWidth, count - p * kWidth)));
    return kLeafBit | ((n - 1) << kPackCountShift) | first;
  }
};

}  // namespace

TrianglePack16 makeTrianglePack16(const TriangleMesh& mesh, std::span<const uint32_t> tris) {
  return makePack<TrianglePack16, kWide16Width>(mesh, tris);
}

void collapseToWide16(const BinaryBvh& binary, const TriangleMesh& mesh, Wide16Bvh& out,
                      CollapseWorkspace* workspace) {
  if (binary.empty()) {
    out = Wide16Bvh{};
    return;
  }
  // The defaults are the 16-wide layout's (docs/performance.md, "Rays per map and per layout").
  CollapseCosts costs;
  CollapseWorkspace local;
  WideCollapser<Layout16>(binary, mesh, costs, out, workspace != nullptr ? *workspace : local).run();
}

}  // namespace pa::bvh_detail
