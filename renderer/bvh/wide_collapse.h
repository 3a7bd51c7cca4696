#pragma once
// The conversion of the binary BVH into both wide layouts (8-wide wide_bvh, 16-wide
// wide16_bvh): the SAH-optimal plan of which binary nodes become wide nodes and leaves
// (OptimalCollapse), and the collapser that writes a layout along it (WideCollapser).
#include <algorithm>
#include <cstdint>
#include <memory>
#include <span>
#include <stdexcept>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "renderer/bvh/binary_bvh.h"
#include "renderer/bvh/triangle_mesh.h"
#include "renderer/bvh/wide_bvh.h"
#include "renderer/core/reuse.h"

namespace pa::bvh_detail {

/// Cost model of the SAH-optimal collapse, in units of one wide node visit. A leaf of up to
/// smallLeafMax triangles is one small pack; a larger one (up to maxLeaf) is tested in packs of
/// packWidth.
struct CollapseCosts {
  uint32_t width = 16;          ///< Children per wide node.
  uint32_t smallLeafMax = 8;    ///< Triangles of a small (8-wide) leaf pack.
  uint32_t packWidth = 16;      ///< Triangles per pack of a larger leaf.
  uint32_t maxLeaf = 16;        ///< Most triangles in one leaf.
  float node = 1.0f;            ///< Visiting a wide node (its children's box tests).
  float smallLeaf = 1.0f;       ///< Testing a small pack.
  float largePack = 1.0f;       ///< Testing one pack of a larger leaf.
};

/// Chooses the wide tree over a binary BVH that minimises the SAH cost of the given model
/// (dynamic programming over the binary tree as in Ylitie, Karras, Laine, "Efficient Incoherent
/// Ray Traversal on GPUs Through Compressed Wide BVHs", HPG 2017): which binary nodes become a
/// wide node's children, and which become leaves (a leaf may merge several binary leaves).
class OptimalCollapse {
 public:
  OptimalCollapse() = default;
  OptimalCollapse(const BinaryBvh& binary, const CollapseCosts& costs) { plan(binary, costs); }
  /// Plans the collapse of binary (which must outlive the queries below), reusing the arrays of
  /// the previous plan: replanning a tree of the same size allocates nothing.
  void plan(const BinaryBvh& binary, const CollapseCosts& costs);
  /// Whether binary node n, taken as a child slot, is a leaf holding all triangles below it.
  bool isLeaf(uint32_t n) const { return leaf_[n] != 0; }
  /// Writes the binary nodes that become the children of the wide node made from binary node n
  /// (not a leaf slot, or the root); returns how many (1..width), in decreasing box area.
  uint32_t children(uint32_t n, uint32_t* out) const;
  /// Triangles below binary node n, in leaf order, appended to out.
  void trianglesBelow(uint32_t n, std::vector<uint32_t>& out) const;
  /// Triangles below binary node n, in leaf order, written to out from index `count` on
  /// (count advances); throws if out is too short.
  void trianglesBelow(uint32_t n, std::span<uint32_t> out, uint32_t& count) const;
  /// Triangle count below binary node n.
  uint32_t triangleCount(uint32_t n) const { return count_[n]; }
  /// Makes room for planning a tree of `nodes` binary nodes at `width` without allocating; the
  /// plan held so far is dropped (its arrays may be reallocated).
  void reserve(size_t nodes, uint32_t width);
  /// Whether this holds a plan made for `binary` (the same tree object, of the same node count).
  bool plannedFor(const BinaryBvh& binary) const { return binary_ == &binary && plannedNodes_ == binary.nodeCount; }

 private:
  /// An array that only grows (default-initialised, no zero fill): the largest arrays of the plan.
  template <class T>
  struct GrowOnly {
    std::unique_ptr<T[]> data;
    size_t capacity = 0;
    T* ensure(size_t n) {
      if (n > capacity) {
        capacity = std::max(n, 2 * capacity);   // geometric: varying sizes stop reallocating
        data.reset(new T[capacity]);
      }
      return data.get();
    }
    T& operator[](size_t i) const { return data[i]; }
  };

  void collect(uint32_t n, uint32_t slots, uint32_t* out, uint32_t& count) const;

  const BinaryBvh* binary_ = nullptr;
  uint32_t plannedNodes_ = 0;       // binary_->nodeCount when planned; 0: no plan held
  uint32_t width_ = 0;
  GrowOnly<float> subtreeCost_;     // [n * width + j - 1]: best cost of n's subtree in <= j slots
  GrowOnly<uint32_t> leavesBelow_;  // [n]: binary leaves below n
  GrowOnly<uint8_t> leftSlots_;     // [n * width + j - 1]: left child's slots, 0 = n is one slot
  GrowOnly<uint8_t> usedSlots_;     // [n * width + j - 1]: slots that best cost uses (<= j)
  GrowOnly<uint8_t> leaf_;          // [n]: n as one slot is a leaf
  GrowOnly<uint32_t> count_;        // [n]: triangles below n
  GrowOnly<uint8_t> distributedLeftW_;   // [n]: left child's slots in n's own wide node
};

/// A leaf slot of a wide tree being written: the binary node whose triangles it holds, and
/// where its reference goes.
struct CollapseLeafSlot {
  uint32_t binary, node, slot;
};

/// What a collapse needs besides its output; kept by a BVH that is collapsed again and again
/// (dynamic meshes), so that a collapse of a same-sized tree allocates nothing.
struct CollapseWorkspace {
  OptimalCollapse plan;
  /// True: collapse along `plan` as it is, where it was made for this binary tree (plannedFor;
  /// a refit moves only its boxes), instead of planning again. A rebuild must plan again: its
  /// new tree may have the old one's node count.
  bool keepPlan = false;
  std::vector<CollapseLeafSlot> leaves;
  std::vector<uint32_t> firstPack;   ///< Per leaf slot: its first pack in its pool.
};

}  // namespace pa::bvh_detail

namespace pa::bvh_detail {

/// Converts a binary BVH into a wide layout along an OptimalCollapse plan. Layout provides:
/// Node, Bvh (with vector `nodes`), kWidth, kMaxPacks (per leaf); emptyNode(); setChild(node, slot, box, reference);
/// finishNode(node, count) (after the children are set); pool(count) (0 or 1: which pack array
/// a leaf of count triangles goes to) and packs(count) (how many packs it takes there);
/// resizePools(bvh, sizes); writeLeaf(bvh, mesh, triangles, first) -> the leaf reference.
template <class Layout>
class WideCollapser {
 public:
  using Node = typename Layout::Node;
  using Bvh = typename Layout::Bvh;

  WideCollapser(const BinaryBvh& binary, const TriangleMesh& mesh, const CollapseCosts& costs, Bvh& out,
                CollapseWorkspace& workspace)
      : binary_(binary), mesh_(mesh), plan_(workspace.plan), out_(out), leaves_(workspace.leaves),
        first_(workspace.firstPack) {
    if (!workspace.keepPlan || !workspace.plan.plannedFor(binary)) workspace.plan.plan(binary, costs);
  }

  void run() {
    out_.nodes.clear();
    reserveGeometric(out_.nodes, binary_.nodeCount / Layout::kWidth + 1);
    out_.nodes.emplace_back();
    leaves_.clear();
    fillNode(0, 0);
    packLeaves();
  }

 private:
  /// Most triangles in one leaf: kMaxPacks packs of at most 16.
  static constexpr uint32_t kMaxLeafTriangles = Layout::kMaxPacks * 16;

  /// Fills wide node `wide` with the children the plan gives binary node `root` (depth first);
  /// leaf slots are listed in leaves_ and referenced by packLeaves().
  void fillNode(uint32_t wide, uint32_t root) {
    uint32_t children[Layout::kWidth];
    const uint32_t count = plan_.children(root, children);
    Node node = Layout::emptyNode();
    for (uint32_t i = 0; i < count; ++i) {
      uint32_t reference = 0;
      if (plan_.isLeaf(children[i])) {
        leaves_.push_back({children[i], wide, i});
      } else {
        reference = static_cast<uint32_t>(out_.nodes.size());
        out_.nodes.emplace_back();
      }
      Layout::setChild(node, i, binary_.nodes[children[i]].bounds, reference);
    }
    Layout::finishNode(node, count);
    out_.nodes[wide] = node;
    for (uint32_t i = 0; i < count; ++i)
      if (!plan_.isLeaf(children[i])) fillNode(node.child[i], children[i]);
  }

  /// Packs every leaf's triangles (in parallel; packs in depth-first order) and writes the leaf
  /// references.
  void packLeaves() {
    std::vector<uint32_t>& first = first_;
    resizeReusing(first, leaves_.size());
    uint32_t sizes[2] = {0, 0};
    for (size_t i = 0; i < leaves_.size(); ++i) {
      const uint32_t count = plan_.triangleCount(leaves_[i].binary);
      const uint32_t packs = Layout::packs(count);
      if (packs > Layout::kMaxPacks) throw std::invalid_argument("BVH leaf too large for the wide layout");
      first[i] = sizes[Layout::pool(count)];
      sizes[Layout::pool(count)] += packs;
    }
    if (std::max(sizes[0], sizes[1]) > kFirstPackMask) throw std::invalid_argument("too many triangles for the wide layout");
    Layout::resizePools(out_, sizes);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, leaves_.size(), 1024), [&](const tbb::blocked_range<size_t>& r) {
      uint32_t tris[kMaxLeafTriangles];
      for (size_t i = r.begin(); i < r.end(); ++i) {
        uint32_t count = 0;
        plan_.trianglesBelow(leaves_[i].binary, tris, count);
        out_.nodes[leaves_[i].node].child[leaves_[i].slot] =
            Layout::writeLeaf(out_, mesh_, std::span<const uint32_t>(tris, count), first[i]);
      }
    });
  }

  const BinaryBvh& binary_;
  const TriangleMesh& mesh_;
  const OptimalCollapse& plan_;
  Bvh& out_;
  std::vector<CollapseLeafSlot>& leaves_;
  std::vector<uint32_t>& first_;
};

}  // namespace pa::bvh_detail
